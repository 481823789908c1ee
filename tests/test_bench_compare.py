#!/usr/bin/python3
"""make bench-compare's translation of one description into both codes'
inputs (pipeline/bench_compare/compare.py): the damping handed to LAMMPS and
the dem2d scenes. Usage: test_bench_compare.py [DEM2D] (with dem2d, the
settling scene is also validated by `dem2d check`)."""
import math
import subprocess
import sys
import tempfile
import tomllib
import unittest
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "pipeline" / "bench_compare"))
import compare  # noqa: E402

DEM2D = sys.argv.pop(1) if len(sys.argv) > 1 else None


class LammpsDamping(unittest.TestCase):
    def test_tsuji_prefactor_equals_the_linear_laws_two_nu(self):
        for e in (0.5, 0.7, 0.9, 0.95):
            log_e = math.log(e)
            two_nu = -2 * log_e / math.sqrt(math.pi**2 + log_e**2)
            self.assertAlmostEqual(compare.tsuji_alpha(compare.lammps_restitution(e)), two_nu, places=10)

    def test_the_fit_alone_would_damp_a_fifth_less_at_e_0_9(self):
        # why the restitution is translated: LAMMPS's fit at e = 0.9 is 0.053, the exact 2 nu is 0.067
        self.assertAlmostEqual(compare.tsuji_alpha(0.9), 0.0529, places=3)
        self.assertAlmostEqual(compare.lammps_restitution(0.9), 0.8756, places=4)


class Dem2dScenes(unittest.TestCase):
    def setUp(self):
        self.d = compare.read_toml(ROOT / "data" / "bench" / "compare.toml")

    def test_the_timed_scene_runs_the_given_steps_at_the_given_dt(self):
        scene = tomllib.loads(compare.dem2d_scene(self.d, settle=False, steps=1000, dt=3e-6))
        self.assertEqual(scene["time"]["dt"], 3e-6)
        self.assertAlmostEqual(scene["time"]["duration"] / scene["time"]["dt"], 1000)
        self.assertNotIn("rolling_resistance", scene["effects"])
        self.assertEqual(scene["contact"]["kn"], self.d["contact"]["kn"])
        inner = sorted(b["a"][0] + s * b["thickness"] / 2 for b, s in zip(scene["body"][1:], (1, -1)))
        self.assertAlmostEqual(inner[0], 0.0)  # left wall's inner face
        self.assertAlmostEqual(inner[1], self.d["bed"]["cell_width"])  # right wall's

    @unittest.skipIf(DEM2D is None, "no dem2d given")
    def test_dem2d_accepts_the_settling_scene(self):
        # (the timed scene has its grains only with --initial, from the settled run)
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / "settle.toml"
            path.write_text(compare.dem2d_scene(self.d, settle=True))
            done = subprocess.run([DEM2D, "check", str(path)], capture_output=True, text=True)
            self.assertEqual(done.returncode, 0, done.stderr)
            self.assertIn("particles 1600", done.stdout)


if __name__ == "__main__":
    unittest.main()

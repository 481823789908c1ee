#!/usr/bin/python3
"""make bench-compare's translation of one description into both codes'
inputs (pipeline/bench_compare/compare.py): the damping handed to LAMMPS and
the dem2d scenes. Usage: test_bench_compare.py [DEM2D] (with dem2d, the
settling scene is also validated by `dem2d check`)."""
import json
import subprocess
import sys
import tempfile
import tomllib
import unittest
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))  # the repository under test: its pipeline package
from pipeline.bench_compare import compare  # noqa: E402

DEM2D = sys.argv.pop(1) if len(sys.argv) > 1 else None


class LammpsDamping(unittest.TestCase):
    def test_tsuji_prefactor_equals_the_given_two_nu(self):
        for two_nu in (0.068, 0.2, 0.5):
            self.assertAlmostEqual(compare.tsuji_alpha(compare.lammps_restitution(two_nu)), two_nu, places=10)

    def test_the_fit_alone_would_damp_a_fifth_less_at_e_0_9(self):
        # why the restitution is translated: LAMMPS's fit at e = 0.9 is 0.053; dem2d's
        # 2 nu for e = 0.9 (non-attractive law, nu = 0.03427) is 0.0685
        self.assertAlmostEqual(compare.tsuji_alpha(0.9), 0.0529, places=3)
        self.assertAlmostEqual(compare.lammps_restitution(2 * 0.0342652), 0.8726, places=3)

    @unittest.skipIf(DEM2D is None, "no dem2d given")
    def test_two_nu_comes_from_dem2d(self):
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / "settle.toml"
            path.write_text(compare.dem2d_scene(compare.read_toml(ROOT / "data" / "bench" / "compare.toml"), settle=True))
            done = subprocess.run([DEM2D, "check", str(path), "--json"], capture_output=True, text=True)
            self.assertEqual(done.returncode, 0, done.stderr)
            self.assertAlmostEqual(json.loads(done.stdout)["normal_damping_ratio"]["grains"], 0.0342652, places=6)


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

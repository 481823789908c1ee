#!/usr/bin/python3
"""The stages cg, network and friction on scenes without an intruder
(examples/box, examples/silo): they measure what needs none, and what they
measure obeys the physics. Usage:
  test_scenes_without_intruder.py DEM2D ANALYSIS_DIR"""
import json
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

import h5py
import numpy as np

ROOT = Path(__file__).resolve().parent.parent
DEM2D = sys.argv.pop(1)
ANALYSIS = Path(sys.argv.pop(1))
G = 9.81  # m/s^2, the examples' gravity

# The box, left until it is at rest (a kinetic energy 500 times lower than the example's stop).
BOX_AT_REST = """
[time]
duration = 3.0
[stop]
kinetic_energy_per_grain_below = 1e-13
min_time = 1.5
"""
# The silo's zones: v* = |V| / 100 mm/s.
SILO_CG = """
[zones]
reference_speed_mm_s = 100.0
"""


def run(*args):
    r = subprocess.run([str(a) for a in args], capture_output=True, text=True)
    if r.returncode != 0:
        raise AssertionError(f"{args[0]} exited {r.returncode}:\n{r.stderr}")
    return r


def metrics(folder, stage):
    return json.loads((folder / "metrics.json").read_text())[stage]


class Box(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        d = Path(cls.tmp.name)
        (d / "rest.toml").write_text(BOX_AT_REST)
        run(DEM2D, "run", ROOT / "examples/box/scene.toml", "--overlay", d / "rest.toml", "--out", d / "run")
        cls.run_file = d / "run/run.h5"
        for stage in ("cg", "network", "friction"):
            run(ANALYSIS / stage, cls.run_file, "--out", d / stage)
        run(ANALYSIS / "bed_metrics", cls.run_file, "--out", d / "bed")
        cls.cg = metrics(d / "cg", "cg")
        cls.net = metrics(d / "network", "network")
        cls.fr = metrics(d / "friction", "friction")
        cls.bed = json.loads((d / "bed" / "metrics.json").read_text())["fill"]
        cls.dir = d

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_each_stage_says_there_is_no_intruder(self):
        for m in (self.cg, self.net, self.fr):
            self.assertIs(m["intruder"], False)
            self.assertIn("no body with role 'intruder'", m["intruder_note"])
        self.assertEqual(self.cg["frame"], "lab")
        self.assertNotIn("cone_angle_deg", self.cg)
        self.assertIsNone(self.fr["critical_height_mm"])
        self.assertIsNone(self.fr["mean_mu_star_lower"])

    def test_floor_and_walls_carry_the_weight_of_a_bed_at_rest(self):
        # Static equilibrium: the vertical forces of the grains on the floor and
        # the walls add up to the grains' weight (to the residual motion's 1e-3).
        with h5py.File(self.run_file) as f:
            weight = f["particles/mass"][:].sum() * G
        final = self.net["final"]
        carried = final["floor_load_N_per_m"] + final["wall_load_N_per_m"] + final["other_bodies_load_N_per_m"]
        self.assertAlmostEqual(carried / weight, 1.0, delta=1e-3)
        self.assertAlmostEqual(final["wall_load_fraction"],
                               final["wall_load_N_per_m"] / (final["wall_load_N_per_m"] + final["floor_load_N_per_m"]),
                               places=12)

    def test_loads_from_the_contacts_equal_the_engines_body_forces(self):
        # network sums the snapshot's contact forces; the engine records its own
        # body forces in /series: at the last snapshot (also the last series row) they agree.
        with h5py.File(self.run_file) as f, h5py.File(self.dir / "network/network.h5") as n:
            self.assertEqual(f["series/time"][-1], f["snapshots/time"][-1])
            engine = f["series/body_force"][-1]  # [body, xy]: left, right, floor
            ours = np.array([[n["load/left_fx"][-1], n["load/left_fy"][-1]],
                             [n["load/right_fx"][-1], n["load/right_fy"][-1]],
                             [np.nan, n["load/floor_fy"][-1]]])
        np.testing.assert_allclose(ours[:2], engine[:2], rtol=1e-9, atol=1e-9)
        self.assertAlmostEqual(ours[2, 1], engine[2, 1], delta=1e-9 * abs(engine[2, 1]))

    def test_cg_bulk_solid_fraction_is_the_bed_stages(self):
        # Two estimates of the same bulk: the kernel's mean over the bulk nodes
        # and bed_metrics' sampled coverage (their regions differ by a few d).
        self.assertAlmostEqual(self.cg["grid"]["phi_ref"], self.bed["solid_fraction"], delta=0.02)
        self.assertGreater(self.bed["solid_fraction"], 0.78)  # a 2D random packing of disks: ~0.80-0.84

    def test_a_bed_at_rest_does_not_move(self):
        self.assertLess(self.cg["final"]["mean_speed_mm_s"], 0.1)
        self.assertIsNone(self.cg["final"]["mobile_fraction"])  # no reference speed: no zones
        self.assertIn("reference speed", self.cg["zones_note"])

    def test_friction_is_within_the_coulomb_cone(self):
        with h5py.File(self.dir / "friction/friction.h5") as f:
            mu = f["figure/mu_star"][:]
            depth_bulk = f["depth/mean_mu_star_bulk"][:]
        self.assertTrue(np.all(mu >= 0) and np.all(mu <= 1 + 1e-9))
        self.assertTrue(0 < self.fr["mean_mu_star_bulk"] < 1)
        self.assertTrue(np.nanmax(depth_bulk) <= 1 + 1e-9)
        self.assertTrue(0 <= self.fr["slip_fraction"] <= 1)

    def test_the_strong_network_spans_a_packed_box(self):
        self.assertIs(self.net["final"]["spanning"], True)
        self.assertGreater(self.net["final"]["strong_contacts"], 0)


class Silo(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        d = Path(cls.tmp.name)
        (d / "cg.toml").write_text(SILO_CG)
        run(DEM2D, "run", ROOT / "examples/silo/scene.toml", "--out", d / "run")
        cls.run_file = d / "run/run.h5"
        run(ANALYSIS / "cg", cls.run_file, "--out", d / "cg", "--config", d / "cg.toml", "--threads", "2")
        run(ANALYSIS / "cg", cls.run_file, "--out", d / "cg1", "--config", d / "cg.toml", "--threads", "1")
        run(ANALYSIS / "network", cls.run_file, "--out", d / "network")
        run(ANALYSIS / "friction", cls.run_file, "--out", d / "friction")
        cls.dir = d

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_the_discharge_flows_then_stops(self):
        with h5py.File(self.dir / "cg/cg.h5") as f:
            speed = f["snapshots/mean_speed"][:]
            mobile = f["zones/mobile_area"][:]
        self.assertGreater(np.nanmax(speed), 0.1)  # m/s: grains falling out of the outlet
        self.assertLess(speed[-1], 1e-3)           # at rest in the box at the end
        self.assertGreater(mobile.max(), 0.0)
        self.assertEqual(mobile[-1], 0.0)
        m = metrics(self.dir / "cg", "cg")
        self.assertEqual(m["velocity_source"], "piv")
        self.assertEqual(m["reference_speed_mm_s"], 100.0)
        self.assertEqual(m["final"]["mobile_fraction"], 0.0)

    def test_cg_does_not_depend_on_the_thread_count(self):
        with h5py.File(self.dir / "cg/cg.h5") as a, h5py.File(self.dir / "cg1/cg.h5") as b:
            for name in ("snapshots/bed_solid_fraction", "snapshots/mean_speed", "zones/mobile_area", "fields/phi"):
                np.testing.assert_array_equal(a[name][:], b[name][:], err_msg=name)

    def test_network_and_friction_run_over_the_whole_discharge(self):
        net = metrics(self.dir / "network", "network")
        fr = metrics(self.dir / "friction", "friction")
        with h5py.File(self.run_file) as f:
            snapshots = len(f["snapshots/time"])
        with h5py.File(self.dir / "friction/friction.h5") as f:
            with_contacts = int((f["snapshots/contacts"][:] > 0).sum())
        self.assertEqual(net["snapshots"], snapshots)
        self.assertEqual(fr["snapshots"], snapshots)
        self.assertEqual(fr["slip_fraction_snapshots"], with_contacts)  # every snapshot with a contact counts
        self.assertTrue(0 <= net["spanning_fraction"] <= 1)

    def test_pulloff_inputs_are_refused(self):
        r = subprocess.run([str(ANALYSIS / "network"), str(self.run_file), "--out", str(self.dir / "n2"),
                            "--events", str(self.dir / "none.h5")], capture_output=True, text=True)
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("no body with role 'intruder'", r.stderr)


if __name__ == "__main__":
    unittest.main(verbosity=2)

#!/usr/bin/python3
"""The accuracy table's comparisons (pipeline/accuracy/table.py) on profiles
and metrics whose answers are known."""
import sys
import unittest
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))  # the repository under test: its pipeline package
from pipeline.accuracy import table  # noqa: E402


class FakeRun(table.Run):
    def __init__(self, height, drag, overlap=None):
        self.height, self.drag = np.asarray(height, float), np.asarray(drag, float)
        self.overlap = np.zeros_like(self.height) if overlap is None else np.asarray(overlap, float)
        self.travel = float(self.height[-1] - self.height[0])


class ProfileTests(unittest.TestCase):
    h = np.arange(1.0, 21.0, 0.01)  # mm

    def test_identical_profiles_deviate_by_zero(self):
        r = FakeRun(self.h, 100 + 10 * np.sin(self.h))
        self.assertAlmostEqual(table.profile_deviation(r, r, 10.0, 1.5, 0.05), 0.0, places=12)

    def test_a_uniform_factor_is_its_relative_deviation(self):
        ref = FakeRun(self.h, 100 + 10 * np.sin(self.h))
        run = FakeRun(self.h, 1.1 * ref.drag)
        self.assertAlmostEqual(table.profile_deviation(run, ref, 10.0, 1.5, 0.05), 0.1, places=6)

    def test_smoothing_removes_fluctuations_shorter_than_the_window(self):
        # a sawtooth of period 0.3 mm averages out over a 1.5 mm window (5 periods)
        ref = FakeRun(self.h, np.full_like(self.h, 50.0))
        run = FakeRun(self.h, 50.0 + 20.0 * ((self.h / 0.3) % 1.0 - 0.5))
        self.assertLess(table.profile_deviation(run, ref, 10.0, 1.5, 0.05), 0.01)
        self.assertGreater(table.profile_deviation(run, ref, 10.0, 0.01, 0.05), 0.05)

    def test_slice_metrics_use_only_the_slice(self):
        drag = np.where(self.h < 11.5, 10.0, 1000.0)  # the slice: [1, 11] mm
        drag[100] = 50.0  # the peak, at 2 mm
        m = FakeRun(self.h, drag, overlap=np.where(self.h < 11.5, 0.001, 0.5)).slice_metrics(10.0)
        self.assertEqual(m["peak_drag_N_per_m"], 50.0)
        self.assertAlmostEqual(m["peak_height_mm"], 2.0)
        self.assertAlmostEqual(m["max_overlap_over_d"], 0.001)

    def test_slice_checks_compare_with_the_tolerances(self):
        tol = {"max_overlap_over_d": 0.01, "profile_rel_rms": 0.2, "peak_drag_rel": 0.2, "peak_height_mm": 1.5,
               "mean_drag_rel": 0.1}
        ref = {"peak_drag_N_per_m": 100.0, "peak_height_mm": 2.0, "mean_drag_N_per_m": 50.0, "max_overlap_over_d": 0.001}
        m = dict(ref, peak_drag_N_per_m=125.0, max_overlap_over_d=0.005)
        checks = {c["check"]: c for c in table.slice_checks(m, ref, 0.1, tol)}
        self.assertFalse(checks["peak_drag_rel"]["ok"])
        self.assertAlmostEqual(checks["peak_drag_rel"]["normalised"], 1.25)
        self.assertTrue(checks["max_overlap_over_d"]["ok"])
        self.assertTrue(checks["profile_rel_rms"]["ok"])


class TargetTests(unittest.TestCase):
    targets = [{"result": "R5", "metric": "cg.beta", "paper": 60.0, "tolerance": 10.0},
               {"result": "R8", "metric": "f.slip", "below": 0.2},
               {"result": "R8", "metric": "f.lower", "above_metric": "f.upper"}]

    def test_a_tolerance_target_bounds_the_deviation_from_the_reference(self):
        ref = {"cg": {"beta": 77.0}, "f": {"slip": 0.05, "lower": 0.4, "upper": 0.3}}
        near = {"cg": {"beta": 70.0}, "f": {"slip": 0.1, "lower": 0.4, "upper": 0.35}}
        far = {"cg": {"beta": 60.0}, "f": {"slip": 0.3, "lower": 0.3, "upper": 0.35}}
        self.assertEqual([r["ok"] for r in table.compare_targets(self.targets, near, ref)], [True, True, True])
        # beta 17 degrees off (tolerance 10), slip's verdict flips, lower < upper now
        self.assertEqual([r["ok"] for r in table.compare_targets(self.targets, far, ref)], [False, False, False])

    def test_a_missing_metric_is_a_miss(self):
        ref = {"cg": {"beta": 77.0}, "f": {"slip": 0.05, "lower": 0.4, "upper": 0.3}}
        rows = table.compare_targets(self.targets, {"f": {"slip": float("nan")}}, ref)
        self.assertEqual([r["ok"] for r in rows], [False, False, False])


class NoiseTests(unittest.TestCase):
    targets = TargetTests.targets

    def row(self, metrics, ref):
        return {"slice_checks": [], "targets": table.compare_targets(self.targets, metrics, ref)}

    def test_a_miss_within_twice_the_noise_does_not_count(self):
        ref = {"cg": {"beta": 60.0}, "f": {"slip": 0.05, "lower": 0.4, "upper": 0.3}}
        row = self.row({"cg": {"beta": 73.0}, "f": {"slip": 0.05, "lower": 0.4, "upper": 0.3}}, ref)
        table.judge(row, {"cg.beta": 7.0})  # 13 deg off, tolerance 10, but equivalent runs differ by 7
        self.assertIsNone(row["within_tolerance"])  # undetermined: the noise never passes a point
        self.assertEqual(row["misses"], [])
        self.assertEqual(row["unresolved_misses"], ["cg.beta"])
        table.judge(row, {"cg.beta": 3.0})
        self.assertEqual(row["misses"], ["cg.beta"])
        self.assertIs(row["within_tolerance"], False)
        clean = self.row({"cg": {"beta": 65.0}, "f": {"slip": 0.05, "lower": 0.4, "upper": 0.3}}, ref)
        table.judge(clean, {"cg.beta": 7.0})
        self.assertIs(clean["within_tolerance"], True)

    def test_a_flip_next_to_the_bound_does_not_count(self):
        ref = {"cg": {"beta": 60.0}, "f": {"slip": 0.21, "lower": 0.4, "upper": 0.3}}
        row = self.row({"cg": {"beta": 60.0}, "f": {"slip": 0.15, "lower": 0.4, "upper": 0.3}}, ref)
        table.judge(row, {"f.slip": 0.02})  # the reference is 0.01 above the bound 0.2: within 2 x noise
        self.assertIsNone(row["within_tolerance"])
        self.assertEqual(row["unresolved_misses"], ["f.slip"])
        table.judge(row, {"f.slip": 0.001})
        self.assertEqual(row["misses"], ["f.slip"])

    def test_a_none_counts_as_make_check_reads_it(self):
        # H_c with a power metric: no value with power >= 0.8 is an evidenced none, with less undetermined
        hc = [{"result": "R6", "metric": "cg.hc", "paper": 78.0, "tolerance": 10.0, "power": "cg.hc_power"}]
        none, weak, found = {"cg": {"hc": None, "hc_power": 1.0}}, {"cg": {"hc": None, "hc_power": 0.5}}, {"cg": {"hc": 100.0}}

        def judged(metrics, ref, noise=5.0):
            row = {"slice_checks": [], "targets": table.compare_targets(hc, metrics, ref)}
            table.judge(row, {"cg.hc": noise})
            return row

        self.assertIs(judged(none, none)["within_tolerance"], True)  # the reference agrees with itself
        self.assertEqual(judged(none, found)["misses"], ["cg.hc"])  # an evidenced none against a number
        self.assertEqual(judged(found, none)["misses"], ["cg.hc"])
        self.assertIsNone(judged(weak, found)["within_tolerance"])  # a weak none decides nothing
        self.assertIsNone(judged(weak, weak)["within_tolerance"])
        self.assertIsNone(judged(none, found, noise=None)["within_tolerance"])  # noise unknown: undetermined
        # a bound that needs what was not found (the top layer's depth fit): two evidenced nones, one verdict
        fit = [{"result": "R4", "metric": "cg.fit", "above": 0.8, "power": "cg.hc_power"}]
        self.assertEqual([c["ok"] for c in table.compare_targets(fit, none, none)], [True])
        self.assertEqual([c["ok"] for c in table.compare_targets(fit, weak, weak)], [False])
        self.assertEqual([c["ok"] for c in table.compare_targets(fit, none, {"cg": {"fit": 0.9}})], [False])
        # without power or `undecided`, a missing value is a miss of its own, as in make check
        row = {"slice_checks": [], "targets": table.compare_targets(self.targets, {"f": {"slip": 0.05, "lower": 0.4,
                                                                                         "upper": 0.3}},
                                                                    {"cg": {"beta": 60.0}, "f": {"slip": 0.05, "lower": 0.4,
                                                                                                 "upper": 0.3}})}
        table.judge(row, {"cg.beta": 1.0})
        self.assertEqual(row["misses"], ["cg.beta"])
        beta = [dict(self.targets[0], undecided="cg.beta_outcome")]
        row = {"slice_checks": [], "targets": table.compare_targets(beta, {}, {"cg": {"beta": 60.0}})}
        table.judge(row, {"cg.beta": 1.0})
        self.assertIsNone(row["within_tolerance"])  # an undecided detector: undetermined

    def test_the_cheapest_point_within_tolerance_and_the_cheaper_undetermined(self):
        rows = [{"name": n, "extent": e, "full_wall_seconds": w, "within_tolerance": v}
                for n, e, w, v in [("ref", "full", 9000.0, True), ("mid", "full", 3000.0, None),
                                   ("soft", "full", 900.0, False), ("vsoft", "full", 100.0, None),
                                   ("slice", "slice", 50.0, True), ("dear", "full", 20000.0, None)]]
        self.assertEqual(table.cheapest_points(rows), ("ref", ["vsoft", "mid"]))
        rows[1]["within_tolerance"] = True
        self.assertEqual(table.cheapest_points(rows), ("mid", ["vsoft"]))
        self.assertEqual(table.cheapest_points([dict(r, within_tolerance=None) for r in rows]),
                         (None, ["vsoft", "soft", "mid", "ref", "dear"]))  # none within: every whole run, by cost

    def test_a_cg_setting_agrees_undetermined_or_not(self):
        hc = {"result": "R6", "metric": "cg.hc", "paper": 78.0, "tolerance": 10.0, "power": "cg.hc_power"}
        phi = {"result": "R11", "metric": "cg.phi", "below": 0.0}
        none, weak = {"cg": {"hc": None, "hc_power": 1.0}}, {"cg": {"hc": None, "hc_power": 0.3}}
        self.assertIs(table.cg_ok(hc, none, none), True)
        self.assertIsNone(table.cg_ok(hc, weak, weak))  # the reference grid itself undetermined: so is every grid
        self.assertIsNone(table.cg_ok(hc, {"cg": {"hc": 120.0}}, weak))
        self.assertIs(table.cg_ok(hc, {"cg": {"hc": 125}}, {"cg": {"hc": 120.0}}), True)
        self.assertIs(table.cg_ok(hc, {"cg": {"hc": 135.0}}, {"cg": {"hc": 120.0}}), False)
        self.assertIs(table.cg_ok(hc, none, {"cg": {"hc": 120.0}}), False)
        self.assertIs(table.cg_ok(phi, {"cg": {"phi": 0.001}}, {"cg": {"phi": -0.01}}), False)
        self.assertIs(table.cg_ok(phi, {"cg": {"phi": -0.002}}, {"cg": {"phi": -0.01}}), True)

    def test_several_replicas_give_the_larger_noise_and_unknown_stays_unknown(self):
        floor = table.combined_floor([{"cg.beta": 7.0, "f.slip": 0.01, "h": None},
                                      {"cg.beta": 3.0, "f.slip": 0.02, "h": 1.0, "g": 2.0}])
        self.assertEqual(floor, {"cg.beta": 7.0, "f.slip": 0.02, "h": None, "g": 2.0})
        self.assertEqual(table.combined_floor([]), {})


if __name__ == "__main__":
    unittest.main()

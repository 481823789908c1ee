#!/usr/bin/python3
"""make ensemble's aggregate (pipeline/ensemble/aggregate.py) judges every
member or none: a member that does not fit the others (not an object, another
preset, a stage missing, a metric that is not a finite number or null where
others have one, a metric missing, a cut drag.csv) stops it with exit code 2
naming the member and the metric; the machine's times are not metrics, so
the same members give the same files; huge values keep a finite interval.

    /usr/bin/python3 tests/test_aggregate.py
"""
import json
import math
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
# two stages, as the registry's own reader (pipeline/stages.py) requires them
REGISTRY = """[[stage]]
name = "fill"
program = "bed_metrics"
run = "fill"
outputs = ["metrics.json"]

[[stage]]
name = "spectrum"
program = "spectrum"
run = "pulloff"
outputs = ["spectrum.h5", "metrics.json"]
"""


def metrics(k: int) -> dict:
    return {"preset": "fast", "code_version": "x",
            "fill": {"solid_fraction": 0.84 + 0.001 * k, "wall_seconds": 10.0 + k, "note": "text",
                     "ns_per_particle_step": 15.0 + k, "particle_steps_per_second": 6e7 + k},
            "spectrum": {"rupture_spacing_d": 0.2 + 0.01 * k, "top_layer_height_mm": None,
                         "cost": {"seconds": 3.0 * k}, "range": [1, 2]},
            "cost": {"fill": {"wall_seconds": 5.0 * k}}}


class Aggregate(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = Path(self.tmp.name)
        (self.dir / "stages.toml").write_text(REGISTRY)

    def tearDown(self):
        self.tmp.cleanup()

    def members(self, docs, drag=None):
        dirs = []
        for k, doc in enumerate(docs):
            d = self.dir / f"member_{k:03d}"
            (d / "pulloff").mkdir(parents=True, exist_ok=True)
            (d / "metrics.json").write_text(doc if isinstance(doc, str) else json.dumps(doc))
            (d / "pulloff" / "drag.csv").write_text(
                drag if drag is not None and k == 1 else "height_mm,drag_N_per_m\n1.0,10\n2.0,12\n3.5,9\n")
            dirs.append(str(d))
        return dirs

    def aggregate(self, dirs, out="ensemble"):
        return subprocess.run([sys.executable, "-m", "pipeline.ensemble.aggregate", "--registry",
                               str(self.dir / "stages.toml"), str(self.dir / out), "fast", *dirs],
                              capture_output=True, text=True, cwd=ROOT)

    def refused(self, docs, *expected, drag=None):
        r = self.aggregate(self.members(docs, drag))
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertNotIn("Traceback", r.stderr)
        for e in expected:
            self.assertIn(e, r.stderr)
        self.assertFalse((self.dir / "ensemble" / "stats.json").exists())

    def test_good_members_and_the_same_files_twice(self):
        dirs = self.members([metrics(0), metrics(1), metrics(2)])
        self.assertEqual(self.aggregate(dirs).returncode, 0)
        stats = json.loads((self.dir / "ensemble/stats.json").read_text())["metrics"]
        self.assertAlmostEqual(stats["fill.solid_fraction"]["mean"], 0.841, places=12)
        self.assertEqual(stats["spectrum.top_layer_height_mm"]["n"], 0)  # a detector's "none" in every member
        self.assertFalse([p for p in stats if "seconds" in p or ".cost." in p or "per_particle_step" in p
                          or "per_second" in p], "times aggregated as metrics")
        self.assertEqual(self.aggregate(dirs, "again").returncode, 0)
        for name in ("stats.json", "metrics.json", "drag.csv"):
            self.assertEqual((self.dir / "ensemble" / name).read_bytes(), (self.dir / "again" / name).read_bytes())

    def test_a_member_value_that_is_not_a_number_or_null(self):
        for bad in (float("nan"), float("inf"), "0.2", True, [0.2], 10**400):
            m = metrics(1)
            m["spectrum"]["rupture_spacing_d"] = bad
            with self.subTest(bad=repr(bad)[:20]):
                self.refused([metrics(0), m], "member_001/metrics.json: spectrum.rupture_spacing_d",
                             "not a finite number or null")

    def test_members_that_are_not_metrics_of_this_ensemble(self):
        for doc, expected in (("[]", "not a JSON object of metrics but list"), ("3", "but int"),
                              ("null", "but NoneType"), ("{}", "no metrics of the stage(s) fill, spectrum"),
                              ({**metrics(1), "preset": "default"}, "preset 'default', not 'fast'")):
            with self.subTest(doc=doc):
                self.refused([metrics(0), doc], "member_001/metrics.json", expected)
        no_stage = metrics(1)
        del no_stage["spectrum"]
        self.refused([metrics(0), no_stage], "no metrics of the stage(s) spectrum")
        lacking = metrics(1)
        del lacking["fill"]["solid_fraction"]
        self.refused([metrics(0), lacking], "member_001/metrics.json: fill.solid_fraction is missing (member_000 has it)")

    def test_a_cut_drag_file(self):
        for cut in ("height_mm,drag_N_per_m\n1.0,10\n2.0", "height_mm,drag_N_per_m\n", "height_mm,drag_N_per_m\n1,nan\n"):
            with self.subTest(cut=cut):
                self.refused([metrics(0), metrics(1)], "member_001/pulloff/drag.csv: unreadable", drag=cut)

    def test_drag_heights_out_of_any_bed(self):
        self.refused([metrics(0), metrics(1)], "member_001/pulloff/drag.csv: heights from 0 to 1e+12 mm",
                     drag="height_mm,drag_N_per_m\n1.0,10\n1e12,3\n")

    def test_drag_below_the_floor_is_binned_not_dropped(self):
        dirs = self.members([metrics(0), metrics(1)], drag="height_mm,drag_N_per_m\n-2.5,7\n1.0,10\n")
        self.assertEqual(self.aggregate(dirs).returncode, 0)
        rows = (self.dir / "ensemble/drag.csv").read_text().splitlines()
        self.assertTrue(rows[1].startswith("-2.5,"), rows[:3])  # the bin [-3, -2) mm, member_001's 7 N/m
        self.assertIn(",7,", rows[1])

    def test_huge_values_keep_a_finite_interval(self):
        a, b = metrics(0), metrics(1)
        a["fill"]["solid_fraction"], b["fill"]["solid_fraction"] = 1e308, 1.5e308
        self.assertEqual(self.aggregate(self.members([a, b])).returncode, 0)
        s = json.loads((self.dir / "ensemble/stats.json").read_text())["metrics"]["fill.solid_fraction"]
        self.assertTrue(math.isfinite(s["mean"]) and all(math.isfinite(x) for x in s["ci95"]), s)
        self.assertAlmostEqual(s["mean"] / 1.25e308, 1.0, places=12)


if __name__ == "__main__":
    unittest.main(verbosity=1)

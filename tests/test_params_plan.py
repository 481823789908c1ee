#!/usr/bin/python3
"""make params' plan (pipeline/params/plan.py): every point's scenes are valid
and change only their knob, as intended; bad plans are refused naming the key.
Its report's verdicts (pipeline/params/report.py) are three-valued and never
easier to pass as the interval widens.

    /usr/bin/python3 tests/test_params_plan.py BUILD/sim/dem2d
"""
import importlib.util
import json
import math
import subprocess
import sys
import tempfile
import tomllib
import unittest
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DEM2D = sys.argv.pop(1) if len(sys.argv) > 1 else str(ROOT / "build/release/sim/dem2d")


def plan(config, name, out):
    return subprocess.run([sys.executable, "-m", "pipeline.params.plan", str(config), name, str(out)], cwd=ROOT,
                          capture_output=True, text=True)


def bodies(scene):
    return {b["name"]: b for b in scene["body"]}


class ParamsPlan(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.out = {}
        for name in ("reduced", "full"):
            cls.out[name] = Path(cls.tmp.name) / name
            r = plan("data/params.toml", name, cls.out[name])
            assert r.returncode == 0, r.stderr
        cls.points = {n: json.loads((cls.out[n] / "plan.json").read_text())["points"] for n in cls.out}

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def scene(self, plan_name, point, which):
        with open(self.out[plan_name] / "points" / point / f"{which}.toml", "rb") as f:
            return tomllib.load(f)

    def test_every_fill_is_a_valid_scene(self):
        for plan_name, preset in (("reduced", "fast"), ("full", "default")):
            for p in self.points[plan_name]:
                d = self.out[plan_name] / "points" / p["point"]
                r = subprocess.run([DEM2D, "check", str(d / "fill.toml"), "--overlay", f"pipeline/presets/{preset}.toml",
                                    "--overlay", str(d / "overlay.toml")], cwd=ROOT, capture_output=True, text=True)
                self.assertEqual(r.returncode, 0, f"{plan_name}/{p['point']}: {r.stderr}")

    def test_cell_width_moves_the_walls_centres_the_intruder_and_scales_the_grains(self):
        for plan_name in ("reduced", "full"):
            base = self.scene(plan_name, "base", "fill")
            for w in (60, 140):
                fill, pull = self.scene(plan_name, f"cell_width_{w}", "fill"), self.scene(plan_name, f"cell_width_{w}", "pulloff")
                for s in (fill, pull):
                    b = bodies(s)
                    self.assertAlmostEqual(b["right"]["a"][0] - b["left"]["a"][0] - 0.002, w * 1e-3, places=12)
                    self.assertAlmostEqual(0.5 * (b["intruder"]["a"][0] + b["intruder"]["b"][0]), w * 5e-4, places=12)
                    self.assertLess(s["domain"]["xmin"], 0.0)
                    self.assertGreater(s["domain"]["xmax"], w * 1e-3)
                self.assertEqual(fill["generator"][0]["count"], round(base["generator"][0]["count"] * w / 100))

    def test_intruder_length_is_tip_to_tip(self):
        for length in (5, 20):
            b = bodies(self.scene("reduced", f"intruder_length_{length}", "pulloff"))["intruder"]
            self.assertAlmostEqual(b["b"][0] - b["a"][0] + b["thickness"], length * 1e-3, places=12)
        square = bodies(self.scene("reduced", "shape_square", "fill"))["intruder"]
        self.assertEqual((square["shape"], square["size"], square["thickness"]), ("rectangle", [0.01, 0.002], 0.0))

    def test_pull_speed_scales_every_time_in_travel(self):
        base = self.scene("reduced", "base", "pulloff")
        fast = self.scene("reduced", "pull_speed_12", "pulloff")
        v0, v = bodies(base)["intruder"]["velocity"][1], bodies(fast)["intruder"]["velocity"][1]
        self.assertAlmostEqual(v, 0.012)
        for table, key in (("output", "series_interval"), ("output", "snapshot_interval"),
                           ("output", "displacement_window"), ("stop", "free_time"), ("time", "duration")):
            self.assertAlmostEqual(fast[table][key] * v, base[table][key] * v0, places=15, msg=key)
        shared = next(p for p in self.points["reduced"] if p["point"] == "pull_speed_12")
        self.assertTrue(shared["shared_bed"])  # the base's beds: only the pull changes
        waves = [line.split() for line in (self.out["reduced"] / "targets.txt").read_text().splitlines()]
        line = next(w for w in waves if w[1] == shared["members"][0] + "/metrics.json")
        self.assertEqual(line[0], "2")
        # each Slurm task's time limit (minutes): 3 x its estimate, at least 10
        self.assertTrue(all(len(w) == 3 and int(w[2]) >= 10 for w in waves), waves[:3])

    def test_law_knobs_are_overlays_after_the_preset(self):
        coh = tomllib.loads((self.out["reduced"] / "points/cohesion_5/overlay.toml").read_text())
        d, rho = 3e-3, 2500.0
        self.assertTrue(coh["effects"]["cohesion"])
        self.assertAlmostEqual(coh["contact"]["cohesion_force"], 5 * rho * math.pi * d * d / 4 * 9.81, places=12)
        self.assertAlmostEqual(coh["contact"]["cohesion_range"], 0.05 * d, places=15)
        mu = tomllib.loads((self.out["reduced"] / "points/friction_0.3/overlay.toml").read_text())
        self.assertEqual(mu["contact"], {"friction": 0.3, "wall": {"friction": 0.3}})
        self.assertEqual(tomllib.loads((self.out["reduced"] / "points/base/overlay.toml").read_text()), {})
        # a geometry point's scenes differ from the base's only in geometry
        base, wide = self.scene("reduced", "base", "fill"), self.scene("reduced", "cell_width_140", "fill")
        self.assertEqual({k for k in base if base[k] != wide[k]}, {"name", "domain", "generator", "body"})

    def test_bad_plans_are_refused_naming_the_key(self):
        config = Path(self.tmp.name) / "bad.toml"
        good = (ROOT / "data/params.toml").read_text()
        for change, message in (("preset = \"fast\"", "preset = 'nosuch'"), ("members = 1", "members = 0"),
                                ("knob = \"friction\"", "knob = 'frictoin'")):
            text = good.replace(change, change.replace("fast", "nosuch").replace("= 1", "= 0")
                                .replace("friction\"", "frictoin\""), 1)
            config.write_text(text)
            r = plan(config, "reduced", Path(self.tmp.name) / "bad")
            self.assertEqual(r.returncode, 2, text)
            self.assertIn(message, r.stderr)
        r = plan("data/params.toml", "nosuch", Path(self.tmp.name) / "bad")
        self.assertIn("no plan [nosuch]", r.stderr)


def load_report():
    sys.path.insert(0, str(ROOT))  # the repository under test: its pipeline package
    return importlib.import_module("pipeline.params.report")


class ParamsVerdicts(unittest.TestCase):
    within = staticmethod(load_report().within)

    def test_three_values(self):
        self.assertEqual(self.within(45.0, 3.0, 45.0, 10.0), "holds")
        self.assertEqual(self.within(14.8, 5.0, 47.5, 10.0), "fails")
        self.assertEqual(self.within(40.0, 8.0, 47.5, 10.0), "undetermined")
        self.assertEqual(self.within(float("nan"), 1.0, 47.5, 10.0), "?")

    def test_a_value_without_a_spread_decides_nothing(self):
        # one member, and the base point had none to lend a spread (the reduced plan's 5 mm intruder: a top
        # layer 14.8 mm deep against (L_c - L)/2 = 47.5 mm, while no base member had one)
        self.assertEqual(self.within(14.8, float("nan"), 47.5, 10.0), "undetermined")
        self.assertEqual(self.within(47.5, float("nan"), 47.5, 10.0), "undetermined")

    def test_members_without_a_value_keep_a_claim_from_holding(self):
        # the base's H_c: 2 of 3 members found a significant loss; the third found none
        self.assertEqual(self.within(45.0, 3.0, 45.0, 10.0, every_member=False), "undetermined")
        self.assertEqual(self.within(14.8, 3.0, 47.5, 10.0, every_member=False), "fails")

    def test_never_easier_to_pass_as_the_interval_widens(self):
        for mean in [x * 0.5 for x in range(0, 200)]:
            seen = [self.within(mean, 0.25 * k, 47.5, 10.0) for k in range(0, 120)]
            first_other = next((i for i, v in enumerate(seen) if v != "holds"), len(seen))
            self.assertNotIn("holds", seen[first_other:], mean)
            self.assertNotIn("fails", seen[seen.index("undetermined"):] if "undetermined" in seen else [], mean)

    def test_t_quantile_as_make_check(self):
        t975 = load_report().t975
        # Student's t 0.975: tabulated values, and the expansion beyond 30 degrees of freedom
        self.assertAlmostEqual(t975(1), 12.706)
        self.assertAlmostEqual(t975(15), 2.131)
        self.assertAlmostEqual(t975(30), 2.042)
        self.assertAlmostEqual(t975(40), 2.021, places=3)
        self.assertAlmostEqual(t975(120), 1.980, places=3)
        self.assertTrue(all(t975(k) > t975(k + 1) > 1.959964 for k in range(1, 200)))

    def test_a_miss_is_absence_only_with_the_power_to_find_it(self):
        confident = load_report().misses_confident
        nan = float("nan")
        # H_c: a member that found a loss, and misses with power 0.9 / 0.5 / none measured
        found = {"wall_mobility_length_mm": 91.0, "wall_mobility_power": nan}
        strong = {"wall_mobility_length_mm": nan, "wall_mobility_power": 0.9}
        weak = {"wall_mobility_length_mm": nan, "wall_mobility_power": 0.5}
        unmeasured = {"wall_mobility_length_mm": nan, "wall_mobility_power": nan}
        keys = ("wall_mobility_length_mm", "wall_mobility_power")
        self.assertTrue(confident({"values": [found, strong]}, *keys))
        self.assertFalse(confident({"values": [found, weak]}, *keys))
        self.assertFalse(confident({"values": [strong, unmeasured]}, *keys))
        # the top layer's keys by default
        self.assertTrue(confident({"values": [{"top_layer_found": 0.0, "top_layer_power": 0.85}]}))
        self.assertFalse(confident({"values": [{"top_layer_found": 0.0, "top_layer_power": 0.6}]}))


if __name__ == "__main__":
    unittest.main(verbosity=1)

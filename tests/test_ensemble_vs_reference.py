"""pipeline/accuracy/ensemble_vs_reference.py: an ensemble against the whole-run reference's members,
three-valued, and noise never turning a difference into agreement."""
import json
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from pipeline.accuracy import ensemble_vs_reference as evr  # noqa: E402

TOL = {"metric": "cg.beta", "result": "R5", "tolerance": 10.0}
BOUND = {"metric": "f.slip", "result": "R7", "below": 0.2}


def refs(*betas, slip=0.05):
    return [{"cg": {"beta": b}, "f": {"slip": slip}} for b in betas]


def stats(mean, ci, n=4):
    return {"mean": mean, "n": n, "ci95": ci}


class ToleranceTests(unittest.TestCase):
    def test_within_the_tolerance_agrees_whatever_the_noise(self):
        for noise in (0.0, 30.0):
            r = evr.compare(TOL, refs(60.0, 60.0 + noise), {"cg": {"beta": 65.0 + noise / 2}},
                            stats(65.0 + noise / 2, [60.0, 70.0]))
            self.assertEqual(r["verdict"], "agrees")
            self.assertAlmostEqual(r["deviation"], 5.0)

    def test_beyond_the_tolerance_differs_only_clear_of_the_noise_and_the_interval(self):
        ens = {"cg": {"beta": 75.0}}
        self.assertEqual(evr.compare(TOL, refs(60.0, 61.0), ens, stats(75.0, [72.0, 78.0]))["verdict"], "differs")
        # the reference's members 8 apart: 15 is within twice their spread
        self.assertEqual(evr.compare(TOL, refs(56.0, 64.0), ens, stats(75.0, [72.0, 78.0]))["verdict"], "undetermined")
        # the ensemble's interval reaches into the tolerance band
        self.assertEqual(evr.compare(TOL, refs(60.0, 61.0), ens, stats(75.0, [68.0, 82.0]))["verdict"], "undetermined")
        # one reference member only: no noise known, no difference claimed
        self.assertEqual(evr.compare(TOL, refs(60.0), ens, stats(75.0, [72.0, 78.0]))["verdict"], "undetermined")

    def test_a_missing_value_is_undetermined(self):
        r = evr.compare(TOL, refs(60.0, 61.0), {"cg": {}}, None)
        self.assertEqual(r["verdict"], "undetermined")
        self.assertIsNone(r["deviation"])


class BoundTests(unittest.TestCase):
    def test_same_verdicts_agree(self):
        r = evr.compare(BOUND, refs(60.0, 60.0), {"f": {"slip": 0.1}}, stats(0.1, [0.08, 0.12]))
        self.assertEqual(r["verdict"], "agrees")

    def test_a_flip_differs_only_with_the_interval_across_nothing(self):
        ens = {"f": {"slip": 0.3}}
        self.assertEqual(evr.compare(BOUND, refs(60.0, 60.0), ens, stats(0.3, [0.25, 0.35]))["verdict"], "differs")
        self.assertEqual(evr.compare(BOUND, refs(60.0, 60.0), ens, stats(0.3, [0.15, 0.45]))["verdict"], "undetermined")
        split = refs(60.0, 60.0)
        split[1]["f"]["slip"] = 0.25
        self.assertEqual(evr.compare(BOUND, split, ens, stats(0.3, [0.25, 0.35]))["verdict"], "undetermined")


class HelperTests(unittest.TestCase):
    def test_the_reference_members(self):
        points = [{"name": "x"}, {"name": "r", "full_reference": True}, {"name": "r2", "replica_of": "r"},
                  {"name": "y", "replica_of": "x"}]
        self.assertEqual(evr.reference_members(points), ["r", "r2"])
        self.assertEqual(evr.reference_members(points[:1]), [])


class CommandTests(unittest.TestCase):
    """The command on the repository's sweep and targets, with made-up member files."""
    repo = Path(__file__).resolve().parents[1]

    def run_it(self, out: Path, ensemble: Path):
        return subprocess.run([sys.executable, "-m", "pipeline.accuracy.ensemble_vs_reference", "data/accuracy.toml",
                               str(out), str(ensemble)], cwd=self.repo, capture_output=True, text=True)

    def test_writes_the_table_and_names_a_missing_input(self):
        with tempfile.TemporaryDirectory() as tmp:
            out, ensemble = Path(tmp) / "acc", Path(tmp) / "default" / "ensemble"
            r = self.run_it(out, ensemble)
            self.assertEqual(r.returncode, 2, r.stderr)
            self.assertIn("kn_1.92e8/metrics.json: no such file", r.stderr)
            for name, beta in (("kn_1.92e8", 68.0), ("kn_1.92e8_replica", 69.0)):
                (out / "points" / name).mkdir(parents=True)
                (out / "points" / name / "metrics.json").write_text(json.dumps({"cg": {"cone_angle_deg": beta}}))
            r = self.run_it(out, ensemble)
            self.assertEqual(r.returncode, 2, r.stderr)
            self.assertIn("run `make ensemble PRESET=default`", r.stderr)
            ensemble.mkdir(parents=True)
            (ensemble / "metrics.json").write_text(json.dumps({"cg": {"cone_angle_deg": 70.5}}))
            (ensemble / "stats.json").write_text(json.dumps({"metrics": {"cg.cone_angle_deg": {
                "values": [70.0, 71.0], "n": 2, "mean": 70.5, "sd": 0.7, "ci95": [70.0, 71.0]}}}))
            r = self.run_it(out, ensemble)
            self.assertEqual(r.returncode, 0, r.stderr)
            rows = {t["metric"]: t for t in json.loads((out / "ensemble_vs_reference.json").read_text())["targets"]}
            self.assertEqual(rows["cg.cone_angle_deg"]["verdict"], "agrees")
            self.assertAlmostEqual(rows["cg.cone_angle_deg"]["deviation"], 2.0)
            self.assertIn("| cg.cone_angle_deg (R5) | 68, 69 | 70.5 [70, 71] | 2 | ±10 | agrees |",
                          (out / "ensemble_vs_reference.md").read_text())


if __name__ == "__main__":
    unittest.main()

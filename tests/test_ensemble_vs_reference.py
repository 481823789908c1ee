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


def judged(ci=None, verdict=None, n=4):
    """A row of the ensemble's check.json: its verdict and the 95 % t-interval of the members' mean."""
    row = {"members": str(n)}
    if ci is not None:
        row["interval"] = f"{ci[0]}, {ci[1]}"
    if verdict is not None:
        row["verdict"] = verdict
    return row


class ToleranceTests(unittest.TestCase):
    def test_agrees_only_with_the_interval_inside_the_band_the_reference_noise_leaves(self):
        # reference 60 and 61 (mean 60.5, spread 1): the band is 60.5 +- 9.5
        r = evr.compare(TOL, refs(60.0, 61.0), {"cg": {"beta": 65.0}}, judged([62.0, 68.0]))
        self.assertEqual(r["verdict"], "agrees")
        self.assertAlmostEqual(r["deviation"], 4.5)
        # the same mean, the interval reaching past 70.0
        r = evr.compare(TOL, refs(60.0, 61.0), {"cg": {"beta": 65.0}}, judged([59.0, 71.0]))
        self.assertEqual(r["verdict"], "undetermined")
        # the same interval, the reference's members 10 apart: the band is 65 +- 5
        r = evr.compare(TOL, refs(60.0, 70.0), {"cg": {"beta": 65.0}}, judged([59.0, 71.0]))
        self.assertEqual(r["verdict"], "undetermined")

    def test_more_noise_never_makes_agreement_easier(self):
        """For a fixed difference, whatever is not agreement stays so as the ensemble's interval widens or the
        reference's members spread; beyond the tolerance nothing agrees."""
        spreads, halves = (0.0, 1.0, 4.0, 10.0, 25.0), (0.5, 2.0, 5.0, 15.0)
        for dev in (0.0, 4.0, 8.0, 9.9, 12.0, 30.0):
            agrees = {(s, h): evr.compare(TOL, refs(60.0 - s / 2, 60.0 + s / 2), {"cg": {"beta": 60.0 + dev}},
                                          judged([60.0 + dev - h, 60.0 + dev + h]))["verdict"] == "agrees"
                      for s in spreads for h in halves}
            for (s, h), ok in agrees.items():
                if dev > 10.0:
                    self.assertFalse(ok, (dev, s, h))
                noisier = [agrees[(s2, h2)] for s2 in spreads for h2 in halves if s2 >= s and h2 >= h]
                if not ok:
                    self.assertFalse(any(noisier), (dev, s, h))
            self.assertEqual(agrees[(0.0, 0.5)], dev < 9.5, dev)

    def test_beyond_the_tolerance_differs_only_clear_of_the_noise_and_the_interval(self):
        ens = {"cg": {"beta": 75.0}}
        self.assertEqual(evr.compare(TOL, refs(60.0, 61.0), ens, judged([72.0, 78.0]))["verdict"], "differs")
        # the reference's members 8 apart: 15 is within twice their spread
        self.assertEqual(evr.compare(TOL, refs(56.0, 64.0), ens, judged([72.0, 78.0]))["verdict"], "undetermined")
        # the ensemble's interval reaches into the tolerance band
        self.assertEqual(evr.compare(TOL, refs(60.0, 61.0), ens, judged([68.0, 82.0]))["verdict"], "undetermined")
        # one reference member only: no noise known, nothing claimed either way
        self.assertEqual(evr.compare(TOL, refs(60.0), ens, judged([72.0, 78.0]))["verdict"], "undetermined")
        self.assertEqual(evr.compare(TOL, refs(60.0), {"cg": {"beta": 61.0}}, judged([60.5, 61.5]))["verdict"],
                         "undetermined")

    def test_a_missing_value_or_interval_is_undetermined(self):
        r = evr.compare(TOL, refs(60.0, 61.0), {"cg": {}}, None)
        self.assertEqual(r["verdict"], "undetermined")
        self.assertIsNone(r["deviation"])
        r = evr.compare(TOL, refs(60.0, 61.0), {"cg": {"beta": 60.5}}, judged(n=1))
        self.assertEqual(r["verdict"], "undetermined")


class BoundTests(unittest.TestCase):
    """A bound's verdicts: the ensemble's own (three-valued, from its check.json) against each member's."""

    def test_the_same_decided_verdict_agrees(self):
        r = evr.compare(BOUND, refs(60.0, 60.0), {"f": {"slip": 0.1}}, judged([0.08, 0.12], "holds"))
        self.assertEqual(r["verdict"], "agrees")

    def test_an_undecided_ensemble_agrees_with_nothing(self):
        # the mean holds, but the ensemble's interval straddles the bound: its verdict is undetermined
        r = evr.compare(BOUND, refs(60.0, 60.0), {"f": {"slip": 0.1}}, judged([0.0, 0.25], "undetermined"))
        self.assertEqual(r["verdict"], "undetermined")
        r = evr.compare(BOUND, refs(60.0, 60.0), {"f": {"slip": 0.1}}, judged([0.08, 0.12]))
        self.assertEqual(r["verdict"], "undetermined")

    def test_a_shape_shows_the_interval_of_its_differences(self):
        shape = {"metric": "f.lower", "result": "R8", "above_metric": "f.upper"}
        members = [{"f": {"lower": 0.4, "upper": 0.3}}, {"f": {"lower": 0.42, "upper": 0.31}}]
        r = evr.compare(shape, members, {"f": {"lower": 0.41, "upper": 0.3}}, judged([0.07, 0.13], "holds"))
        self.assertEqual(r["verdict"], "agrees")
        self.assertEqual(r["ensemble_ci95_minus"], "f.upper")
        self.assertIn("| 0.41 [minus `f.upper`: 0.07, 0.13] | holds vs holds, holds |",
                      evr.markdown([r], ["a", "b"], Path("e")))

    def test_a_flip_differs_only_when_the_members_agree(self):
        ens = {"f": {"slip": 0.3}}
        self.assertEqual(evr.compare(BOUND, refs(60.0, 60.0), ens, judged([0.25, 0.35], "fails"))["verdict"],
                         "differs")
        split = refs(60.0, 60.0)
        split[1]["f"]["slip"] = 0.25
        self.assertEqual(evr.compare(BOUND, split, ens, judged([0.25, 0.35], "fails"))["verdict"],
                         "undetermined")


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
            r = self.run_it(out, ensemble)
            self.assertEqual(r.returncode, 2, r.stderr)
            self.assertIn("check.json: no such file", r.stderr)
            (ensemble / "check.json").write_text(json.dumps({"testsuites": [{"testsuite": [
                {"metric": "cg.cone_angle_deg", "verdict": "fails", "interval": "70, 71", "members": "4"},
                {"metric": "friction.slip_fraction", "verdict": "holds", "interval": "0.05, 0.06", "members": "4"}]}]}))
            r = self.run_it(out, ensemble)
            self.assertEqual(r.returncode, 0, r.stderr)
            rows = {t["metric"]: t for t in json.loads((out / "ensemble_vs_reference.json").read_text())["targets"]}
            self.assertEqual(rows["cg.cone_angle_deg"]["verdict"], "agrees")
            self.assertAlmostEqual(rows["cg.cone_angle_deg"]["deviation"], 2.0)
            self.assertIn("| cg.cone_angle_deg (R5) | 68, 69 | 70.5 [70, 71] | 2 | ±10 | agrees |",
                          (out / "ensemble_vs_reference.md").read_text())


if __name__ == "__main__":
    unittest.main()

#!/usr/bin/python3
"""The report's reasons quote the run's own numbers (pipeline/report/report.py,
fill_in): placeholders in deviations.toml are filled in from metrics.json,
and one that names no value stops the report with an error naming it. Its
writers leave nothing half-written on a full disk and say so (exit 2, no
traceback); an unreadable input is to be deleted and made again."""
import contextlib
import io
import re
import subprocess
import sys
import tempfile
import tomllib
import unittest
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))  # the repository under test: its pipeline package
from pipeline import files  # noqa: E402
from pipeline.report import report  # noqa: E402

METRICS = {"fill": {"solid_fraction": 0.8414430434, "bed_height_mm": 141.1},
           "spectrum": {"envelope_fit_upper": {"slope": -0.2436, "r2": 0.3625}},
           "cg": {"cone_angle_sd_deg": None}}


FULL_DISK = """
import resource, signal, sys
sys.path.insert(0, sys.argv[1])
signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # writes past the limit fail with EFBIG, as on a full disk
resource.setrlimit(resource.RLIMIT_FSIZE, (4096, 4096))
from pipeline import files
from pipeline.report import common
if sys.argv[2] == "text":
    files.write_atomic(__import__("pathlib").Path(sys.argv[3]) / "report.html", "x" * 100000)
else:
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots()
    ax.imshow(__import__("numpy").random.default_rng(1).random((400, 400)))
    common.save(fig, sys.argv[3], "fig.png")
"""


class Headline(unittest.TestCase):
    def test_the_small_test_scene_is_not_judged_against_the_paper(self):
        quick = report.headline("quick", 21, 13)
        self.assertIn("Not comparable with the paper", quick)
        self.assertNotIn("targets pass", quick)
        self.assertEqual(report.headline("default", 21, 9), "**12 of 21 paper targets pass** (9 fail).")


class Detectors(unittest.TestCase):
    def test_the_percolation_loss_says_what_its_test_found(self):
        net = {"percolation_loss_outcome": "none: the strong network still percolates in the highest height bin; "
               "power 1 to find one at the paper's depth", "percolation_loss_p_value": 0.6,
               "percolation_loss_height_mm": None, "percolation_loss_rule_height_mm": None}
        text = "\n".join(report.detectors_section({"network": net}))
        self.assertIn("**Percolation loss (R4).** none: the strong network still percolates", text)
        self.assertIn("(p = 0.6): — mm; the height rule alone: — mm.", text)
        self.assertNotIn("Percolation loss", "\n".join(report.detectors_section({"network": {}})))


class Writes(unittest.TestCase):
    def test_a_full_disk_leaves_nothing_half_written_and_says_so(self):
        for kind, name in (("text", "report.html"), ("figure", "fig.png")):
            with self.subTest(kind=kind), tempfile.TemporaryDirectory() as out:
                r = subprocess.run([sys.executable, "-c", FULL_DISK, str(ROOT), kind, out],
                                   capture_output=True, text=True)
                self.assertEqual(r.returncode, 2, r.stderr)
                self.assertNotIn("Traceback", r.stderr)
                self.assertIn(f"{name}: cannot write it", r.stderr)
                self.assertEqual(list(Path(out).iterdir()), [], "a file was left behind")

    def test_an_unreadable_input_is_to_be_deleted_and_made_again(self):
        with tempfile.TemporaryDirectory() as d:
            cut = Path(d) / "metrics.json"
            cut.write_text('{"fill": {"solid_fra')
            err = io.StringIO()
            with contextlib.redirect_stderr(err), self.assertRaises(SystemExit):
                files.read_json(cut, "make ensemble PRESET=fast")
            self.assertIn(f"{cut}: unreadable", err.getvalue())
            self.assertIn("delete it and run `make ensemble PRESET=fast`", err.getvalue())

    def test_the_make_target_is_written_last(self):
        source = (ROOT / "pipeline" / "report" / "report.py").read_text()
        self.assertLess(source.index('write_atomic(results / "report.html"'),
                        source.index('write_atomic(results / "report.md"'))


class FillIn(unittest.TestCase):
    def test_values_are_formatted_as_asked(self):
        text = "Φ {fill.solid_fraction:.3f}, R² {spectrum.envelope_fit_upper.r2:.2f}, {fill.bed_height_mm} mm"
        self.assertEqual(report.fill_in(text, METRICS, "here"), "Φ 0.841, R² 0.36, 141.1 mm")

    def test_an_unmeasured_value_reads_as_a_dash(self):
        self.assertEqual(report.fill_in("± {cg.cone_angle_sd_deg:.0f}°", METRICS, "here"), "± —°")

    def test_text_without_placeholders_is_unchanged(self):
        text = "μ* ≈ 0.24 {not a placeholder} and d/2"
        self.assertEqual(report.fill_in(text, METRICS, "here"), text)

    def test_a_placeholder_naming_no_value_is_an_error_naming_it(self):
        for text in ("{fill.solid_fractoin:.3f}", "{spectrum.envelope_fit_upper.r2.x}", "{network.keystones}"):
            err = io.StringIO()
            with self.assertRaises(SystemExit) as exit_, contextlib.redirect_stderr(err):
                report.fill_in(text, METRICS, "deviations.toml, miss 'x'")
            self.assertEqual(exit_.exception.code, 2)
            self.assertIn(text, err.getvalue())
            self.assertIn("deviations.toml, miss 'x'", err.getvalue())

    def test_deviations_toml_quotes_run_numbers_only_through_placeholders(self):
        with open(ROOT / "pipeline" / "report" / "deviations.toml", "rb") as f:
            d = tomllib.load(f)
        stages = {s.name for s in files.stages()} | {"cost"}  # metrics.json's top-level groups
        found = [m.group(1) for entry in d["deviation"] + d["miss"]
                 for m in report.PLACEHOLDER.finditer(entry["reason"])]
        self.assertGreater(len(found), 10)
        for name in found:
            self.assertIn(name.split(".")[0], stages, name)
        # every decimal written out in a miss reason is the paper's value or
        # the accuracy sweep's, never one run's
        allowed = {"0.82", "0.24", "0.25", "0.32", "0.34", "1.92", "87.5"}
        for entry in d["miss"]:
            for number in re.findall(r"\d+\.\d+", report.PLACEHOLDER.sub("", entry["reason"])):
                self.assertIn(number, allowed, entry["metric"])


class Misses(unittest.TestCase):
    def test_a_miss_without_an_entry_says_plainly_that_no_reason_is_known(self):
        lines = report.deviations("quick", [{"name": "x", "metric": "cg.no_such_metric", "ours": 1.0}], METRICS)
        line = next(x for x in lines if "cg.no_such_metric" in x)
        self.assertIn(report.NO_REASON, line)
        self.assertNotIn("not analysed yet", line)

    def test_every_target_has_a_reason_should_it_miss(self):
        with open(ROOT / "data" / "paper_targets.toml", "rb") as f:
            targets = {t["metric"] for t in tomllib.load(f)["target"]}
        with open(ROOT / "pipeline" / "report" / "deviations.toml", "rb") as f:
            reasons = {m["metric"] for m in tomllib.load(f)["miss"]}
        self.assertLessEqual(reasons, targets)  # no reason for a metric that is not a target


if __name__ == "__main__":
    unittest.main()

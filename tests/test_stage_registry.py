#!/usr/bin/python3
"""The stage registry (pipeline/stages.py) cannot rewrite the Makefile: the
Make it generates defines only STAGE* variables, quotes every argument (no
make or shell expansion, even under make -n), refuses names the Makefile
uses and settings outside the repository, is kept per registry path, and a
malformed registry is an error naming it, never a traceback; the report
scripts read the registry make was given (STAGE_REGISTRY).

    /usr/bin/python3 tests/test_stage_registry.py
"""
import os
import re
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))  # the repository under test: its pipeline package
from pipeline import stages  # noqa: E402

BASE = (ROOT / "pipeline/stages.toml").read_text()


def extra(name="extra", program="friction", args=None, config='"data/friction.toml"'):
    text = f'\n[[stage]]\nname = "{name}"\nprogram = "{program}"\nrun = "pulloff"\nconfig = {config}\n'
    if args is not None:
        text += "args = [" + ", ".join('"' + a.replace("\\", "\\\\").replace('"', '\\"') + '"' for a in args) + "]\n"
    return BASE + text + 'outputs = ["friction.h5", "metrics.json"]\n'


class Registry(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = Path(self.tmp.name)

    def tearDown(self):
        self.tmp.cleanup()

    def registry(self, text, name="stages.toml"):
        path = self.dir / name
        path.write_text(text)
        return path

    def generate(self, text):
        r = subprocess.run([sys.executable, "-m", "pipeline.stages", "make", str(self.registry(text))],
                           capture_output=True, text=True, cwd=ROOT)
        return r

    def refused(self, text, *expected):
        r = self.generate(text)
        self.assertEqual(r.returncode, 2, r.stdout[-300:])
        self.assertNotIn("Traceback", r.stderr)
        for e in expected:
            self.assertIn(e, r.stderr)

    def test_only_stage_variables_whatever_the_program_is_called(self):
        for program in ("python", "path", "shell", "check", "threads", "members", "results", "build"):
            with self.subTest(program=program):
                r = self.generate(extra(program=program))
                self.assertEqual(r.returncode, 0, r.stderr)
                assigned = re.findall(r"^([A-Za-z_][\w]*)\s*[:?+]?=", r.stdout, re.M)
                self.assertTrue(assigned)
                self.assertEqual([v for v in assigned if not v.startswith("STAGE")], [])

    def test_names_the_makefile_uses_are_refused(self):
        for name in ("build", "install", "test", "check", "ensemble", "cyclic", "needs", "clean", "reproduce",
                     "figures", "metrics", "params",
                     # folders of the Makefile's own rules: the pull-off slice, on its own or another bed
                     "pulloff_5mm", "pulloff_5mm_on_default_bed", "report"):
            with self.subTest(name=name):
                self.refused(extra(name=name), f"name = '{name}': a name the Makefile uses already")

    def test_settings_outside_the_repository_are_refused(self):
        for config in ('"/etc/hostname"', '"../stages.toml"', '"data/../../x.toml"', '"data/no_such.toml"', "3"):
            with self.subTest(config=config):
                self.refused(extra(config=config), "config = ", "must be a settings file in the repository")

    def test_malformed_registries_are_named(self):
        for text in ("stage = 3\n", "stage = [1, 2]\n", "[stage]\nname = \"x\"\n", "stages = []\n",
                     BASE + '\n[[stage]]\nname = 5\n', BASE.replace('outputs = ["metrics.json"]', 'outputs = "x"', 1),
                     BASE + '\n[[stage]]\nname = "x"\nprogram = "friction"\nrun = "pulloff"\noutputs = ["../a", "metrics.json"]\n',
                     BASE.replace('inputs = { "--bed" = "fill/run.h5" }', 'inputs = { "--bed; x" = "fill/run.h5" }'),
                     "not toml ["):
            with self.subTest(text=text[-60:]):
                self.refused(text, str(self.dir / "stages.toml"))

    def test_what_a_stage_reads_is_one_of_the_known_parts_of_a_run_file(self):
        self.assertEqual(self.generate(extra().replace('run = "pulloff"\nconfig', 'run = "pulloff"\n'
                                                         'reads = ["snapshots", "contacts"]\nconfig')).returncode, 0)
        for reads in ('["snapshot"]', '"series"', '["series", "series"]', '[1]'):
            with self.subTest(reads=reads):
                text = extra().replace('run = "pulloff"\nconfig', f'run = "pulloff"\nreads = {reads}\nconfig')
                self.refused(text, "reads = ", 'must be an array of distinct values among "series"')
        by_name = {s.name: s.reads for s in stages.load()}
        self.assertEqual(by_name["network"], ("snapshots", "contacts"))
        self.assertEqual(by_name["pulloff"], ("series",))

    def test_huge_keys_names_and_paths_give_a_short_message(self):
        long = "x" * 100000
        for text in (extra(name="a" * 65), extra(program="p" * 65), extra(config=f'"data/{long}.toml"'),
                     BASE + f'\n[[stage]]\n{long} = 1\n', BASE.replace('"--bed"', f'"--{long}"', 1)):
            with self.subTest(text=text[-40:]):
                r = self.generate(text)
                self.assertEqual(r.returncode, 2, r.stderr[-300:])
                self.assertNotIn("Traceback", r.stderr)
                self.assertIn(str(self.dir / "stages.toml"), r.stderr)
                self.assertLess(len(r.stderr), 600, r.stderr[:300])

    def test_arguments_are_one_word_each_and_never_expanded(self):
        marker = self.dir / "ran"
        args = ["a b", f"; touch {marker}", f"$(shell touch {marker})", "# rest", "`touch x`", "it's", "--out={dir}/x",
                "a,b", ")", "(c"]
        registry = self.registry(extra(args=args))
        env = {**os.environ, "NO_DEPS": "1"}
        r = subprocess.run(["make", "-n", "--no-print-directory", "extra", "PRESET=quick",
                            f"STAGE_REGISTRY={registry}", f"RESULTS={self.dir}/results"],
                           cwd=ROOT, capture_output=True, text=True, env=env)
        try:
            self.assertFalse(marker.exists(), "an argument ran a command")
            line = next((l for l in r.stdout.splitlines() if "analysis/friction" in l and "--out" in l), None)
            self.assertIsNotNone(line, r.stdout[-2000:] + r.stderr[-2000:])
            for word in ("'a b'", f"'; touch {marker}'", f"'$(shell touch {marker})'", "'# rest'", "'`touch x`'",
                         "'it'\\''s'", f"'--out=''{self.dir}/results/extra''/x'", "'a,b'", "')'", "'(c'"):
                self.assertIn(word, line)
        finally:
            self.forget(registry)

    def forget(self, registry):
        """The generated file of a registry this test made (make generates it even under -n)."""
        generated = ROOT / "build/release/registries" / (str(registry.resolve()).lstrip("/") + ".mk")
        generated.unlink(missing_ok=True)
        try:  # and the folders made for it, up to the first that holds something else
            os.removedirs(generated.parent)
        except OSError:
            pass

    def test_each_registry_path_has_its_own_generated_rules(self):
        copy = self.registry(extra(name="extra"))
        env = {**os.environ, "NO_DEPS": "1"}
        own = ROOT / "build/release/registries" / (str((ROOT / "pipeline/stages.toml").resolve()).lstrip("/") + ".mk")
        before = own.read_bytes() if own.exists() else None
        try:
            subprocess.run(["make", "-n", "--no-print-directory", "build", f"STAGE_REGISTRY={copy}"], cwd=ROOT,
                           capture_output=True, env=env)
            self.assertTrue((ROOT / "build/release/registries" / (str(copy.resolve()).lstrip("/") + ".mk")).exists())
            if before is not None:
                self.assertEqual(own.read_bytes(), before, "a registry elsewhere named stages.toml replaced the rules")
        finally:
            self.forget(copy)

    def test_the_report_scripts_read_the_registry_make_was_given(self):
        copy = self.registry(extra(name="extra"))
        r = subprocess.run([sys.executable, "-c", "from pipeline import files; "
                            "print(' '.join(s.name for s in files.stages()))"], cwd=ROOT, capture_output=True,
                           text=True, env={**os.environ, "DEM2D_STAGE_REGISTRY": str(copy)})
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertTrue(r.stdout.split()[-1] == "extra", r.stdout)


if __name__ == "__main__":
    unittest.main(verbosity=1)

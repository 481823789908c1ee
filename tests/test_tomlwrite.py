#!/usr/bin/python3
"""The one TOML writer (pipeline/tomlwrite.py): what it writes reads back as
the same document (tomllib), for seeded random documents with awkward keys,
strings, numbers and nesting; its layout of the overlays the pipeline
writes is fixed (a changed byte would make Make redo every run that reads
one); the fuzzer's raw values are written as given; what TOML cannot hold
is refused."""
import math
import random
import sys
import tomllib
import unittest
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))  # the repository under test: its pipeline package
from pipeline import tomlwrite  # noqa: E402

KEYS = ["kn", "a b", "k.e", "ü", "", "x-y_1", '"q"', "tab\tkey", "1"]
STRINGS = ["", "plain", "line\nbreak", 'quo"te', "back\\slash", "tab\t", "\x00\x1f\x7f", "ünï", "#not a comment"]


def random_value(rng: random.Random, depth: int):
    kind = rng.randrange(7 if depth < 3 else 5)
    if kind == 0:
        return rng.choice([True, False])
    if kind == 1:
        return rng.choice([0, -1, 2**63 - 1, -2**63, 7])
    if kind == 2:
        return rng.choice([0.0, -0.0, 1e-310, 1.7976931348623157e308, 0.1, 1e16, -2.5, math.inf, -math.inf])
    if kind == 3:
        return rng.choice(STRINGS)
    if kind == 4:
        return [rng.choice([1.5, 2, "s", True]) for _ in range(rng.randrange(4))]
    if kind == 5:
        return random_table(rng, depth + 1)
    return [random_table(rng, depth + 1) for _ in range(1 + rng.randrange(3))]


def random_table(rng: random.Random, depth: int) -> dict:
    return {rng.choice(KEYS) + str(i): random_value(rng, depth) for i in range(rng.randrange(1, 5))}


class RoundTrip(unittest.TestCase):
    def test_random_documents_read_back_the_same(self):
        rng = random.Random(20261204)
        for trial in range(500):
            doc = random_table(rng, 0)
            text = tomlwrite.dumps(doc, header="a header\nof two lines")
            with self.subTest(trial=trial):
                self.assertEqual(tomllib.loads(text), doc, text)

    def test_nan_and_numpy_numbers(self):
        back = tomllib.loads(tomlwrite.dumps({"a": math.nan, "b": np.float64(0.25), "c": np.int64(-3), "d": (1, 2)}))
        self.assertTrue(math.isnan(back["a"]))
        self.assertEqual((back["b"], back["c"], back["d"]), (0.25, -3, [1, 2]))
        self.assertIs(type(back["c"]), int)  # an integer stays one (dem2d refuses 3.0 for a count)

    def test_raw_values_are_written_as_given(self):
        self.assertEqual(tomlwrite.dumps({"t": {"count": tomlwrite.Raw("4294967297.0")}}), "[t]\ncount = 4294967297.0\n")

    def test_what_toml_cannot_hold_is_refused(self):
        for bad in (None, object(), {1, 2}, b"bytes"):
            with self.subTest(bad=bad), self.assertRaises(ValueError):
                tomlwrite.dumps({"a": bad})


class Layout(unittest.TestCase):
    def test_an_overlay_as_the_pipeline_writes_it(self):
        doc = {"contact": {"kn": 19200000.0, "kt": 9600000.0, "wall": {"kn": 19200000.0}},
               "time": {"dt_over_critical": 0.05},
               "body": [{"name": "intruder", "velocity": [0.0, 0.0012]}]}
        self.assertEqual(tomlwrite.dumps(doc, "accuracy point kn_1.92e7"),
                         "# accuracy point kn_1.92e7\n\n"
                         "[contact]\nkn = 19200000.0\nkt = 9600000.0\n\n[contact.wall]\nkn = 19200000.0\n\n"
                         "[time]\ndt_over_critical = 0.05\n\n"
                         "[[body]]\nname = \"intruder\"\nvelocity = [0.0, 0.0012]\n")


if __name__ == "__main__":
    unittest.main()

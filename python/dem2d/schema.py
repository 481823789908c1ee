"""The run file's schema, as the engine that writes run files prints it (`dem2d inspect --schema`).

run_file_schema.json beside this module is that output: the build writes it into share/dem2d and
installs it here; a source tree holds a copy that its tests keep equal to the program's. Every
dataset's type and shape, the series, the sizes of the /parameters values that are not one number,
the motion kinds' values and the limits come from it, not from lists in this package.
"""
from __future__ import annotations

import json
import re
from functools import lru_cache
from pathlib import Path

SCHEMA_FILE = Path(__file__).with_name("run_file_schema.json")


@lru_cache(maxsize=None)
def schema() -> dict:
    """The whole schema (format, dimensions, attributes, datasets, effects, max_vertices, parameters)."""
    with open(SCHEMA_FILE, encoding="utf-8") as f:
        return json.load(f)


@lru_cache(maxsize=None)
def _datasets() -> dict:
    return {d["path"]: d for d in schema()["datasets"]}


def dataset(path: str) -> dict:
    """The schema's row of a dataset (path, type, shape, units, description, when); KeyError if it has none."""
    return _datasets()[path]


def known(path: str) -> bool:
    """Whether the schema has a row for this dataset."""
    return path in _datasets()


def dtype(path: str) -> str:
    """A dataset's element type as numpy spells it: f8, i8, i4, u1, or str."""
    return dataset(path)["type"]


def shape(path: str, sizes: dict) -> tuple:
    """A dataset's shape with a file's sizes (symbol -> size: {"S": 12, "N": 1600, ...}); KeyError naming a
    symbol not among them."""
    return shape_of(dataset(path)["shape"], sizes)


def shape_of(text: str, sizes: dict) -> tuple:
    """A schema shape ("S,N,2", "S+1", "B,K+1") with the sizes."""
    out = []
    for part in text.split(","):
        m = re.fullmatch(r"([A-Z])(?:\+(\d+))?|(\d+)", part)
        if m is None:
            raise ValueError(f"{SCHEMA_FILE}: {text!r} is not a schema shape")
        out.append(int(m.group(3)) if m.group(3) else sizes[m.group(1)] + int(m.group(2) or 0))
    return tuple(out)


def group(prefix: str, always: bool = True) -> list:
    """The datasets under `prefix` ("series/"), by their names there; with `always`, only those every run
    file holds (no scene setting they depend on)."""
    return [d["path"][len(prefix):] for d in schema()["datasets"]
            if d["path"].startswith(prefix) and not d["path"].endswith("/") and (not always or not d["when"])]


def parameters() -> dict:
    """/parameters' layout: format, shapes (key -> "2", "4", "n,2"), motion_kinds (kind -> the values it
    needs), max_motion_pieces."""
    return schema()["parameters"]

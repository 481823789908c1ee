"""The run file's rules, as the analyses' C++ reader applies them (sim/runfile/run_reader.cpp).

A Run checks the file's structure when it is opened (format, counts, every
dataset's shape and element type, the constants' values, times strictly
increasing) and a snapshot's or series dataset's values when they are read.
`dem2d inspect RUN.h5` and check_run(path) read a whole file with these rules
and must agree on every file (make fuzz, class `reader`). Every refusal is a
RunFileError whose message starts with the file's path and names the dataset.
"""
from __future__ import annotations

import h5py
import numpy as np

from . import schema

FORMATS = (schema.schema()["format"],)


class RunFileError(ValueError):
    """A damaged run file, or not a run file: the message names the file and the dataset."""


def dtype_code(ds) -> str:
    """The element type as numpy spells it ("f8", "i4", "u1"; "str" for strings)."""
    if h5py.check_string_dtype(ds.dtype) is not None:
        return "str"
    return ds.dtype.kind + str(ds.dtype.itemsize)


def _dtype_ok(got, want):
    # floats may be stored as f4; integers only as the exact type written
    return got == want or (want == "f8" and got == "f4")


class Checker:
    """The checks of one open run file; fail() raises a RunFileError naming it."""

    def __init__(self, path, f: h5py.File):
        self.path, self.f = str(path), f

    def fail(self, what):
        raise RunFileError(f"{self.path}: {what}")

    def need(self, name):
        if name not in self.f or not isinstance(self.f[name], h5py.Dataset):
            self.fail(f"dataset /{name} is missing (truncated or not a run file?)")
        return self.f[name]

    def length(self, name):
        """The length of a 1-D dataset that sets a count."""
        ds = self.need(name)
        if ds.ndim != 1:
            self.fail(f"dataset /{name} has shape {list(ds.shape)}, expected one dimension")
        return ds.shape[0]

    def dataset(self, name, shape, dtype):
        ds = self.need(name)
        if tuple(ds.shape) != tuple(shape):
            self.fail(f"dataset /{name} has shape {list(ds.shape)}, expected {list(shape)}")
        if not _dtype_ok(dtype_code(ds), dtype):
            self.fail(f"dataset /{name} holds {dtype_code(ds)}, expected {dtype}")
        return ds

    def finite(self, name, values, row_word="row", row0=0):
        v = np.asarray(values, dtype=float)
        bad = ~np.isfinite(v)
        if bad.any():
            rows = v.reshape(len(v), -1) if v.ndim else v.reshape(1, 1)
            k = int(np.argmax(~np.isfinite(rows).all(axis=1)))  # the first row holding one
            what = "NaN" if np.isnan(rows[k]).any() else "an infinite value"
            self.fail(f"dataset /{name}: {row_word} {row0 + k} holds {what}: a run file holds finite numbers only")
        return values

    def schema_dataset(self, name, sizes):
        """The dataset, its shape and type checked against the schema's row (with the file's sizes)."""
        return self.dataset(name, schema.shape(name, sizes), schema.dtype(name))

    def checked(self, name, sizes):
        """The whole dataset, its shape and type the schema's, floats finite."""
        data = self.schema_dataset(name, sizes)[...]
        return self.finite(name, data) if schema.dtype(name) == "f8" else data

    def increasing(self, name, t, unit=" s"):
        for k in np.flatnonzero(~(np.diff(t) > 0))[:1]:
            self.fail(f"dataset /{name} is not strictly increasing: row {k + 1} is {t[k + 1]:g}{unit} "
                      f"after {t[k]:g}{unit}")

    def strings(self, name, count=None):
        ds = self.need(name)
        if h5py.check_string_dtype(ds.dtype) is None or ds.ndim != 1:
            self.fail(f"dataset /{name} is not a list of strings")
        if count is not None and ds.shape[0] != count:
            self.fail(f"/{name} must have one entry per body ({count})")
        return [str(s) for s in ds.asstr()[...]]


def root_scalar(c: Checker, name: str, integer: bool, default=None):
    """The root attribute `name` as one integer (or one number of any kind), `default` where it is absent;
    RunFileError naming it when it is a string, an array or (for an integer) a float."""
    if name not in c.f.attrs:
        return default
    v = np.asarray(c.f.attrs[name])
    if v.shape != () or v.dtype.kind not in ("iu" if integer else "iuf"):
        c.fail(f"root attribute {name} = {str(c.f.attrs[name])[:40]}: must be "
               f"{'an integer' if integer else 'a number'}")
    return int(v) if integer else float(v)


def check_structure(c: Checker) -> dict:
    """What is checked on opening; returns the counts N, B, K, S, C, T and the per-snapshot contact index."""
    f = c.f
    fmt = f.attrs.get("format")
    fmt = fmt.decode(errors="replace") if isinstance(fmt, bytes) else fmt
    if not isinstance(fmt, str) or fmt not in FORMATS:
        c.fail(f"not a dem2d run file: format attribute is {fmt if fmt is not None else '(none)'}, "
               f"expected {', '.join(FORMATS)}")
    if "parameters" not in f:
        c.fail(f"written by dem2d {f.attrs.get('code_version', 'an unknown version')}, before run files carried "
               "their parameters (/parameters): run its scene again with this dem2d (make rebuilds the study's "
               "run files)")
    c.need("bodies/name")
    N = c.length("particles/diameter")
    sizes = {"N": N}
    diameter = c.checked("particles/diameter", sizes)
    mass = c.checked("particles/mass", sizes)
    for i in np.flatnonzero(~((diameter > 0) & (mass > 0)))[:1]:
        c.fail(f"grain {i} has diameter {diameter[i]:g} m and mass {mass[i]:g} kg/m in /particles: both must be > 0")
    B = sizes["B"] = len(c.strings("bodies/name"))
    thickness = c.checked("bodies/thickness", sizes)
    for b in np.flatnonzero(thickness < 0)[:1]:
        c.fail(f"dataset /bodies/thickness: body {b} has a negative thickness")
    c.strings("bodies/role", B)
    c.strings("bodies/shape", B)
    counts = c.checked("bodies/vertex_count", sizes)
    most = schema.schema()["max_vertices"]
    for n in counts[(counts < 1) | (counts > most)][:1]:
        c.fail(f"/bodies/vertex_count has {n}, expected 1..{most}")
    sizes["K"] = int(max([1, *counts]))
    for attr, count, what in (("n_particles", N, "grains (/particles)"), ("n_bodies", B, "bodies (/bodies)")):
        if (n := root_scalar(c, attr, True)) is not None and n != count:
            c.fail(f"root attribute {attr} is {n}, but the file holds {count} {what}")
    sizes["S"] = c.length("snapshots/time")
    times = c.checked("snapshots/time", sizes)
    steps = c.checked("snapshots/step", sizes)
    start = c.checked("snapshots/contact_start", sizes)
    c.increasing("snapshots/time", times)
    for k in np.flatnonzero(np.diff(steps) <= 0)[:1]:
        c.fail(f"dataset /snapshots/step is not strictly increasing (row {k + 1})")
    if start[0] != 0 or np.any(np.diff(start) < 0):
        c.fail("/snapshots/contact_start is not a non-decreasing index starting at 0")
    sizes["C"] = int(start[-1])
    for d in schema.schema()["datasets"]:  # every snapshot and contact dataset a run file holds
        if required(d) and d["path"].startswith(("snapshots/", "contacts/")):
            c.schema_dataset(d["path"], sizes)
    sizes["T"], series_times = 0, np.zeros(0)
    if "series/time" in f:
        sizes["T"] = c.length("series/time")
        series_times = c.checked("series/time", sizes)
        c.increasing("series/time", series_times)
    check_records(c, sizes)
    # the run's end (C++: RunReader::end_time): finite, at or after the last snapshot and series row
    end = root_scalar(c, "end_time", False)
    if end is None:
        c.fail("root attribute end_time is missing")
    last = max([0.0] + [float(t[-1]) for t in (times, series_times) if len(t)])
    if not (np.isfinite(end) and end >= last):
        c.fail(f"root attribute end_time = {end:g}: must be a finite time (s) at or after the run's last "
               f"snapshot and series row ({last:g} s)")
    if len(times) and end != float(times[-1]):  # (C++: the final state always ends the file)
        c.fail(f"root attribute end_time = {end:g}: must be the time of the run's last snapshot ({float(times[-1]):g} s), "
               "the state every run file ends with")
    return {**sizes, "times": times, "start": start}


def required(d: dict) -> bool:
    """Whether every run file holds the schema's dataset d (with /series/time, for the series)."""
    return not d["when"] and not d["optional"]


def check_records(c: Checker, sizes):
    """What no snapshot read needs but a run file holds; files written before these existed lack them."""
    f, N = c.f, sizes["N"]
    for name, symbol in (("lost/id", "L"), ("events/jam_time", "J")):
        if name in f:
            sizes[symbol] = c.length(name)
    for d in schema.schema()["datasets"]:  # the others' shapes and types (the series: Series)
        if d["optional"] and not d["path"].startswith("series/") and d["path"] in f and \
                all(not ch.isupper() or ch in sizes for ch in d["shape"]):  # (lost/x without lost/id: not read)
            c.schema_dataset(d["path"], sizes)
    if "particles/id" in f:
        ids = c.checked("particles/id", sizes)
        for i in np.flatnonzero(ids != np.arange(N))[:1]:
            c.fail(f"dataset /particles/id: row {i} holds {ids[i]}")
    if "particles/inertia" in f:  # > 0; +infinity for a grain that does not rotate
        inertia = f["particles/inertia"][...]
        for v in inertia[~(inertia > 0)][:1]:
            c.fail(f"dataset /particles/inertia holds {v:g}: moments of inertia are > 0")
    # the displacement window (C++: RunReader::displacement_window): a finite number of seconds >= 0
    w = root_scalar(c, "displacement_window", False, 0.0)
    if not (np.isfinite(w) and w >= 0.0):
        c.fail(f"root attribute displacement_window = {w:g}: must be a finite number of seconds >= 0 (0: none)")
    if "lost/id" in f:
        ids = c.checked("lost/id", sizes)
        for i in ids[(ids < 0) | (ids >= N)][:1]:
            c.fail(f"dataset /lost/id holds {i}, not a grain")
        for name in ("lost/step", "lost/x", "lost/y"):
            c.checked(name, sizes)
    if "events/jam_time" in f:
        c.increasing("events/jam_time", c.checked("events/jam_time", sizes))


def check_contacts(c: Checker, k, first, rows: dict, N, B):
    """A snapshot's contact rows: finite values, i a grain, j a grain > i or a body (-1 - b), sliding 0/1."""
    for name in ("fn", "ft", "overlap", "nx", "ny", "mr", "line"):
        if name in rows:
            c.finite(f"contacts/{name}", rows[name], "row", first)
    i, j, sliding = rows["i"], rows["j"], rows["sliding"]
    grain = j >= 0
    bad = (i < 0) | (i >= N) | np.where(grain, (j >= N) | (j <= i), -1 - j >= B) | (sliding > 1)
    for r in np.flatnonzero(bad)[:1]:
        c.fail(f"snapshot {k}: contact row {first + r} (i = {i[r]}, j = {j[r]}, sliding = {sliding[r]}) is not a "
               "contact: /contacts/i must name a grain, /contacts/j a grain j > i or a body (-1 - b), "
               "/contacts/sliding 0 or 1")


SERIES = [name for name in schema.group("series/") if name != "time"]  # what /series holds in every run file


def check_series_dataset(c: Checker, name, sizes):
    """/series/<name>: one row per /series/time; the schema's shape and type (finite floats), or floats of
    any row shape for a column the schema does not list."""
    path = f"series/{name}"
    ds = c.need(path)
    if ds.ndim == 0 or ds.shape[0] != sizes["T"]:
        c.fail(f"dataset /{path} has shape {list(ds.shape)}, expected {sizes['T']} rows (one per /series/time)")
    if schema.known(path):
        return c.checked(path, sizes)
    return c.finite(path, c.dataset(path, ds.shape, "f8")[...])


def obeys_rule(rule: str, v: float):
    """Whether v obeys a rule as the writer spells it ("finite", "> 0", ">= 0", "0 or 1", "in (0, 1]");
    None if unknown."""
    if rule == "finite":
        return bool(np.isfinite(v))
    if rule == "0 or 1":
        return v in (0.0, 1.0)
    if rule == "> 0":
        return bool(np.isfinite(v) and v > 0)
    if rule == ">= 0":
        return bool(np.isfinite(v) and v >= 0)
    if not (rule.startswith(("in (", "in [")) and rule.endswith((")", "]"))):
        return None
    try:
        lo, hi = (float(x) for x in rule[4:-1].split(","))
    except ValueError:
        return None
    return bool(np.isfinite(v) and (v > lo if rule[3] == "(" else v >= lo) and (v < hi if rule[-1] == ")" else v <= hi))


def check_parameter_keys(c: Checker, g: h5py.Group):
    """Every value a /parameters group lists in its attribute `keys` is there."""
    groups = [g]
    g.visititems(lambda n, o: groups.append(o) if isinstance(o, h5py.Group) else None)
    for group in groups:
        listed = group.attrs.get("keys")
        for key in (listed.decode() if isinstance(listed, bytes) else listed or "").split(","):
            if key and not isinstance(group.get(key), h5py.Dataset):
                c.fail(f"{group.name}/{key}: missing")


def check_parameter(c: Checker, ds: h5py.Dataset):
    """A /parameters value: float64, one number or of its shape in the schema, each number obeying the rule
    stored with it (attribute `valid`; flags: "0 or 1")."""
    name = ds.name.lstrip("/")
    if dtype_code(ds) != "f8":
        c.fail(f"/{name}: not float64")
    shape = schema.parameters()["shapes"].get(name.rsplit("/", 1)[-1])
    values = np.asarray(ds[()], dtype=float).reshape(-1)
    if shape is None and ds.ndim != 0:
        c.fail(f"/{name}: not a scalar")
    if shape == "n,2" and (ds.ndim != 2 or ds.shape[1] != 2):
        c.fail(f"/{name}: not a list of (x, y)")
    if shape not in (None, "n,2") and values.size != int(shape):
        c.fail(f"/{name}: {values.size} values, expected {shape}")
    rule = ds.attrs.get("valid", "finite")
    rule = rule.decode() if isinstance(rule, bytes) else str(rule)
    for v in values:
        ok = obeys_rule(rule, float(v))
        if ok is None:
            c.fail(f"/{name}@valid: '{rule}' is not a rule this reader knows")
        if not ok:
            c.fail(f"/{name}: {float(v):g}: must be {rule}")
    return ds[()]

#!/usr/bin/python3
"""Checks a dem2d run file against its schema, and its XDMF companion.

Usage: /usr/bin/python3 tests/check_run_file.py --schema SCHEMA.json RUN.h5 [RUN.xdmf] [--same-as OTHER.h5]
SCHEMA.json is the program's own (`dem2d inspect --schema > SCHEMA.json`): the
root attributes, every dataset's type and shape, the energy ledger's terms and
the effects come from there, not from a copy here. The XDMF defaults to RUN.h5
with the extension .xdmf. With --same-as, every dataset must also equal
OTHER.h5's bit for bit (a resumed run against an uninterrupted one). Needs h5py
and numpy. Prints every problem found and exits 1 if there is any, 0 otherwise.
"""
import argparse
import json
import os
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import h5py
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "python"))  # the tree's reader: its shape syntax
from dem2d.checks import dtype_code  # noqa: E402
from dem2d.schema import shape_of  # noqa: E402

ATTRIBUTE_TYPES = {"str": str, "i8": np.int64, "f8": np.float64}
ENERGY = "series/energy/"


def datasets(f):
    names = []
    f.visititems(lambda name, obj: names.append(name) if isinstance(obj, h5py.Dataset) else None)
    return names


def check_run_file(f, schema, errors):
    for a in schema["attributes"]:
        name, kind = a["name"], ATTRIBUTE_TYPES[a["type"]]
        if name not in f.attrs:
            errors.append(f"missing root attribute {name}")
        elif kind is str and not isinstance(f.attrs[name], (str, bytes)):
            errors.append(f"attribute {name} is not a string")
        elif kind is not str and np.asarray(f.attrs[name]).dtype != kind:
            errors.append(f"attribute {name} is {np.asarray(f.attrs[name]).dtype}, not {np.dtype(kind)}")
    if errors:
        return
    if f.attrs["format"] != schema["format"]:
        errors.append(f"format is {f.attrs['format']!r}, the schema's {schema['format']!r}")
    effects = [e for e in f.attrs["effects"].split(",") if e]
    if not set(effects) <= set(schema["effects"]):
        errors.append(f"unknown effects {set(effects) - set(schema['effects'])}")

    dim = lambda name: f[name].shape[0] if name in f else -1  # noqa: E731
    dims = {"N": int(f.attrs["n_particles"]), "B": int(f.attrs["n_bodies"]), "T": dim("series/time"),
            "S": dim("snapshots/time"), "C": dim("contacts/i"), "L": dim("lost/id"), "J": dim("events/jam_time"),
            "K": max([1] + [int(n) for n in f["bodies/vertex_count"][()]]) if "bodies/vertex_count" in f else -1,
            "Q": dim("xdmf/sequence")}
    assert set(dims) == set(schema["dimensions"]), f"the schema's dimensions {sorted(schema['dimensions'])}"
    N, B = dims["N"], dims["B"]
    energy = "series/energy" in f
    known = set()
    for d in schema["datasets"]:
        name, code = d["path"], d["type"]
        known.add(name)
        if d["when"] and not (d["when"] == "output.energy_balance" and energy):
            continue
        if name not in f:
            errors.append(f"missing dataset /{name}")
        elif f[name].shape != shape_of(d["shape"], dims):
            errors.append(f"/{name} has shape {f[name].shape}, expected {shape_of(d['shape'], dims)}")
        elif dtype_code(f[name]) != code:
            errors.append(f"/{name} is {dtype_code(f[name])}, expected {code}")
    for name in datasets(f):
        if name not in known and not name.startswith("parameters/"):
            errors.append(f"/{name}: a dataset the schema does not know")
    if errors:
        return
    for name in datasets(f):  # every dataset says what it holds
        for attr in ("units", "description"):
            if not isinstance(f[name].attrs.get(attr), str) or not f[name].attrs[attr]:
                errors.append(f"/{name} has no {attr} attribute")
    if dim("lost/id") != f.attrs["lost_particles"]:
        errors.append("lost_particles does not match /lost/id")
    if not np.array_equal(f["particles/id"][...], np.arange(N)):
        errors.append("/particles/id is not 0..N-1")
    for table in ("series", "snapshots"):
        step = f[table + "/step"][...]
        if np.any(np.diff(step) < 0) or (len(step) and step[-1] > f.attrs["steps"]):
            errors.append(f"/{table}/step is not ascending up to the final step")
        if not np.allclose(f[table + "/time"][...], step * f.attrs["dt"], rtol=1e-12, atol=0):
            errors.append(f"/{table}/time is not step * dt")

    start = f["snapshots/contact_start"][...]
    C = dim("contacts/i")
    if start[0] != 0 or start[-1] != C or np.any(np.diff(start) < 0):
        errors.append("/snapshots/contact_start is not 0 .. C, ascending")
    i, j = f["contacts/i"][...], f["contacts/j"][...]
    if np.any((i < 0) | (i >= N)) or np.any((j >= N) | (j < -B)):
        errors.append("/contacts/i or /contacts/j out of range")
    if np.any((j >= 0) & (j <= i)):
        errors.append("/contacts/j: grain partners must be > i")
    overlap, fn = f["contacts/overlap"][...], f["contacts/fn"][...]
    if "cohesion" in effects:  # attraction: a contact may pull (fn < 0) and stay open across a gap (overlap < 0)
        if not (np.isfinite(overlap).all() and np.isfinite(fn).all()):
            errors.append("/contacts: overlap and fn must be finite")
    elif np.any(overlap <= 0) or np.any(fn < 0):
        errors.append("/contacts: overlap must be > 0 and fn >= 0 (without the cohesion effect)")
    if not np.allclose(np.hypot(f["contacts/nx"][...], f["contacts/ny"][...]), 1.0, atol=1e-12):
        errors.append("/contacts: normals are not unit vectors")
    if np.any(f["contacts/sliding"][...] > 1):
        errors.append("/contacts/sliding is not 0/1")
    mu_star = f["contacts/mu_star"][...]
    if np.any(mu_star[~np.isnan(mu_star)] > 1 + 1e-9) or np.any(mu_star < 0):
        errors.append("/contacts/mu_star outside [0, 1] (the Coulomb cone)")
    line, position = f["contacts/line"][...], f["snapshots/position"]
    seq = f["xdmf/sequence"][...]
    if not np.array_equal(seq, np.arange(len(seq))) or len(seq) < 2 * max(np.diff(start), default=0):
        errors.append("/xdmf/sequence is not 0, 1, ... up to twice the most contacts of a snapshot")
    for k in range(len(start) - 1):  # contacts of a snapshot come in slot order: pairs by (i, j), then walls
        ik, jk = i[start[k]:start[k + 1]], j[start[k]:start[k + 1]]
        pairs = jk >= 0
        if np.any(np.diff(pairs.astype(int)) > 0) or np.any(np.diff(ik[pairs]) < 0) or np.any(np.diff(ik[~pairs]) < 0):
            errors.append(f"contacts of snapshot {k} are not in slot order")
            break
        xy, lk = position[k], line[start[k]:start[k + 1]]
        if not (np.array_equal(lk[:, 0], xy[ik]) and np.array_equal(lk[pairs, 1], xy[jk[pairs]])):
            errors.append(f"/contacts/line of snapshot {k}: not from grain i's centre to grain j's")
            break
    if "series/energy" in f:
        check_energy(f, schema, errors)


def check_energy(f, schema, errors):
    """The ledger's terms (shapes and types checked with the layout), and their sum constant to round-off
    (docs/energy.md)."""
    signs = schema["energy_balance"]  # each term's sign in the conserved total
    terms = {t: f[ENERGY + t][...] for t in signs}
    total = sum(signs[t] * v for t, v in terms.items())
    scale = max(np.max(np.abs(v)) for v in terms.values())
    if scale > 0 and np.max(np.abs(total - total[0])) > 1e-9 * scale:
        errors.append(f"the energy balance does not close: its total moves by {np.max(np.abs(total - total[0])):.3g} J/m "
                      f"(largest term {scale:.3g} J/m)")


# run.xdmf: one temporal collection of spatial collections (one per snapshot) of up to
# three named grids: topology type, and the arrays each grid must have
PARTS = {"particles": ("Polyvertex", {"diameter", "velocity", "omega", "theta", "active"}),
         "bodies": ("Polyline", {"thickness"}),
         "contacts": ("Polyline", {"fn", "ft", "mu_star", "overlap", "sliding"})}


def check_xdmf(f, h5_path, xdmf_path, errors):
    try:
        root = ET.parse(xdmf_path).getroot()
    except ET.ParseError as e:
        errors.append(f"{xdmf_path}: not well-formed XML: {e}")
        return
    h5_name = os.path.basename(h5_path)
    times = f["snapshots/time"][...]
    start = f["snapshots/contact_start"][...]
    N, B = int(f.attrs["n_particles"]), int(f.attrs["n_bodies"])
    top = root.findall("./Domain/Grid")
    if len(top) != 1 or top[0].get("CollectionType") != "Temporal":
        errors.append(f"{xdmf_path}: the domain holds {len(top)} grids, expected one temporal collection")
        return
    snapshots = top[0].findall("Grid")
    if len(snapshots) != len(times):
        errors.append(f"{xdmf_path}: {len(snapshots)} snapshots, the run file has {len(times)}")
        return
    for k, snapshot in enumerate(snapshots):
        if snapshot.get("CollectionType") != "Spatial":
            errors.append(f"snapshot {k}: not a spatial collection")
            continue
        if float(snapshot.find("Time").get("Value")) != times[k]:
            errors.append(f"snapshot {k}: time differs from /snapshots/time")
        present = {"particles": True, "bodies": B > 0, "contacts": start[k + 1] > start[k]}
        grids = {g.get("Name"): g for g in snapshot.findall("Grid")}
        expected = [name for name in PARTS if present[name]]
        if list(grids) != expected:
            errors.append(f"snapshot {k}: grids {list(grids)}, expected {expected}")
            continue
        for name, grid in grids.items():
            where = f"snapshot {k} {name}"
            topology, arrays = PARTS[name]
            if grid.find("Topology").get("TopologyType") != topology:
                errors.append(f"{where}: topology is not {topology}")
            if grid.find("Geometry").get("GeometryType") != "XY":
                errors.append(f"{where}: geometry is not XY")
            names = {a.get("Name") for a in grid.findall("Attribute")}
            if names != arrays:
                errors.append(f"{where}: attributes {sorted(names)}, expected {sorted(arrays)}")
            for item in grid.iter("DataItem"):
                check_item(f, item, k, start, h5_name, where, errors)
            connectivity = grid.find("Topology/DataItem").text.strip()
            if name == "particles" and N and connectivity != f"{h5_name}:/particles/id":
                errors.append(f"{where}: connectivity is not /particles/id")


def check_item(f, item, k, start, h5_name, where, errors):
    """A DataItem names a dataset of the run file, and selects within it what grid k shows."""
    dims = tuple(int(d) for d in item.get("Dimensions").split())
    path, _, selection = item.text.strip().partition("|")
    file, _, dataset = path.partition(":")
    if file != h5_name or dataset.lstrip("/") not in f:
        errors.append(f"{where}: {item.text.strip()} does not name a dataset of {h5_name}")
        return
    shape = f[dataset].shape
    if not selection:
        if shape != dims:
            errors.append(f"{where}: {dataset} has shape {shape}, declared {dims}")
        return
    first, stride, count, space = ([int(v) for v in part.split()] for part in selection.split(":"))
    if tuple(space) != shape or np.prod(count) != np.prod(dims):
        errors.append(f"{where}: selection {selection} does not fit {dataset} {shape} / {dims}")
    elif any(c > 0 and s + (c - 1) * t >= n for s, t, c, n in zip(first, stride, count, shape)):
        errors.append(f"{where}: selection {selection} out of bounds of {dataset} {shape}")
    elif dataset.startswith("/snapshots/") and first[0] != k:
        errors.append(f"{where}: {dataset} selects snapshot {first[0]}")
    elif dataset.startswith("/contacts/") and (first[0], count[0]) != (start[k], start[k + 1] - start[k]):
        errors.append(f"{where}: {dataset} selects rows {first[0]}+{count[0]}, not snapshot {k}'s contacts")


def compare_datasets(f, other_path, errors):
    """Every dataset of f equal, bit for bit, to the same dataset of other_path."""
    with h5py.File(other_path, "r") as g:
        for name in datasets(f):
            if name not in g:
                errors.append(f"{name} missing from {other_path}")
                continue
            a, b = f[name][()], g[name][()]
            same = a.tolist() == b.tolist() if a.dtype == object else a.tobytes() == b.tobytes()
            if a.dtype != b.dtype or a.shape != b.shape or not same:
                errors.append(f"{name} differs from {other_path}")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--schema", required=True, help="the program's schema (dem2d inspect --schema > FILE)")
    parser.add_argument("run")
    parser.add_argument("xdmf", nargs="?")
    parser.add_argument("--same-as", dest="same_as")
    args = parser.parse_args()
    h5_path = args.run
    xdmf_path = args.xdmf or os.path.splitext(h5_path)[0] + ".xdmf"
    errors = []
    try:
        with open(args.schema) as s:
            schema = json.load(s)
    except (OSError, json.JSONDecodeError) as e:
        sys.exit(f"{args.schema}: cannot read the schema: {e}")
    try:
        f = h5py.File(h5_path, "r")
    except OSError as e:
        sys.exit(f"{h5_path}: cannot open as HDF5: {e}")
    with f:
        check_run_file(f, schema, errors)
        if not errors:
            check_xdmf(f, h5_path, xdmf_path, errors)
        if not errors and args.same_as:
            compare_datasets(f, args.same_as, errors)
        summary = {t: f[t + "/time"].shape[0] for t in ("series", "snapshots") if t + "/time" in f}
    for e in errors:
        print(f"{h5_path}: {e}", file=sys.stderr)
    if errors:
        sys.exit(1)
    print(f"{h5_path}: ok ({summary}, XDMF {xdmf_path})")


if __name__ == "__main__":
    main()

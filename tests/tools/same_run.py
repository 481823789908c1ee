#!/usr/bin/env python3
"""same_run.py A.h5 B.h5 [--ignore-attr NAME ...]: are two run files the same run?

Every dataset must match bit for bit (same shape, dtype and bytes) and every
attribute must be equal, except those that describe the invocation rather than
the run: wall time, code version, threads, paths. Prints the first
differences; exit status 0 if the same, 1 if not, 2 on bad input. Used to
check that a restructuring of the engine leaves existing scenes' results
bitwise unchanged.
"""
import argparse
import sys

try:
    import h5py
    import numpy as np
except ImportError as e:  # Debian: python3-h5py, python3-numpy
    sys.exit(f"same_run.py: {e}; run it with a Python that has h5py and numpy (e.g. /usr/bin/python3)")

INVOCATION = {"wall_seconds", "code_version", "threads", "scene_path", "initial_run", "created"}


def items(f):
    out = {}
    def visit(name, obj):
        out[name] = obj
    f.visititems(visit)
    return out


def same_attrs(a, b, where, ignore, diffs):
    for k in sorted(set(a.attrs) | set(b.attrs)):
        if k in ignore:
            continue
        if k not in a.attrs or k not in b.attrs:
            diffs.append(f"{where}: attribute {k} only in {'B' if k not in a.attrs else 'A'}")
            continue
        va, vb = a.attrs[k], b.attrs[k]
        if isinstance(va, np.ndarray) or isinstance(vb, np.ndarray):
            eq = np.array_equal(np.asarray(va), np.asarray(vb))
        else:
            eq = va == vb
        if not eq:
            diffs.append(f"{where}: attribute {k}: {va!r} != {vb!r}")


def compare(pa, pb, ignore):
    diffs = []
    with h5py.File(pa, "r") as fa, h5py.File(pb, "r") as fb:
        ia, ib = items(fa), items(fb)
        same_attrs(fa, fb, "/", ignore, diffs)
        for name in sorted(set(ia) | set(ib)):
            if name not in ia or name not in ib:
                diffs.append(f"/{name} only in {'B' if name not in ia else 'A'}")
                continue
            a, b = ia[name], ib[name]
            same_attrs(a, b, "/" + name, ignore, diffs)
            if isinstance(a, h5py.Dataset) != isinstance(b, h5py.Dataset):
                diffs.append(f"/{name}: a dataset in one file only")
                continue
            if not isinstance(a, h5py.Dataset):
                continue
            if a.size != b.size or a.dtype != b.dtype or a.shape != b.shape:
                diffs.append(f"/{name}: shape/dtype {a.shape} {a.dtype} != {b.shape} {b.dtype}")
                continue
            va, vb = a[()], b[()]
            if isinstance(va, np.ndarray) and va.dtype.kind in "fiub":
                if va.tobytes() != vb.tobytes():
                    bad = np.flatnonzero(va.reshape(-1).view(np.uint8) != vb.reshape(-1).view(np.uint8))
                    diffs.append(f"/{name}: {bad.size} bytes differ")
            elif not np.array_equal(np.asarray(va), np.asarray(vb)):
                diffs.append(f"/{name}: values differ")
    return diffs


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("a")
    ap.add_argument("b")
    ap.add_argument("--ignore-attr", action="append", default=[], help="also ignore this attribute")
    args = ap.parse_args()
    try:
        diffs = compare(args.a, args.b, INVOCATION | set(args.ignore_attr))
    except OSError as e:
        print(f"same_run.py: {e}", file=sys.stderr)
        return 2
    for d in diffs[:20]:
        print(f"{args.a} vs {args.b}: {d}")
    if len(diffs) > 20:
        print(f"... and {len(diffs) - 20} more")
    print(f"same_run: {'same' if not diffs else f'{len(diffs)} differences'}: {args.a} {args.b}")
    return 1 if diffs else 0


if __name__ == "__main__":
    sys.exit(main())

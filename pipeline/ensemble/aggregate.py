#!/usr/bin/python3
"""Aggregates the members of an ensemble (docs/ensemble.md).

    python3 pipeline/ensemble/aggregate.py ENSEMBLE_DIR PRESET MEMBER_DIR...

Reads each member's metrics.json and pulloff/drag.csv and writes into
ENSEMBLE_DIR:

  stats.json    for every number of the members' metrics (dotted path): the
                members' values, n (the finite ones), mean, sd (n - 1), and a
                95 % bootstrap interval of the mean (10 000 resamples of the
                members, percentile; fixed seed: the same members give the
                same interval)
  metrics.json  the members' means in the layout of one run's metrics.json
                (what `make check` judges, with stats.json's intervals)
  drag.csv      the drag against height in 1 mm bins: every member's bin
                mean, and the ensemble's mean and sd
  drag.png      those profiles: the members, their mean and +-1 sd band

A missing or unreadable member file stops with a message naming it and the
make target that makes it (exit code 2).
"""
import csv
import json
import math
import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "report"))
from files import fail, read_json, write_atomic  # noqa: E402

RESAMPLES = 10000
SEED = 20261124
BIN_MM = 1.0


def numbers(tree, prefix=""):
    """(dotted path, value) of every number in a metrics tree (lists skipped)."""
    if isinstance(tree, dict):
        for k, v in tree.items():
            yield from numbers(v, f"{prefix}.{k}" if prefix else k)
    elif isinstance(tree, (int, float)) and not isinstance(tree, bool):
        yield prefix, float(tree)
    elif tree is None:
        yield prefix, math.nan


def bootstrap_ci(values: np.ndarray, rng) -> list:
    if len(values) == 1:
        return [float(values[0])] * 2
    means = rng.choice(values, size=(RESAMPLES, len(values)), replace=True).mean(axis=1)
    return [float(np.percentile(means, 2.5)), float(np.percentile(means, 97.5))]


def statistics(members: list) -> dict:
    paths = {}
    for m in members:
        for path, v in numbers({k: v for k, v in m.items() if k not in ("cost", "code_version", "preset")}):
            paths.setdefault(path, [])
    for m in members:
        flat = dict(numbers(m))
        for path in paths:
            paths[path].append(flat.get(path, math.nan))
    rng = np.random.default_rng(SEED)
    stats = {}
    for path, values in paths.items():
        finite = np.array([v for v in values if math.isfinite(v)])
        entry = {"values": [v if math.isfinite(v) else None for v in values], "n": int(len(finite))}
        if len(finite):
            entry["mean"] = float(finite.mean())
            entry["sd"] = float(finite.std(ddof=1)) if len(finite) > 1 else None
            entry["ci95"] = bootstrap_ci(finite, rng)
        else:
            entry.update(mean=None, sd=None, ci95=None)
        stats[path] = entry
    return stats


def nested(stats: dict) -> dict:
    out = {}
    for path, s in stats.items():
        node = out
        *parents, leaf = path.split(".")
        for p in parents:
            node = node.setdefault(p, {})
        node[leaf] = s["mean"]
    return out


def drag_bins(member_dirs: list, preset: str) -> tuple:
    profiles = []
    for d in member_dirs:
        path = d / "pulloff" / "drag.csv"
        try:
            with open(path) as f:
                rows = list(csv.DictReader(f))
            h = np.array([float(r["height_mm"]) for r in rows])
            drag = np.array([float(r["drag_N_per_m"]) for r in rows])
        except (OSError, KeyError, ValueError) as e:
            fail(f"{path}: unreadable ({e}): run `make ensemble PRESET={preset}`")
        profiles.append((h, drag))
    top = max(float(h.max()) for h, _ in profiles if len(h))
    edges = np.arange(0.0, top + BIN_MM, BIN_MM)
    centres = 0.5 * (edges[1:] + edges[:-1])
    table = np.full((len(profiles), len(centres)), np.nan)
    for k, (h, drag) in enumerate(profiles):
        idx = np.digitize(h, edges) - 1
        for b in range(len(centres)):
            sel = idx == b
            if sel.any():
                table[k, b] = drag[sel].mean()
    return centres, table


def write_drag(out: Path, names: list, centres, table) -> None:
    with warnings.catch_warnings():  # a bin no member reached: NaN, written empty
        warnings.simplefilter("ignore", RuntimeWarning)
        mean = np.nanmean(table, axis=0)
        sd = np.nanstd(table, axis=0, ddof=1) if len(names) > 1 else np.zeros_like(mean)
    lines = ["height_mm," + ",".join(f"{n}_N_per_m" for n in names) + ",mean_N_per_m,sd_N_per_m"]
    for b, h in enumerate(centres):
        cells = [f"{v:.6g}" if math.isfinite(v) else "" for v in list(table[:, b]) + [mean[b], sd[b]]]
        lines.append(f"{h:g}," + ",".join(cells))
    write_atomic(out / "drag.csv", "\n".join(lines) + "\n")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.5, 3.6), dpi=110)
    for k, n in enumerate(names):
        ax.plot(centres, table[k], lw=0.6, alpha=0.6, label=n if len(names) <= 8 else None)
    ax.fill_between(centres, mean - sd, mean + sd, color="k", alpha=0.15, lw=0, label="mean ± 1 sd")
    ax.plot(centres, mean, color="k", lw=1.4, label="ensemble mean")
    ax.set_xlabel("intruder height (mm)")
    ax.set_ylabel("drag (N/m), 1 mm bins")
    ax.set_title(f"Drag of {len(names)} ensemble members")
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    tmp = out / "drag.tmp.png"
    fig.savefig(tmp)
    tmp.replace(out / "drag.png")


def main(argv: list) -> int:
    if len(argv) < 4:
        fail("usage: aggregate.py ENSEMBLE_DIR PRESET MEMBER_DIR...")
    out, preset = Path(argv[1]), argv[2]
    member_dirs = [Path(d) for d in argv[3:]]
    members = [read_json(d / "metrics.json", f"make ensemble PRESET={preset}") for d in member_dirs]
    names = [d.name for d in member_dirs]
    stats = statistics(members)
    out.mkdir(parents=True, exist_ok=True)
    doc = {"preset": preset, "members": names, "code_versions": sorted({m.get("code_version", "") for m in members}),
           "bootstrap": {"resamples": RESAMPLES, "seed": SEED, "interval": "95 % percentile interval of the mean"},
           "metrics": stats}
    write_atomic(out / "stats.json", json.dumps(doc, indent=1) + "\n")
    means = nested(stats)
    means["preset"], means["members"] = preset, len(names)
    write_atomic(out / "metrics.json", json.dumps(means, indent=2) + "\n")
    centres, table = drag_bins(member_dirs, preset)
    write_drag(out, names, centres, table)
    print(f"aggregate: {len(names)} members, {len(stats)} metrics -> {out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

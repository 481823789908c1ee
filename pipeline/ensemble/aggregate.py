"""Aggregates the members of an ensemble (docs/ensemble.md).

    python3 -m pipeline.ensemble.aggregate ENSEMBLE_DIR PRESET MEMBER_DIR...

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
make target that makes it (exit code 2). So does a member that does not fit
the others: metrics that are not a JSON object, another preset, a stage of
the registry missing (--registry, pipeline/stages.toml), a metric that is not
a finite number or null (a detector's "none") where another member has a
number, or a metric the others have and it lacks: every member is judged on,
or none. The machine's times (any `cost` and `wall_seconds`) are not metrics
and are left out, so the same members give the same files.
"""
import argparse
import csv
import json
import math
import sys
import warnings
from pathlib import Path

import numpy as np

from pipeline import stages
from pipeline.files import fail, read_json, write_atomic

RESAMPLES = 10000
SEED = 20261124
BIN_MM = 1.0
MAX_BINS = 10**6  # bins of the drag profile: a height range wider than this is a damaged file


def is_time(path: str) -> bool:
    """The machine's wall-clock figures: not metrics of the run."""
    parts = path.split(".")
    return "cost" in parts or parts[-1] in ("wall_seconds", "ns_per_particle_step", "particle_steps_per_second")


def leaves(tree, prefix=""):
    """(dotted path, value) of every leaf of a metrics tree, the machine's times left out."""
    if isinstance(tree, dict):
        for k, v in tree.items():
            yield from leaves(v, f"{prefix}.{k}" if prefix else k)
    elif not is_time(prefix):
        yield prefix, tree


def flat(member: dict, stages: list) -> dict:
    """{dotted path: value} of a member's metrics, its registry stages only."""
    return dict(leaves({k: v for k, v in member.items() if k in stages}))


def is_number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def is_finite(v) -> bool:
    """A number a float holds finitely (JSON's integers have no bound: 10**400 is not one)."""
    try:
        return is_number(v) and math.isfinite(v)
    except OverflowError:
        return False


def member_problems(members: list, dirs: list, preset: str, stages: list) -> list:
    """What keeps each member from being judged with the others (empty if nothing)."""
    problems, flats = [], []
    for d, m in zip(dirs, members):
        where = d / "metrics.json"
        if not isinstance(m, dict):
            problems.append(f"{where}: not a JSON object of metrics but {type(m).__name__}")
            flats.append(None)
            continue
        if m.get("preset") != preset:
            problems.append(f"{where}: preset {m.get('preset')!r}, not {preset!r}: a member of another ensemble")
        missing = [s for s in stages if not isinstance(m.get(s), dict)]
        if missing:
            problems.append(f"{where}: no metrics of the stage(s) {', '.join(missing)}")
        flats.append(flat(m, stages))
    numeric = {path for f in flats if f for path, v in f.items() if is_number(v)}
    for d, f in zip(dirs, flats):
        if f is None:
            continue
        for path in sorted(numeric):
            if path not in f:
                holder = next(h for h, g in zip(dirs, flats) if g and is_number(g.get(path)))
                problems.append(f"{d / 'metrics.json'}: {path} is missing ({holder.name} has it)")
            elif f[path] is not None and not is_finite(f[path]):
                problems.append(f"{d / 'metrics.json'}: {path} = {json.dumps(f[path])[:60]}: "
                                "not a finite number or null")
    return problems


def scaled(values: np.ndarray) -> float:
    """A scale that keeps sums of huge values finite (1e308 + 1e308 would overflow); 1 for ordinary ones,
    whose sums stay exactly as they were."""
    top = float(np.max(np.abs(values))) if len(values) else 0.0
    return top if top > 1e100 else 1.0


def bootstrap_ci(values: np.ndarray, rng) -> list:
    if len(values) == 1:
        return [float(values[0])] * 2
    k = scaled(values)
    means = rng.choice(values / k, size=(RESAMPLES, len(values)), replace=True).mean(axis=1)
    return [k * float(np.percentile(means, 2.5)), k * float(np.percentile(means, 97.5))]


def statistics(members: list, stages: list) -> dict:
    flats = [flat(m, stages) for m in members]
    # every number or null (a detector's "none") a member has, in the order they first appear
    paths = list(dict.fromkeys(path for f in flats for path, v in f.items() if v is None or is_number(v)))
    rng = np.random.default_rng(SEED)
    stats = {}
    for path in paths:
        values = [float(f[path]) if f.get(path) is not None else math.nan for f in flats]
        finite = np.array([v for v in values if math.isfinite(v)])
        entry = {"values": [v if math.isfinite(v) else None for v in values], "n": int(len(finite))}
        if len(finite):
            k = scaled(finite)
            entry["mean"] = k * float((finite / k).mean())
            entry["sd"] = k * float((finite / k).std(ddof=1)) if len(finite) > 1 else None
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
            if not len(rows) or not (np.isfinite(h).all() and np.isfinite(drag).all()):
                raise ValueError("no rows" if not len(rows) else "a value is not finite")
        except (OSError, KeyError, ValueError, TypeError) as e:  # (TypeError: a row cut short)
            fail(f"{path}: unreadable ({e}): delete it and run `make ensemble PRESET={preset}`")
        profiles.append((h, drag))
    low = min(0.0, BIN_MM * math.floor(min(float(h.min()) for h, _ in profiles) / BIN_MM))
    top = max(float(h.max()) for h, _ in profiles)
    if (top - low) / BIN_MM > MAX_BINS:
        worst = max(zip(member_dirs, profiles), key=lambda m: float(np.abs(m[1][0]).max()))[0]
        fail(f"{worst / 'pulloff' / 'drag.csv'}: heights from {low:g} to {top:g} mm: more than {MAX_BINS} bins of "
             f"{BIN_MM:g} mm (a pull-off is at most metres); delete it and run `make ensemble PRESET={preset}`")
    edges = np.arange(low, top + BIN_MM, BIN_MM)
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
    try:
        fig.savefig(tmp)
        tmp.replace(out / "drag.png")
    except OSError as e:  # a full disk: no half-written figure, a message instead of a traceback
        tmp.unlink(missing_ok=True)
        fail(f"{out / 'drag.png'}: cannot write it ({e.strerror or e}); nothing was left half-written")


def registry_stages(path: Path) -> list:
    """The names of the registry's stages, read and checked by the registry's own reader (pipeline/stages.py)."""
    try:
        return [s.name for s in stages.load(path)]
    except stages.RegistryError as e:
        fail(f"not a stage registry: {e}")


def main(argv: list) -> int:
    args = argparse.ArgumentParser(description="Aggregates an ensemble's members (docs/ensemble.md).")
    args.add_argument("--registry", type=Path, default=Path(__file__).resolve().parents[1] / "stages.toml",
                      help="the stage registry whose stages every member must have (pipeline/stages.toml)")
    args.add_argument("out", type=Path, metavar="ENSEMBLE_DIR")
    args.add_argument("preset", metavar="PRESET")
    args.add_argument("member_dirs", type=Path, nargs="+", metavar="MEMBER_DIR")
    a = args.parse_args(argv[1:])
    out, preset, member_dirs = a.out, a.preset, a.member_dirs
    stages = registry_stages(a.registry)
    members = [read_json(d / "metrics.json", f"make ensemble PRESET={preset}") for d in member_dirs]
    problems = member_problems(members, member_dirs, preset, stages)
    if problems:
        fail(f"{len(problems)} problem(s) with the members; none is aggregated until each is fixed (delete the "
             f"member's folder and run `make ensemble PRESET={preset}` to remake it):\n  " + "\n  ".join(problems[:20]) +
             (f"\n  ... and {len(problems) - 20} more" if len(problems) > 20 else ""))
    names = [d.name for d in member_dirs]
    stats = statistics(members, stages)
    centres, table = drag_bins(member_dirs, preset)  # (read before anything is written)
    out.mkdir(parents=True, exist_ok=True)
    doc = {"preset": preset, "members": names, "code_versions": sorted({m.get("code_version", "") for m in members}),
           "bootstrap": {"resamples": RESAMPLES, "seed": SEED, "interval": "95 % percentile interval of the mean"},
           "metrics": stats}
    write_atomic(out / "stats.json", json.dumps(doc, indent=1) + "\n")
    means = nested(stats)
    means["preset"], means["members"] = preset, len(names)
    write_atomic(out / "metrics.json", json.dumps(means, indent=2) + "\n")
    write_drag(out, names, centres, table)
    print(f"aggregate: {len(names)} members, {len(stats)} metrics -> {out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

"""The accuracy sweep's table and Pareto figure (make accuracy).

    /usr/bin/python3 -m pipeline.accuracy.table data/accuracy.toml results/accuracy

For every point of data/accuracy.toml:
  - the slice comparison: over the first slice_mm of travel, the drag profile
    (smoothed over smoothing_d), its bottom peak, its mean and the largest
    overlap, against the paper-fidelity reference point (knob = "reference");
  - for whole pull-offs, every metric of data/paper_targets.toml against the
    whole-run reference (full_reference = true), a miss being a deviation
    larger than the paper target's own tolerance (for a bound, a verdict that
    differs from the reference's);
  - the cost: the engine's wall time on one thread (a slice's projected to the
    whole pull-off's travel).
and for every [[cg]] setting the cg stage's metrics against the reference
grid. Writes RESULTS/table.json, RESULTS/table.md, RESULTS/pareto.png and
RESULTS/profiles.png (the smoothed drag profiles).
"""
import json
import math
import sys
from pathlib import Path

from pipeline.files import fail, read_json, read_toml, write_atomic

MAKE = "make accuracy"
CG_METRICS = ["cg.cone_angle_deg", "cg.wall_mobility_length_mm", "cg.dilatancy_delta_phi"]
KNOB_ORDER = ["reference", "default", "replica", "kn", "dt", "V"]


def dotted(metrics: dict, path: str):
    v = metrics
    for key in path.split("."):
        if not isinstance(v, dict) or key not in v:
            return None
        v = v[key]
    return v if isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) else None


class Run:
    """One point's pull-off: its drag series, overlaps and cost."""

    def __init__(self, directory: Path):
        import numpy as np

        import dem2d

        run_file = directory / "pulloff" / "run.h5"
        try:
            with dem2d.open_run(run_file) as r:
                self.wall = float(r.attrs["wall_seconds"])
                self.steps = int(r.attrs["steps"])
                self.dt = float(r.dt)
                d_mean = float(np.mean(r.particles.diameter))
                self.overlap = np.asarray(r.series["max_overlap"]) / d_mean
                self.d_mean_mm = 1e3 * d_mean
        except (OSError, KeyError, ValueError) as e:
            fail(f"{run_file}: unreadable ({e}): rerun `{MAKE}`")
        csv = directory / "pulloff" / "drag.csv"
        try:
            data = np.loadtxt(csv, delimiter=",", skiprows=1, ndmin=2)
        except (OSError, ValueError) as e:
            fail(f"{csv}: unreadable ({e}): rerun `{MAKE}`")
        self.height, self.drag = data[:, 1], data[:, 2]
        n = min(len(self.height), len(self.overlap))
        self.height, self.drag, self.overlap = self.height[:n], self.drag[:n], self.overlap[:n]
        self.travel = float(self.height[-1] - self.height[0])

    def smoothed(self, grid, window_mm: float):
        """Running mean of the drag over window_mm of travel, sampled at grid (mm)."""
        import numpy as np

        c = np.concatenate([[0.0], np.cumsum(self.drag)])
        lo = np.searchsorted(self.height, grid - window_mm / 2)
        hi = np.searchsorted(self.height, grid + window_mm / 2, side="right")
        return (c[hi] - c[lo]) / np.maximum(hi - lo, 1)

    def slice_metrics(self, top_mm: float) -> dict:
        import numpy as np

        keep = self.height <= self.height[0] + top_mm + 1e-9
        h, f = self.height[keep], self.drag[keep]
        k = int(np.argmax(f))
        return {"peak_drag_N_per_m": float(f[k]), "peak_height_mm": float(h[k]),
                "mean_drag_N_per_m": float(np.mean(f)), "max_overlap_over_d": float(np.max(self.overlap[keep]))}


def profile_deviation(run: Run, ref: Run, top_mm: float, window_mm: float, step_mm: float) -> float:
    """rms(F - F_ref) / rms(F_ref) of the smoothed profiles over [start, start + top_mm]."""
    import numpy as np

    start = max(run.height[0], ref.height[0])
    grid = np.arange(start, start + top_mm + 1e-9, step_mm)
    a, b = run.smoothed(grid, window_mm), ref.smoothed(grid, window_mm)
    return float(np.sqrt(np.mean((a - b) ** 2)) / np.sqrt(np.mean(b ** 2)))


def reference_members(points: list) -> list:
    """The whole-run reference's point name (full_reference = true), then its replicas' ([] without one)."""
    ref = next((p.get("name") for p in points if p.get("full_reference")), None)
    return [] if ref is None else [ref] + [p.get("name") for p in points if p.get("replica_of") == ref]


def verdict(target: dict, metrics: dict):
    """A bound target's own verdict on metrics (None: a metric missing)."""
    v, b = dotted(metrics, target["metric"]), bound(target, metrics)
    if v is None or b is None:
        return None
    return v < b if "below" in target else v > b


def bound(target: dict, metrics: dict):
    """The value a bound target compares with: its constant, or another metric of the same run."""
    if "above_metric" in target:
        return dotted(metrics, target["above_metric"])
    return target.get("below", target.get("above"))


MIN_POWER = 0.8  # data/paper_targets.toml's default min_power (a target may name its own), as `make check` reads it


def answer(target: dict, metrics: dict):
    """What a run says to a target, read as `make check` reads it: its number; without one, "none" where
    the target's power metric reaches min_power (the detector would have found the claim: evidence of
    absence), None (undetermined) where the power is lower or the target names `undecided`, else
    "missing" (a failure of its own)."""
    v = dotted(metrics, target["metric"])
    if v is not None:
        return v
    if "power" in target:
        power = dotted(metrics, target["power"])
        return "none" if power is not None and power >= target.get("min_power", MIN_POWER) else None
    return None if "undecided" in target else "missing"


def compare_targets(targets: list, metrics: dict, ref: dict) -> list:
    """Every target's metric against the reference's: deviation, its tolerance, ok, and whether both
    answers are decided (not undetermined: only then can a difference count as a miss)."""
    rows = []
    for t in targets:
        v, r = dotted(metrics, t["metric"]), dotted(ref, t["metric"])
        a, b = answer(t, metrics), answer(t, ref)
        row = {"metric": t["metric"], "result": t["result"], "value": v, "reference": r,
               "deviation": None if v is None or r is None else v - r, "answer": a}
        if "tolerance" in t:
            row["tolerance"], row["decided"] = t["tolerance"], a is not None and b is not None
            if "none" in (a, b):  # two evidenced nones agree; a none against a number does not
                row["ok"] = a == b
            else:
                row["ok"] = row["deviation"] is not None and abs(row["deviation"]) <= t["tolerance"]
            row["normalised"] = None if row["deviation"] is None else abs(row["deviation"]) / t["tolerance"]
        else:  # a bound or a shape: the verdict must not change (two evidenced nones: the same verdict)
            mine, theirs = verdict(t, metrics), verdict(t, ref)
            row["ok"] = a == b == "none" or (mine is not None and mine == theirs)
            row["verdict"], row["reference_verdict"] = mine, theirs
            bounds = (bound(t, metrics), bound(t, ref))
            row["margins"] = (None if None in (v, r) or None in bounds
                              else (abs(v - bounds[0]), abs(r - bounds[1])))
        rows.append(row)
    return rows


def slice_checks(m: dict, ref: dict, dev: float, tol: dict) -> list:
    def rel(key):
        return abs(m[key] - ref[key]) / abs(ref[key])

    checks = [("max_overlap_over_d", m["max_overlap_over_d"], tol["max_overlap_over_d"]),
              ("profile_rel_rms", dev, tol["profile_rel_rms"]),
              ("peak_drag_rel", rel("peak_drag_N_per_m"), tol["peak_drag_rel"]),
              ("peak_height_mm", abs(m["peak_height_mm"] - ref["peak_height_mm"]), tol["peak_height_mm"]),
              ("mean_drag_rel", rel("mean_drag_N_per_m"), tol["mean_drag_rel"])]
    return [bound_check(c, v, t) for c, v, t in checks]


def bound_check(name: str, value: float, tolerance: float) -> dict:
    return {"check": name, "value": value, "tolerance": tolerance, "ok": value <= tolerance,
            "normalised": value / tolerance}


def check_name(c: dict) -> str:
    return c.get("check") or c["metric"]


def noise_floor(slice_noise: list, target_noise: list) -> dict:
    """What two equivalent runs (a point and its replica) differ by, per check (None: a metric missing
    in one of them). The overlap checks bound the run itself, they compare nothing: no noise."""
    floor = {c["check"]: 0.0 if "overlap" in c["check"] else c["value"] for c in slice_noise}
    for c in target_noise:
        floor[c["metric"]] = None if c["deviation"] is None else abs(c["deviation"])
    return floor


def combined_floor(floors: list) -> dict:
    """One noise floor from several pairs of equivalent runs: per check the largest of their differences (each
    pair is one sample of it; None where any pair lacks the metric)."""
    out = {}
    for f in floors:
        for k, v in f.items():
            out[k] = None if v is None or (k in out and out[k] is None) else max(v, out.get(k, 0.0))
    return out


def judge(row: dict, floor: dict) -> None:
    """A miss counts only when it stands out of the noise: a deviation beyond max(tolerance, 2 x noise);
    a flipped verdict only when both values are more than 2 x noise from the bound. Sets each check's
    "significant" and the row's misses (counted), unresolved_misses (within the noise) and within_tolerance:
    True when every check is within its tolerance, False with a miss that counts, None (undetermined) when
    the only misses are within the noise: noise can leave a point undecided, never pass it."""
    checks = row["slice_checks"] + row.get("targets", [])
    for c in checks:
        noise = floor.get(check_name(c), 0.0)
        if c["ok"]:
            c["significant"] = False
        elif noise is None:  # the noise of a metric missing in a point or its replica is unknown
            c["significant"] = False
        elif "margins" in c:  # a bound: both sides clearly on their side of it
            c["significant"] = c["margins"] is None or min(c["margins"]) > 2.0 * noise
        else:
            deviation = c["value"] if "check" in c else c["deviation"]
            if deviation is None:  # a none against a number counts; an undetermined answer never does
                c["significant"] = c.get("decided", False)
            else:
                c["significant"] = abs(deviation) > max(c["tolerance"], 2.0 * noise)
        if c.get("normalised") is not None and noise is not None:
            c["normalised"] *= c["tolerance"] / max(c["tolerance"], 2.0 * noise)
    row["misses"] = [check_name(c) for c in checks if c["significant"]]
    row["unresolved_misses"] = [check_name(c) for c in checks if not c["ok"] and not c["significant"]]
    row["within_tolerance"] = False if row["misses"] else None if row["unresolved_misses"] else True
    # the worst comparison, over what it is allowed (the overlap, a bound, is shown on its own)
    normalised = [c["normalised"] for c in checks if c.get("normalised") is not None and "overlap" not in check_name(c)]
    row["worst_normalised_deviation"] = max(normalised) if normalised else None


def fmt(v, digits=3) -> str:
    if v is None:
        return "—"
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, int):
        return str(v)
    return f"{v:.{digits}g}"


def within(v) -> str:
    """A point's three-valued verdict: within every tolerance, not, or undetermined (misses within the noise)."""
    return "undetermined" if v is None else fmt(v)


def setting(p: dict) -> str:
    return {"reference": "paper law, dt = 1e-7 s", "default": "the base (preset fast)",
            "kn": f"k_n = {p.get('kn', 0):.3g} N/m", "dt": f"dt = dt_c x {p.get('dt_over_critical', 0):.3g}",
            "V": f"V = {p.get('V_mm_s', 0):g} mm/s",
            "replica": f"{p.get('replica_of')}, dt = dt_c x {p.get('dt_over_critical', 0):.3g}"}[p["knob"]]


def main() -> None:
    if len(sys.argv) != 3:
        fail("usage: python3 -m pipeline.accuracy.table data/accuracy.toml RESULTS_DIR")
    config_path, out = Path(sys.argv[1]), Path(sys.argv[2])
    config = read_toml(config_path)
    sweep, tol = config["sweep"], config["tolerance"]
    targets = read_toml(Path("data/paper_targets.toml"))["target"]
    points = config["point"]
    ref_slice = next((p for p in points if p["knob"] == "reference"), None)
    ref_full = next((p for p in points if p.get("full_reference")), None)
    if ref_slice is None or ref_full is None:
        fail(f"{config_path}: needs a point with knob = \"reference\" and one with full_reference = true")

    runs = {p["name"]: Run(out / "points" / p["name"]) for p in points}
    full = {p["name"]: read_json(out / "points" / p["name"] / "metrics.json", MAKE)
            for p in points if p["extent"] == "full"}
    full_travel = runs[ref_full["name"]].travel
    d_mm = runs[ref_slice["name"]].d_mean_mm
    window_mm, top_mm = sweep["smoothing_d"] * d_mm, sweep["slice_mm"]
    ref_run = runs[ref_slice["name"]]
    ref_slice_m = ref_run.slice_metrics(top_mm)

    rows = []
    for p in sorted(points, key=lambda p: KNOB_ORDER.index(p["knob"])):
        run = runs[p["name"]]
        sm = run.slice_metrics(top_mm)
        dev = profile_deviation(run, ref_run, top_mm, window_mm, sweep["profile_step_mm"])
        row = {"name": p["name"], "knob": p["knob"], "setting": setting(p), "extent": p["extent"],
               "time_step_s": run.dt, "steps": run.steps, "wall_seconds": run.wall,
               "full_wall_seconds": run.wall * (1.0 if p["extent"] == "full" else full_travel / run.travel),
               "full_wall_projected": p["extent"] != "full",
               "slice": sm, "profile_rel_rms": dev, "slice_checks": slice_checks(sm, ref_slice_m, dev, tol)}
        if p["extent"] == "full":
            m = full[p["name"]]
            row["run_max_overlap_over_d"] = float(run.overlap.max())
            row["slice_checks"].append(bound_check("run_max_overlap_over_d", row["run_max_overlap_over_d"],
                                                   tol["max_overlap_over_d"]))
            row["targets"] = compare_targets(targets, m, full[ref_full["name"]])
            row["profile_rel_rms_full"] = profile_deviation(run, runs[ref_full["name"]], full_travel - 1e-6,
                                                            window_mm, sweep["profile_step_mm"])
        rows.append(row)

    floors = {}
    for replica in (p for p in points if p["knob"] == "replica"):
        a, b = runs[replica["name"]], runs[replica["replica_of"]]
        slice_noise = slice_checks(a.slice_metrics(top_mm), b.slice_metrics(top_mm),
                                   profile_deviation(a, b, top_mm, window_mm, sweep["profile_step_mm"]), tol)
        target_noise = (compare_targets(targets, full[replica["name"]], full[replica["replica_of"]])
                        if replica["extent"] == "full" else [])
        floors[replica["replica_of"]] = noise_floor(slice_noise, target_noise)
    floor = combined_floor(list(floors.values()))
    for row in rows:
        judge(row, floor)

    cg_rows = cg_table(config, out, targets)
    cheapest, undecided = cheapest_points(rows)
    result = {"slice_mm": top_mm, "smoothing_mm": window_mm, "d_mean_mm": d_mm, "slice_reference": ref_slice["name"],
              "full_reference": ref_full["name"], "points": rows, "cg": cg_rows, "noise_floor": floor, "noise_floors": floors,
              "overlap_tolerance": tol["max_overlap_over_d"],
              "cheapest_within_tolerance": cheapest, "cheaper_undetermined": undecided}
    write_atomic(out / "table.json", json.dumps(result, indent=2) + "\n")
    write_atomic(out / "table.md", markdown(result, targets))
    pareto(result, out / "pareto.png")
    profiles(points, runs, result, out / "profiles.png")
    print(f"accuracy: {len(rows)} points, {len(cg_rows)} cg settings; cheapest within tolerance: "
          f"{result['cheapest_within_tolerance']} -> {out / 'table.md'}", file=sys.stderr)


def cg_ok(target: dict, metrics: dict, ref: dict):
    """A cg setting's metric against the reference grid's, as compare_targets judges it, or None where
    either run's answer is undetermined."""
    if answer(target, metrics) is None or answer(target, ref) is None:
        return None
    return compare_targets([target], metrics, ref)[0]["ok"]


def cheapest_points(rows: list):
    """The cheapest whole-run point within every tolerance (its name, or None), and the cheaper whole-run
    points that no miss rules out (undetermined, cheapest first): more replicas or members would decide them."""
    full = sorted((r for r in rows if r["extent"] == "full"), key=lambda r: r["full_wall_seconds"])
    cheapest = next((r for r in full if r["within_tolerance"] is True), None)
    cheaper = full if cheapest is None else full[:full.index(cheapest)]
    return (cheapest["name"] if cheapest else None), [r["name"] for r in cheaper if r["within_tolerance"] is None]


def cg_table(config: dict, out: Path, targets: list) -> list:
    settings = config.get("cg", [])
    if not settings:
        return []
    by_metric = {t["metric"]: t for t in targets}
    metrics = {c["name"]: read_json(out / "cg" / c["name"] / "metrics.json", MAKE) for c in settings}
    timing = {c["name"]: read_json(out / "cg" / c["name"] / "timing.json", MAKE) for c in settings}
    ref = next(c for c in settings if c.get("reference"))
    rows = []
    for c in settings:
        m, r = metrics[c["name"]], metrics[ref["name"]]
        row = {"name": c["name"], "spacing_mm": c["spacing_mm"], "w_over_d": c["w_over_d"],
               "reference": c is ref,
               "wall_seconds": timing[c["name"]]["wall_seconds"], "metrics": {}}
        for key in CG_METRICS:
            v, rv = dotted(m, key), dotted(r, key)
            t = by_metric.get(key, {})
            entry = {"value": v, "reference": rv, "deviation": None if v is None or rv is None else v - rv}
            entry["ok"] = cg_ok(t, m, r) if t else None
            if "tolerance" in t:
                entry["tolerance"] = t["tolerance"]
            row["metrics"][key] = entry
        oks = [e["ok"] for e in row["metrics"].values()]
        row["within_tolerance"] = False if False in oks else None if None in oks else True
        rows.append(row)
    return rows


def markdown(result: dict, targets: list) -> str:
    rows, floor = result["points"], result["noise_floor"]

    def noise(name: str) -> str:
        return fmt(floor[name]) if name in floor else "—"

    lines = ["# Accuracy and cost (make accuracy)", "",
             f"Slice: the first {result['slice_mm']:g} mm of travel, compared with point "
             f"`{result['slice_reference']}` (drag smoothed over {result['smoothing_mm']:.2f} mm). Whole runs: "
             f"every paper target's metric compared with point `{result['full_reference']}`, within the target's "
             "tolerance (bounds: same verdict). Wall time: the pull-off on one thread; for a slice, projected to "
             "the whole travel (marked ~).", "",
             "| point | setting | dt (s) | wall (s) | whole pull-off (s) | max overlap/d (slice) | peak drag (N/m) "
             "| peak at (mm) | mean drag (N/m) | profile dev. (slice) | profile dev. (run) | max overlap/d (run) "
             "| within tolerance | misses | misses within the noise |", "|" + "---|" * 15]
    for r in rows:
        s = r["slice"]
        whole = ("~" if r["full_wall_projected"] else "") + f"{r['full_wall_seconds']:.0f}"
        lines.append(f"| {r['name']} | {r['setting']} | {r['time_step_s']:.3g} | {r['wall_seconds']:.0f} | {whole} "
                     f"| {s['max_overlap_over_d']:.4f} | {s['peak_drag_N_per_m']:.0f} | {s['peak_height_mm']:.2f} "
                     f"| {s['mean_drag_N_per_m']:.1f} | {r['profile_rel_rms']:.3f} | {fmt(r.get('profile_rel_rms_full'))} "
                     f"| {fmt(r.get('run_max_overlap_over_d'), 3)} | {within(r['within_tolerance'])} "
                     f"| {', '.join(r['misses']) or '—'} | {', '.join(r['unresolved_misses']) or '—'} |")
    if floor:
        pairs = ", ".join(f"`{r['name']}` against `{r['setting'].split(',')[0]}`" for r in rows if r["knob"] == "replica")
        lines += ["", f"Noise floor of the slice comparison (the larger of {pairs}): " +
                  ", ".join(f"{k} {noise(k)}" for k in ["profile_rel_rms", "peak_drag_rel", "peak_height_mm",
                                                         "mean_drag_rel"]) + "."]
    full_rows = [r for r in rows if "targets" in r]
    if full_rows:
        lines += ["", "Whole-run metrics (value; deviation from the reference in brackets when it exceeds the "
                  "target's tolerance, or the verdict when a bound's verdict flips):", "",
                  "| metric | tolerance | noise (replicas) | " + " | ".join(r["name"] for r in full_rows) + " |",
                  "|---|---|---|" + "---|" * len(full_rows)]
        for i, t in enumerate(targets):
            cells = []
            for r in full_rows:
                c = r["targets"][i]
                cell = "none" if c.get("answer") == "none" else fmt(c["value"])
                if not c["ok"]:
                    what = fmt(c["deviation"]) if "tolerance" in c else "verdict flips"
                    cell += f" **({what})**" if c["significant"] else f" ({what}, within the noise)"
                cells.append(cell)
            tolerance = f"±{t['tolerance']:g}" if "tolerance" in t else "verdict"
            lines.append(f"| {t['metric']} ({t['result']}) | {tolerance} | {noise(t['metric'])} | " + " | ".join(cells) + " |")
    if result["cg"]:
        ref = next(c for c in result["cg"] if c["reference"])
        lines += ["", f"Coarse-graining grid and kernel width (the cg stage on point `default`'s pull-off, "
                  f"one thread; reference {ref['name']}):", "",
                  "| setting | spacing (mm) | w/d | w/Δx | cg wall (s) | " +
                  " | ".join(CG_METRICS) + " | within tolerance |", "|" + "---|" * (6 + len(CG_METRICS))]
        for c in result["cg"]:
            cells = [f"{fmt(e['value'])} ({fmt(e['deviation'], 2)})" for e in c["metrics"].values()]
            lines.append(f"| {c['name']} | {c['spacing_mm']:g} | {c['w_over_d']:g} | "
                         f"{c['w_over_d'] * result['d_mean_mm'] / c['spacing_mm']:.1f} | {c['wall_seconds']:.0f} | "
                         + " | ".join(cells) + f" | {within(c['within_tolerance'])} |")
    lines += ["", f"Cheapest whole-run point within every tolerance: **{result['cheapest_within_tolerance']}**."]
    if result["cheaper_undetermined"]:
        lines += ["Cheaper, undetermined (every miss within the noise): " +
                  ", ".join(f"`{n}`" for n in result["cheaper_undetermined"]) + "."]
    lines += [""]
    return "\n".join(lines)


def pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def save(fig, path: Path) -> None:
    tmp = path.with_suffix(".tmp.png")
    fig.savefig(tmp, dpi=120)
    tmp.replace(path)


def profiles(points: list, runs: dict, result: dict, path: Path) -> None:
    """The smoothed drag profiles: the slice for k_n and dt (with the reference), the whole run for V."""
    import numpy as np

    plt = pyplot()
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.2))
    window = result["smoothing_mm"]
    ref = next(p for p in points if p["knob"] == "reference")
    for ax, knob in zip(axes[:2], ["kn", "dt"]):
        for p in [ref] + [q for q in points if q["knob"] in (knob, "default")]:
            r = runs[p["name"]]
            grid = np.arange(r.height[0], r.height[0] + result["slice_mm"], 0.05)
            ax.plot(grid, r.smoothed(grid, window), lw=2.2 if p is ref else 1.1,
                    color="k" if p is ref else None, label=setting(p))
        ax.set_title(f"first {result['slice_mm']:g} mm: {'stiffness' if knob == 'kn' else 'time step'}")
    for p in [q for q in points if q["knob"] in ("V", "default")]:
        r = runs[p["name"]]
        grid = np.arange(r.height[0], r.height[-1], 0.25)
        axes[2].plot(grid, r.smoothed(grid, 3 * window), lw=1.1, label=setting(p))
    axes[2].set_title(f"whole pull-off, smoothed over {3 * window:.1f} mm: pull speed")
    for ax in axes:
        ax.set_xlabel("intruder height H (mm)")
        ax.set_ylabel("drag (N/m)")
        ax.legend(fontsize=7)
    fig.tight_layout()
    save(fig, path)


def pareto(result: dict, path: Path) -> None:
    """Error against cost: left, the worst deviation of the comparisons (overlap aside) over what it is
    allowed, max(tolerance, 2 x noise); right, the largest overlap. Filled: within every tolerance."""
    plt = pyplot()
    colours = {"reference": "k", "default": "tab:red", "replica": "tab:purple", "kn": "tab:blue", "dt": "tab:green",
               "V": "tab:orange"}
    fig, (left, right) = plt.subplots(1, 2, figsize=(13, 4.8))
    for r in result["points"]:
        x = r["full_wall_seconds"]
        overlap = max(c["value"] for c in r["slice_checks"] if "overlap" in c["check"])
        style = dict(c=colours[r["knob"]] if r["within_tolerance"] is True else "none", edgecolors=colours[r["knob"]],
                     marker="o" if r["extent"] == "full" else "^", s=45, zorder=3)
        worst = r["worst_normalised_deviation"] if r["knob"] != "reference" else None
        for ax, y in ((left, worst), (right, 100 * overlap)):
            if y is None:
                continue
            ax.scatter(x, max(y, 1e-3), **style)
            ax.annotate(r["name"], (x, max(y, 1e-3)), xytext=(4, 3), textcoords="offset points", fontsize=7)
    # the sweep's knobs; "default" is the sweep's base point (preset fast), not preset default
    names = {"reference": "reference (paper law)", "default": "base (preset fast)", "replica": "replica",
             "kn": "k_n varied", "dt": "dt varied", "V": "V varied"}
    for knob, c in colours.items():
        left.scatter([], [], c=c, label=names[knob])
    left.axhline(1.0, color="grey", ls="--", lw=1, label="tolerance")
    right.axhline(100 * result["overlap_tolerance"], color="grey", ls="--", lw=1, label="1 % of d")
    left.set_ylabel("worst deviation / max(tolerance, 2 x noise)")
    right.set_ylabel("largest overlap (% of d)")
    for ax in (left, right):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("whole pull-off on one thread (s; triangles: projected from the 10 mm slice)")
        ax.legend(fontsize=7)
    left.set_title("accuracy against cost (filled: within every tolerance)")
    right.set_title("overlap against cost")
    fig.tight_layout()
    save(fig, path)


if __name__ == "__main__":
    main()

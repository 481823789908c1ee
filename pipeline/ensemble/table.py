"""The ensemble's table of paper targets (docs/ensemble.md).

    python3 -m pipeline.ensemble.table ENSEMBLE_DIR

Reads ENSEMBLE_DIR/stats.json (pipeline/ensemble/aggregate.py) and
ENSEMBLE_DIR/check.json (check_paper_targets --ensemble) and writes
ENSEMBLE_DIR/table.md: for each paper target the members' values, their
mean, sd and 95 % t-interval of the mean, the paper's value, the verdict
(holds, fails, undetermined) and, when undetermined, the members that would decide.
"""
import sys
from pathlib import Path

from pipeline.files import check_rows, fail, read_json, write_atomic


def g(v) -> str:
    return "—" if v is None else f"{v:.4g}"


# the CG-versus-PIV comparison (stage piv) across the members: (label, metric path, unit)
PIV_ROWS = [("β by PIV", "piv.cone_angle_deg.piv.mean", "°"), ("β by CG, same nodes", "piv.cone_angle_deg.cg.mean", "°"),
            ("β, PIV − CG (paired)", "piv.cone_angle_deg.difference.mean", "°"),
            ("immobile zone, PIV − CG", "piv.zone_area_immobile_mm2.difference.mean", "mm²"),
            ("cone zone, PIV − CG", "piv.zone_area_cone_mm2.difference.mean", "mm²"),
            ("dragged zone, PIV − CG", "piv.zone_area_dragged_mm2.difference.mean", "mm²"),
            ("median \\|Δv*\\|", "piv.median_abs_vstar_difference", ""),
            ("rms Δ(\\|v − V\\|/V)", "piv.rms_vstar_difference_intruder_frame", ""),
            ("tip vortices by PIV (share of pairs)", "piv.vortices.piv.tip_rate", ""),
            ("tip vortices by CG (share of pairs)", "piv.vortices.cg.tip_rate", ""),
            ("β by the cg stage (its level, all nodes)", "cg.cone_angle_deg", "°")]


def piv_lines(metrics: dict) -> list:
    """The members' CG-versus-PIV comparison: each member's value (its mean over its frame pairs), the
    members' mean, sd and 95 % bootstrap interval of that mean; nothing when the members have no piv stage."""
    if not any(path.startswith("piv.") for path in metrics):
        return []
    rows = [(label, metrics[path], unit) for label, path, unit in PIV_ROWS if path in metrics]
    lines = ["", "## Synthetic PIV against coarse-graining, across the members", "",
             "Each member's value is its mean over its frame pairs (stage `piv`); the interval is the 95 % bootstrap "
             "interval of the members' mean (aggregate.py), which, unlike the pairs' interval within one run, counts "
             "the realisations as independent.", "",
             "| quantity | members | mean | sd | 95 % interval | unit |", "|---|---|---|---|---|---|"]
    for label, s, unit in rows:
        ci = s.get("ci95")
        lines.append(f"| {label} | {', '.join(g(v) for v in s.get('values', []))} | {g(s.get('mean'))} | "
                     f"{g(s.get('sd'))} | {f'[{g(ci[0])}, {g(ci[1])}]' if ci else '—'} | {unit} |")
    return lines


def main(argv: list) -> int:
    if len(argv) != 2:
        fail("usage: python3 -m pipeline.ensemble.table ENSEMBLE_DIR")
    d = Path(argv[1])
    stats = read_json(d / "stats.json", "make ensemble")
    check = read_json(d / "check.json", "make ensemble")
    tests = check_rows(check)
    n = len(stats["members"])
    count = {k: sum(t.get("verdict") == k for t in tests) for k in ("holds", "fails", "undetermined")}
    lines = [f"# Ensemble of {n} members, preset `{stats['preset']}`", "",
             f"Members: {', '.join(stats['members'])}; code: {', '.join(stats['code_versions'])}.",
             "Verdict on the members' 95 % Student-t interval of the mean: **holds** where the interval lies inside the "
             "paper's band (paper ± tolerance, or beyond a bound), **fails** where it lies wholly outside, "
             "**undetermined** where it straddles an edge: more members would decide, about as many as the last column "
             "says if the spread stays the same. A shape (ours above another metric) is judged on the members' "
             "differences. More noise can only make a verdict undetermined, never make it hold (docs/ensemble.md).", "",
             f"**{count['holds']} hold, {count['fails']} fail, {count['undetermined']} undetermined** "
             f"(of {len(tests)} targets).", "",
             "| result | metric | members | mean | sd | 95 % t-interval | paper | verdict | members to decide |",
             "|---|---|---|---|---|---|---|---|---|"]
    for t in tests:
        s = stats["metrics"].get(t.get("metric", ""), {})
        values = ", ".join(g(v) for v in s.get("values", []))
        interval = f"[{t['interval']}]" if t.get("interval") else "—"
        paper = t.get("paper", "")
        tol = t.get("tolerance", "")
        paper_cell = f"{paper} {tol.split(';')[0]}" if tol.startswith("±") else paper
        lines.append(f"| {t.get('result', '')} | `{t.get('metric', '')}` | {values} | {g(s.get('mean'))} | "
                     f"{g(s.get('sd'))} | {interval} | {paper_cell} | {t.get('verdict', '')} | "
                     f"{t.get('members_needed', '')} |")
    lines += piv_lines(stats["metrics"])
    write_atomic(d / "table.md", "\n".join(lines) + "\n")
    print(f"table: {count['holds']} hold, {count['fails']} fail, {count['undetermined']} undetermined of "
          f"{len(tests)} targets -> {d / 'table.md'}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

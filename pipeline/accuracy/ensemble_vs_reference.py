"""An ensemble (make ensemble) against the accuracy sweep's whole-run reference.

    python3 -m pipeline.accuracy.ensemble_vs_reference data/accuracy.toml RESULTS_DIR ENSEMBLE_DIR

The reference's members are the sweep's point with full_reference = true (the
paper's stiffness over the whole pull-off) and every replica naming it
(RESULTS_DIR/points/<name>/metrics.json); the ensemble's are summed up in
ENSEMBLE_DIR/metrics.json (the members' means) and judged in check.json
(check_paper_targets --ensemble: each target's verdict and the 95 %
t-interval of the members' mean, the interval the ensemble's own verdicts
use; stats.json's bootstrap interval only describes the members and is as
narrow as their range for a few of them). For every target of
data/paper_targets.toml:

- a target with a tolerance: the ensemble's mean against the reference
  members' mean r, whose noise is their spread s. It **agrees** when the
  ensemble's 95 % interval lies wholly within r +- (tolerance - s/2): the
  band narrows by the reference's own uncertainty, so a wider interval or
  a noisier reference can only make agreement harder. It **differs** when
  the means differ by more than both the tolerance and 2 s and the
  ensemble's 95 % interval lies wholly outside r +- the tolerance; else it
  is **undetermined**. Noise never turns a difference into agreement.
- a bound or a shape: the ensemble's own three-valued verdict
  (holds, fails or undetermined) against each reference member's verdict. It agrees when
  the ensemble's verdict is decided and every member's is the same; it
  differs when the members agree with each other and the ensemble decided
  the other way; else undetermined (a verdict missing, the members split,
  the ensemble undecided).

Writes RESULTS_DIR/ensemble_vs_reference.json and .md.
"""
import json
import sys
from pathlib import Path

from pipeline.accuracy.table import dotted, fmt, reference_members, verdict
from pipeline.files import check_rows, fail, read_json, read_toml, write_atomic

TARGETS = Path("data/paper_targets.toml")


def interval(judged):
    """The 95 % t-interval of a check.json row ("lo, hi"; {}: none), or None."""
    try:
        lo, hi = (float(x) for x in judged.get("interval", "").split(","))
    except ValueError:
        return None
    return [lo, hi] if lo <= hi else None


def compare(target: dict, refs: list, ensemble: dict, judged) -> dict:
    """One target: refs are the reference members' metrics, ensemble the ensemble's metrics.json (the means),
    judged its row of check.json (verdict, interval, members) or None (not judged)."""
    name, judged = target["metric"], judged or {}
    values = [dotted(m, name) for m in refs]
    known = [v for v in values if v is not None]
    row = {"metric": name, "result": target["result"], "reference_values": values,
           "reference_mean": sum(known) / len(known) if known else None,
           "reference_noise": max(known) - min(known) if len(known) == len(values) and len(known) > 1 else None,
           "ensemble_mean": dotted(ensemble, name), "ensemble_n": int(judged.get("members") or 0) or None,
           "ensemble_ci95": interval(judged)}
    if "above_metric" in target:  # the ensemble judges a shape on the members' differences: its interval is theirs
        row["ensemble_ci95_minus"] = target["above_metric"]
    ci = row["ensemble_ci95"]
    if "tolerance" in target:
        tol, r, e, noise = target["tolerance"], row["reference_mean"], row["ensemble_mean"], row["reference_noise"]
        row["tolerance"] = tol
        row["deviation"] = None if r is None or e is None else e - r
        if row["deviation"] is None or noise is None or ci is None:
            row["verdict"] = "undetermined"
        elif r - (tol - noise / 2) <= ci[0] and ci[1] <= r + (tol - noise / 2):
            row["verdict"] = "agrees"
        elif abs(row["deviation"]) > max(tol, 2.0 * noise) and (ci[0] > r + tol or ci[1] < r - tol):
            row["verdict"] = "differs"
        else:
            row["verdict"] = "undetermined"
        return row
    theirs = [verdict(target, m) for m in refs]
    row["ensemble_verdict"], row["reference_verdicts"] = judged.get("verdict"), theirs
    mine = {"holds": True, "fails": False}.get(row["ensemble_verdict"])
    if mine is not None and None not in theirs and len(set(theirs)) == 1:
        row["verdict"] = "agrees" if theirs[0] == mine else "differs"
    else:
        row["verdict"] = "undetermined"
    return row


def held(v) -> str:
    return "—" if v is None else "holds" if v else "fails"


def markdown(rows: list, names: list, ensemble_dir: Path) -> str:
    counts = {v: sum(r["verdict"] == v for r in rows) for v in ("agrees", "differs", "undetermined")}
    lines = [f"# {ensemble_dir} against the whole-run reference", "",
             f"Reference: {', '.join(f'`{n}`' for n in names)} (mean; noise = their spread). "
             f"{counts['agrees']} agree, {counts['differs']} differ, {counts['undetermined']} undetermined "
             "(pipeline/accuracy/ensemble_vs_reference.py says how each is decided).", "",
             "| metric (result) | reference members | ensemble mean [95 %] | deviation | tolerance | verdict |",
             "|---|---|---|---|---|---|"]
    for r in rows:
        refs = ", ".join(fmt(v) for v in r["reference_values"])
        ci = r["ensemble_ci95"]
        of = f"minus `{r['ensemble_ci95_minus']}`: " if "ensemble_ci95_minus" in r else ""
        ens = fmt(r["ensemble_mean"]) + (f" [{of}{fmt(ci[0])}, {fmt(ci[1])}]" if ci else "")
        if "tolerance" in r:
            dev, tol = fmt(r["deviation"]), f"±{r['tolerance']:g}"
        else:
            dev = f"{r['ensemble_verdict'] or '—'} vs {', '.join(held(v) for v in r['reference_verdicts'])}"
            tol = "verdict"
        lines.append(f"| {r['metric']} ({r['result']}) | {refs} | {ens} | {dev} | {tol} | {r['verdict']} |")
    return "\n".join(lines) + "\n"


def main() -> None:
    if len(sys.argv) != 4:
        fail("usage: python3 -m pipeline.accuracy.ensemble_vs_reference data/accuracy.toml RESULTS_DIR ENSEMBLE_DIR")
    config_path, out, ensemble_dir = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
    names = reference_members(read_toml(config_path).get("point", []))
    if not names:
        fail(f"{config_path}: no point with full_reference = true")
    refs = [read_json(out / "points" / n / "metrics.json", f"make {out}/points/{n}/metrics.json") for n in names]
    # results/<preset>/ensemble: made by make ensemble PRESET=<preset>
    make = f"make ensemble PRESET={ensemble_dir.parent.name}"
    ensemble = read_json(ensemble_dir / "metrics.json", make)
    judged = {t.get("metric"): t for t in check_rows(read_json(ensemble_dir / "check.json", make))}
    rows = [compare(t, refs, ensemble, judged.get(t["metric"])) for t in read_toml(TARGETS)["target"]]
    result = {"reference": names, "ensemble": str(ensemble_dir), "targets": rows}
    write_atomic(out / "ensemble_vs_reference.json", json.dumps(result, indent=2) + "\n")
    write_atomic(out / "ensemble_vs_reference.md", markdown(rows, names, ensemble_dir))
    print(f"ensemble_vs_reference: {ensemble_dir} against {', '.join(names)} -> {out / 'ensemble_vs_reference.md'}",
          file=sys.stderr)


if __name__ == "__main__":
    main()

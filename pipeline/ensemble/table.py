#!/usr/bin/python3
"""The ensemble's table of paper targets (docs/ensemble.md).

    python3 pipeline/ensemble/table.py ENSEMBLE_DIR

Reads ENSEMBLE_DIR/stats.json (pipeline/ensemble/aggregate.py) and
ENSEMBLE_DIR/check.json (check_paper_targets --ensemble) and writes
ENSEMBLE_DIR/table.md: for each paper target the members' values, their
mean, sd and 95 % interval of the mean, the paper's value and the verdict.
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "report"))
from files import check_rows, fail, read_json, write_atomic  # noqa: E402


def g(v) -> str:
    return "—" if v is None else f"{v:.4g}"


def main(argv: list) -> int:
    if len(argv) != 2:
        fail("usage: table.py ENSEMBLE_DIR")
    d = Path(argv[1])
    stats = read_json(d / "stats.json", "make ensemble")
    check = read_json(d / "check.json", "make ensemble")
    tests = check_rows(check)
    n = len(stats["members"])
    passed = sum(t.get("verdict") == "pass" for t in tests)
    lines = [f"# Ensemble of {n} members, preset `{stats['preset']}`", "",
             f"Members: {', '.join(stats['members'])}; code: {', '.join(stats['code_versions'])}.",
             "Interval: 95 % bootstrap interval of the members' mean "
             f"({stats['bootstrap']['resamples']} resamples). Verdict: a paper value ± tolerance passes when it lies "
             "within that interval widened by the tolerance; a bound is judged on the mean (docs/ensemble.md).", "",
             f"**{passed} of {len(tests)} targets pass.**", "",
             "| result | metric | members | mean | sd | 95 % interval | paper | verdict |",
             "|---|---|---|---|---|---|---|---|"]
    for t in tests:
        s = stats["metrics"].get(t.get("metric", ""), {})
        values = ", ".join(g(v) for v in s.get("values", []))
        ci = s.get("ci95")
        interval = f"[{g(ci[0])}, {g(ci[1])}]" if ci else "—"
        paper = t.get("paper", "")
        tol = t.get("tolerance", "")
        paper_cell = f"{paper} {tol.split(' around')[0]}" if tol.startswith("±") else paper
        lines.append(f"| {t.get('result', '')} | `{t.get('metric', '')}` | {values} | {g(s.get('mean'))} | "
                     f"{g(s.get('sd'))} | {interval} | {paper_cell} | {t.get('verdict', '')} |")
    write_atomic(d / "table.md", "\n".join(lines) + "\n")
    print(f"table: {passed}/{len(tests)} targets pass -> {d / 'table.md'}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

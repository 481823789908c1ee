"""make validate: validation cases with analytic or established references.

Usage: validate.py DEM2D OUT_DIR [--config data/validate.toml] [--quick] [--jobs N]

Each case runs scenes with dem2d (one thread each, N cases side by side) and
compares what it measures with its reference: every check prints expected,
measured, tolerance and pass/fail. Writes OUT_DIR/table.md, table.json and
figures (plots.py). Exit status 0 if every check passes, 1 otherwise, 2 on
bad input. --quick runs the cases listed in [quick] of the config (make test)."""
import argparse
import json
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

from pipeline.files import fail, read_toml, write_atomic
from pipeline.validate import bulk, detectors, impacts, numerics, plots, single, stress
from pipeline.validate.checks import Check

# name -> (title, the functions that run it): one registry for the driver,
# the table and the quick subset
CASES = {
    "impacts_normal": ("Chung & Ooi 1-3: normal impacts", [impacts.normal]),
    "impacts_oblique": ("Chung & Ooi 4-8: oblique impacts with spin", [impacts.oblique_wall, impacts.oblique_pair]),
    "single": ("single grains and a pile at rest", [single.slide_to_roll, single.incline, single.static_pile, stress.pile]),
    "numerics_gas": ("integrator: energy error order, ledger closure", [numerics.elastic_gas]),
    "numerics_stability": ("integrator: dense-packing stability limit", [numerics.stability_limit]),
    "janssen": ("bulk: Janssen saturation in a 2D silo, and its stress", [bulk.janssen, stress.janssen]),
    "beverloo": ("bulk: Beverloo's 2D discharge law", [bulk.beverloo]),
    "repose": ("bulk: angle of repose against mu and mu_r", [bulk.repose]),
    "detectors": ("planted truth: the analyses' detectors", [detectors.planted]),
}


@dataclass
class Context:
    dem2d: str
    out: Path
    config: dict
    quick: bool = False
    figures: dict = field(default_factory=dict)


def run_case(name: str, dem2d: str, out: str, config: dict, quick: bool):
    ctx = Context(dem2d, Path(out), config, quick)
    t0 = time.time()
    checks = []
    for fn in CASES[name][1]:
        try:
            checks += fn(ctx)
        except Exception as e:  # a case that cannot run fails, with the reason; the others go on
            checks.append(Check(CASES[name][0], f"{fn.__name__} ran", 1.0, float("nan"), 0.0, kind="abs",
                                reference=f"{type(e).__name__}: {str(e)[-300:]}"))
    return name, [c.row() for c in checks], ctx.figures, time.time() - t0


def table_md(rows: list, seconds: dict, planted: list, planted_noise: list) -> str:
    out = ["| case | quantity | expected | measured | tolerance | pass | reference |", "|---|---|---|---|---|---|---|"]
    for r in rows:
        if r["case"].startswith("planted: "):  # in their own section below
            continue
        unit = f" {r['unit']}" if r["unit"] else ""
        out.append(f"| {r['case']} | {r['quantity']} | {r['expected']:.6g}{unit} | {r['measured']:.6g}{unit} | "
                   f"{TOLERANCE[r['kind']](r['tolerance'])} | {'pass' if r['passed'] else '**FAIL**'} | {r['reference']} |")
    passed = sum(r["passed"] for r in rows)
    out += ["", f"{passed} of {len(rows)} checks pass. Wall time per case: " +
            ", ".join(f"{k} {v:.0f} s" for k, v in seconds.items()) + "."]
    return "\n".join(out) + "\n" + (detectors.section(planted, planted_noise) if planted else "")


TOLERANCE = {"rel": lambda t: f"±{100 * t:.3g} %", "abs": lambda t: f"±{t:.3g}", "below": lambda t: "at most",
             "above": lambda t: "at least"}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dem2d")
    ap.add_argument("out", type=Path)
    ap.add_argument("--config", type=Path, default=Path(__file__).resolve().parents[2] / "data" / "validate.toml")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--cases", nargs="*", help="run only these cases")
    a = ap.parse_args()
    config = read_toml(a.config)
    names = a.cases or (config["quick"]["cases"] if a.quick else list(CASES))
    unknown = [n for n in names if n not in CASES]
    if unknown:
        fail(f"{a.config}: unknown validation case(s) {unknown} (known: {', '.join(CASES)})")
    a.out.mkdir(parents=True, exist_ok=True)
    results = {}
    with ProcessPoolExecutor(max_workers=a.jobs) as pool:
        futures = [pool.submit(run_case, n, a.dem2d, str(a.out), config, a.quick) for n in names]
        for f in futures:
            name, rows, figures, seconds = f.result()
            results[name] = {"title": CASES[name][0], "checks": rows, "figures": figures, "seconds": seconds}
            bad = [r for r in rows if not r["passed"]]
            print(f"validate: {name}: {len(rows) - len(bad)}/{len(rows)} pass ({seconds:.0f} s)", flush=True)
            for r in bad:
                print(f"  FAIL {r['case']}: {r['quantity']}: expected {r['expected']:.6g}, measured {r['measured']:.6g} "
                      f"({TOLERANCE[r['kind']](r['tolerance'])})", flush=True)
    rows = [r for n in names for r in results[n]["checks"]]
    write_atomic(a.out / "table.json", json.dumps(results, indent=1, default=float) + "\n")
    figures = plots.figure_data(results)
    write_atomic(a.out / "table.md", table_md(rows, {n: results[n]["seconds"] for n in names},
                                              figures.get("planted", []), figures.get("planted_noise", [])))
    plots.draw(results, a.out)
    passed = sum(r["passed"] for r in rows)
    print(f"validate: {passed}/{len(rows)} checks pass -> {a.out / 'table.md'}")
    sys.exit(0 if passed == len(rows) else 1)


if __name__ == "__main__":
    main()

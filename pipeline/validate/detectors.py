"""make validate's planted-truth section: every detector of the analysis
stages run, unchanged, on synthetic input with a known answer
(tests/planted/, the program planted_truth; cases and tolerances in its code,
what is swept in data/planted.toml). Each judged case gives two checks: the
bias of the recovered value against the planted one (or, where nothing is
planted, how often something is found) and how often the detector finds it;
cases shown for comparison (the definitions before this suite) are listed,
not judged. The noise levels are set against what the study's own runs
measure (results/<preset>/metrics.json, when present)."""
import json
import math
import subprocess
from pathlib import Path

from pipeline.validate.checks import Check

ROOT = Path(__file__).resolve().parents[2]


def program(dem2d: str) -> Path:
    """planted_truth of the build tree that holds dem2d (build/<tree>/sim/dem2d)."""
    return Path(dem2d).resolve().parents[1] / "tests" / "planted" / "planted_truth"


def checks_of(rows: list) -> list:
    out = []
    for r in rows:
        if not r["judged"]:
            continue
        case = f"planted: {r['detector']}: {r['case']} (noise {r['noise']:g} {r['noise_unit']})"
        found = r["found"] / r["replicas"]
        ref = f"{r['replicas']} replicas"
        if r["planted"] is None:
            out.append(Check(case, "fraction of replicas finding something (nothing planted)", r["max_false"], found,
                             0.0, kind="below", reference=ref))
        else:
            if r["mean"] is not None or r["min_found"] > 0:  # where found, it must be right
                measured = r["mean"] if r["mean"] is not None else math.nan
                out.append(Check(case, f"{r['quantity']}: mean over the replicas", r["planted"], measured,
                                 r["tolerance"], unit=r["unit"] if r["unit"] != "-" else "", kind="abs",
                                 reference=f"{ref}, sd {r['sd'] if r['sd'] is not None else math.nan:.3g}"))
            if r["min_found"] > 0:
                out.append(Check(case, "fraction of replicas finding it", r["min_found"], found, 0.0, kind="above",
                                 reference=ref))
            if r.get("min_coverage", 0) > 0 and r.get("intervals", 0) > 0:
                out.append(Check(case, "fraction of the intervals holding the planted value", r["min_coverage"],
                                 r["covered"] / r["intervals"], 0.0, kind="above",
                                 reference=f"{r['intervals']} intervals"))
    return out


def study_noise() -> list:
    """The noise the study's runs measure, for the section's header (presets with results)."""
    lines = []
    for preset in ("default", "fast"):
        for folder in (ROOT / "results" / preset, ROOT / "results" / preset / "ensemble"):
            path = folder / "metrics.json"
            if not path.exists():
                continue
            m = json.loads(path.read_text())
            drag = m.get("spectrum", {}).get("noise_level_N_per_m")
            piv = m.get("cg", {}).get("piv_noise", {}).get("grain_rms_over_v")
            if drag is not None or piv is not None:
                what = "ensemble mean" if folder.name == "ensemble" else "single run"
                lines.append(f"preset {preset} ({what}, {path.relative_to(ROOT)}): drag noise "
                             f"{drag if drag is None else f'{drag:.3g}'} N/m, PIV noise per grain "
                             f"{piv if piv is None else f'{piv:.3g}'} x V")
    return lines


def planted(ctx) -> list:
    exe = program(ctx.dem2d)
    if not exe.exists():
        raise FileNotFoundError(f"{exe}: build the tree first (make build)")
    out = ctx.out / "planted.json"
    cmd = [str(exe), "--data", str(ROOT / "data"), "--json", str(out)]
    if ctx.quick:
        cmd.append("--quick")
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode == 2 or not out.exists():
        raise RuntimeError(f"{' '.join(cmd)}: exit {r.returncode}: {r.stderr.strip()[-300:]}")
    data = json.loads(out.read_text())
    ctx.figures["planted"] = data["rows"]
    ctx.figures["planted_noise"] = study_noise()
    return checks_of(data["rows"])


def section(rows: list, noise: list) -> str:
    """table.md's planted-truth section: one line per case, judged or shown for comparison."""
    def g(v, f=".3g"):
        return "none" if v is None else format(v, f)
    out = ["", "## Planted truth: the analyses' detectors", "",
           "Each detector run, unchanged, on synthetic input with a known answer (tests/planted/; "
           "data/planted.toml). Recovered: mean ± sd over the replicas that found something; found: replicas "
           "that found something. Cases with nothing planted must find nothing (at most the stated fraction); "
           "rows marked *for comparison* are the definitions used before, not judged; rows marked *limit* are "
           "families where the detector is known to fall short, shown with the reason, not judged."]
    if noise:
        out += ["", "Noise the study's runs measure: " + "; ".join(noise) + "."]
    out += ["", "Covered: of the replicas that found it and gave an interval, how many intervals hold the planted "
            "value (their nominal confidence is 95 %).",
            "", "| detector | case | noise | planted | recovered | bias | found | covered | tolerance | verdict |",
            "|---|---|---|---|---|---|---|---|---|---|"]
    notes = {}
    for r in rows:
        unit = f" {r['unit']}" if r["unit"] not in ("", "-") else ""
        recovered = "—" if r["mean"] is None else f"{g(r['mean'], '.4g')} ± {g(r['sd'], '.2g')}{unit}"
        tol = (f"at most {r['max_false']:.0%} find" if r["planted"] is None else
               f"±{r['tolerance']:g}{unit}" + (f", {r['min_found']:.0%} find" if r["min_found"] > 0 else "")
               + (f", {r['min_coverage']:.0%} covered" if r.get("min_coverage", 0) > 0 else ""))
        covered = f"{r['covered']}/{r['intervals']}" if r.get("intervals") else "—"
        verdict = ("*limit*" if r.get("limit") else "*for comparison*") if not r["judged"] else \
            ("pass" if r["pass"] else "**FAIL**")
        case = r["case"] + (f" [{notes.setdefault(r['note'], len(notes) + 1)}]" if r.get("note") else "") + \
            (f" [{notes.setdefault('limit: ' + r['limit'], len(notes) + 1)}]" if r.get("limit") else "")
        out.append(f"| {r['detector']} | {case} | {r['noise']:g} {r['noise_unit']} | "
                   f"{'none' if r['planted'] is None else g(r['planted'], '.4g') + unit} | {recovered} | "
                   f"{'—' if r['bias'] is None else g(r['bias'], '+.3g')} | {r['found']}/{r['replicas']} | {covered} | {tol} | "
                   f"{verdict} |")
    out += [""] + [f"[{k}] {note}" + ("" if note.endswith(".") else ".") + "  " for note, k in notes.items()]
    return "\n".join(out) + "\n"

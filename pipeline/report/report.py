"""Writes the reproduction report of one preset's results.

    /usr/bin/python3 -m pipeline.report.report RESULTS_DIR PRESET

Reads RESULTS_DIR/metrics.json (merge_metrics.py), RESULTS_DIR/check.json
(the tolerance tests' GoogleTest JSON output: one test per paper target, with
our value, the paper's and the verdict as properties), RESULTS_DIR/figures/
index.json (figures.py) and pipeline/report/deviations.toml; writes
RESULTS_DIR/report.md.
"""
import base64
import re
import sys
from pathlib import Path

import markdown

from pipeline.files import check_rows, fail, read_json, read_toml, stages, write_atomic

HERE = Path(__file__).resolve().parent


def targets_table(check: dict) -> tuple[list[str], list[dict]]:
    rows = check_rows(check)
    if not rows:
        fail("check.json lists no targets: rerun `make reproduce`")
    lines = ["| result | metric | what | paper | tolerance | ours | verdict |", "|---|---|---|---|---|---|---|"]
    for t in rows:
        verdict = {"pass": "pass", "undetermined": "undetermined"}.get(t.get("verdict"), "**FAIL**")
        lines.append(f"| {t.get('result', t['classname'])} | `{t.get('metric', t['name'])}` | {t.get('what', '')} "
                     f"| {t.get('paper', '')} | {t.get('tolerance', '')} | {t.get('ours', 'missing')} | {verdict} |")
    return lines, rows


# {stage.key} or {stage.key.sub:format} in a reason of deviations.toml (deviation or miss)
PLACEHOLDER = re.compile(r"\{([A-Za-z_]\w*(?:\.\w+)+)(?::([^{}]*))?\}")


def fill_in(text: str, metrics: dict, where: str) -> str:
    """Replaces each placeholder in `text` by that value of metrics.json, formatted
    (None, a metric the run could not measure, as "—"): a reason quotes the
    numbers of the run it explains, never another run's."""
    def value(m: re.Match) -> str:
        v = metrics
        for key in m.group(1).split("."):
            if not isinstance(v, dict) or key not in v:
                fail(f"{where}: '{m.group(0)}' names no value of metrics.json")
            v = v[key]
        if v is None:
            return "—"
        try:
            return format(v, m.group(2) or "")
        except (TypeError, ValueError) as e:
            fail(f"{where}: '{m.group(0)}': cannot format {v!r} ({e})")
    return PLACEHOLDER.sub(value, text)


# A miss that deviations.toml does not explain: said plainly, never dressed up as a reason.
NO_REASON = ("no reason is known: this miss has not been examined (no entry of pipeline/report/deviations.toml "
             "explains it)")


def deviations(preset: str, failed: list[dict], metrics: dict) -> list[str]:
    path = HERE / "deviations.toml"
    d = read_toml(path)
    lines = ["### Method", "", "| what | paper | ours | why |", "|---|---|---|---|"]
    for dev in d.get("deviation", []):
        if preset in dev["presets"]:
            why = fill_in(dev["reason"], metrics, f"{path}, deviation '{dev['what']}'")
            lines.append(f"| {dev['what']} | {dev['paper']} | {dev['ours']} | {why} |")
    lines += ["", "### Results outside the paper's tolerance, or undetermined", ""]
    reasons = {m["metric"]: m["reason"] for m in d.get("miss", [])}
    if not failed:
        lines.append("None: every target passes.")
    for t in failed:
        metric = t.get("metric", t["name"])
        why = fill_in(reasons[metric], metrics, f"{path}, miss '{metric}'") if metric in reasons else NO_REASON
        verdict = " (undetermined: nothing found by a test too weak to call it absent, or no value the detector could stand by)" if t.get("verdict") == "undetermined" else ""
        lines.append(f"- **{t.get('result', '')} `{metric}`** = {t.get('ours', 'missing')}{verdict} (paper {t.get('paper', '')} {t.get('tolerance', '')}; "
                     f"source: {t.get('source', '')}; why this tolerance: {t.get('why', '')}). Why we miss: {why}.")
    return lines


def cost_table(cost: dict) -> list[str]:
    lines = ["| stage | wall time (s) | steps | particle-steps/s | ns per particle-step | threads |",
             "|---|---|---|---|---|---|"]
    for stage, c in cost.items():
        if not isinstance(c, dict):
            continue
        if "steps" in c:
            sim = [str(c["steps"]), f"{c['particle_steps_per_second']:.3g}", f"{c['ns_per_particle_step']:.1f}",
                   str(c["threads"])]
        else:
            sim = ["", "", "", ""]
        lines.append(f"| {stage} | {c['wall_seconds']:.1f} | " + " | ".join(sim) + " |")
    lines.append(f"| **total** | {cost['total_wall_seconds']:.1f} | | | | |")
    return lines


def figures(index: list[dict]) -> list[str]:
    lines = []
    for fig in index:
        lines += [f"### {fig.get('figure', '')}: {fig['title']}", "", f"![{fig['title']}](figures/{fig['file']})", "",
                  fig["caption"], ""]
    return lines


# unit suffixes of metric names, as a reader writes them
UNITS = [("_hz_at_1p2mm_s", " (Hz at 1.2 mm/s)"), ("_N_per_m", " (N/m)"), ("_mm_s", " (mm/s)"), ("_mm", " (mm)"),
         ("_deg", " (°)"), ("_hz", " (Hz)"), ("_d", " (d)"), ("_s", " (s)"), ("_N", " (N)")]


def human(key: str) -> str:
    """A metric or setting name for people: 'rupture_spacing_d' -> 'rupture spacing (d)'."""
    for suffix, unit in UNITS:
        if key.endswith(suffix) and len(key) > len(suffix):
            return key[: -len(suffix)].replace("_", " ").replace("mu star", "μ*") + unit
    return key.replace("_", " ").replace("mu star", "μ*").replace("r2", "R²")


def sensitivity(metrics: dict) -> list[str]:
    """Each stage's tables of how its numbers move with its thresholds: the threshold's values down
    the first column, then only the numbers that move; those that stay put are named below the table.
    Each folded (a <details> block, one click away), so that they do not make most of the page."""
    lines = []
    for stage in (s.name for s in stages()):
        for name, rows in metrics.get(stage, {}).get("sensitivity", {}).items():
            if not isinstance(rows, list) or not rows or not isinstance(rows[0], dict):
                continue
            keys = [k for k in rows[0] if not isinstance(rows[0][k], (dict, list))]
            first, rest = keys[0], keys[1:]
            moving = [k for k in rest if len({fmt(r.get(k)) for r in rows}) > 1]
            still = [k for k in rest if k not in moving]
            header = [human(name) if first == "value" else human(first)] + [human(k) for k in moving]
            lines += ['<details markdown="1">', f'<summary markdown="span">{stage}: {human(name)}</summary>', "",
                      "| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
            for r in rows:
                lines.append("| " + " | ".join(fmt(r.get(k)) for k in [first] + moving) + " |")
            if still:
                lines += ["", "Unchanged over these values: " +
                          "; ".join(f"{human(k)} {fmt(rows[0].get(k))}" for k in still) + "."]
            lines += ["", "</details>", ""]
    return lines


def detectors_section(metrics: dict) -> list[str]:
    """The detectors' own evidence: the rupture rule and the spacing by size, the size distribution's fits,
    the top layer's change point and its interval, the wall mobility's and the percolation loss's tests,
    the noise measured at rest."""
    sp, cg, net = metrics.get("spectrum", {}), metrics.get("cg", {}), metrics.get("network", {})
    lines = []
    if sp:
        lines += [f"**Ruptures (R3).** {sp.get('rupture_rule', '')}: {fmt(sp.get('rupture_count'))} of "
                  f"{fmt(sp.get('event_count'))} events (drops above the drop threshold times the local noise: "
                  f"{fmt(sp.get('drop_delta_N_per_m'))} N/m at the median noise). "
                  f"Median spacing of the ruptures {fmt(sp.get('rupture_spacing_d'))} d; of every event "
                  f"{fmt(sp.get('event_spacing_d'))} d. The spacing against the size threshold:", "",
                  "| kept events | threshold | events | median spacing (d) | mean spacing (d) |", "|---|---|---|---|---|"]
        by = sp.get("spacing_by_threshold", {})
        for kind, label in (("relative_drop", "drop ≥ threshold × load"), ("drop_over_noise", "drop ≥ threshold × σ")):
            for r in by.get(kind, []):
                lines.append(f"| {label} | {fmt(r.get('threshold'))} | {fmt(r.get('events'))} | "
                             f"{fmt(r.get('median_spacing_d'))} | {fmt(r.get('mean_spacing_d'))} |")
        sizes = sp.get("size_distribution", {}).get("drop_N_per_m", {})
        if sizes.get("fitted"):
            ratios = "; ".join(f"{c['a']} vs {c['b']}: R = {c['ratio']:.3g}, p = {c['p']:.2g} ({c['favoured']})"
                               for c in sizes.get("likelihood_ratios", []))
            lines += ["", f"**Drop sizes** ({sizes['sizes']} events in the loading/rupture part; Clauset, Shalizi & "
                      f"Newman 2009): power law above x_min = {sizes['x_min']:.3g} N/m ({sizes['tail']} drops) with "
                      f"α = {sizes['power_law']['alpha']:.3g} (goodness of fit p = {fmt(sizes['power_law'].get('p_value'))}), "
                      f"lognormal μ = {sizes['lognormal']['mu']:.3g}, σ = {sizes['lognormal']['sigma']:.3g}, exponential "
                      f"λ = {sizes['exponential']['lambda']:.3g} per N/m; likelihood ratios: {ratios}. Best: "
                      f"**{sizes['best']}**."]
        top = sp.get("top_layer", {})
        if top:
            lines += ["", f"**Top layer (R4).** Change point of the fluctuations' variance: {top.get('outcome')} "
                      f"(p = {fmt(top.get('p_value'))}, model {top.get('model')}); H_top = {fmt(top.get('height_mm'))} mm, "
                      f"95 % interval {fmt((top.get('interval_mm') or [None])[0])}–"
                      f"{fmt((top.get('interval_mm') or [None, None])[1])} mm. The envelope's definition (before): "
                      f"{fmt(sp.get('top_layer_envelope_height_mm'))} mm."]
    if cg:
        noise = cg.get("piv_noise", {})
        lines += ["", f"**Wall mobility (R6).** {cg.get('wall_mobility_outcome', '')} (p = "
                  f"{fmt(cg.get('wall_mobility_loss_p_value'))}): H_c = {fmt(cg.get('wall_mobility_length_mm'))} mm at "
                  f"levels {fmt((cg.get('wall_mobility_level_range') or [None])[0])}–"
                  f"{fmt((cg.get('wall_mobility_level_range') or [None, None])[1])}; at the fixed level 0.25 (before): "
                  f"{fmt(cg.get('wall_mobility_length_fixed_level_mm'))} mm. Cone level {fmt(cg.get('cone_level'))}. "
                  f"PIV noise at rest: {fmt(noise.get('grain_rms_over_v'))} V per grain and component; v* of single "
                  f"nodes: median {fmt(noise.get('node_vstar_median'))}, 99.9 % {fmt(noise.get('node_vstar_q999'))}."]
    if net.get("percolation_loss_outcome"):
        lines += ["", f"**Percolation loss (R4).** {net['percolation_loss_outcome']} (p = "
                  f"{fmt(net.get('percolation_loss_p_value'))}): {fmt(net.get('percolation_loss_height_mm'))} mm; "
                  f"the height rule alone: {fmt(net.get('percolation_loss_rule_height_mm'))} mm."]
    return lines


def piv_section(metrics: dict) -> list[str]:
    """The paper's comparison: synthetic PIV of the rendered front face against coarse-graining on the same
    nodes, with the cg stage's own numbers beside (piv stage; analysis/piv/README.md)."""
    piv = metrics.get("piv")
    if not piv:
        return []

    def row(label, key, scale_unit):
        c = piv[key]
        cells = []
        for side in ("piv", "cg", "difference"):
            lo, hi = (c[side].get("interval") or [None, None])
            cells.append(f"{fmt(c[side].get('mean'))} [{fmt(lo)}, {fmt(hi)}] ({fmt(c[side].get('snapshots'))})")
        return f"| {label} ({scale_unit}) | " + " | ".join(cells) + " |"

    cgs = piv.get("cg_stage", {})
    v = piv["vortices"]
    lines = [f"{piv['pairs']} frame pairs, {fmt(piv['frame_interval_s'] * 1e3)} ms apart, rendered at "
             f"{fmt(piv['px_per_diameter'])} px a bead and read by PIV (a vector every {fmt(piv['vector_spacing_d'])} d); "
             f"the coarse-grained field of the same grains' displacements on the same nodes. Means over the pairs "
             f"with a value, 95 % t-intervals (pairs of one run are not independent: lower bounds), the number of "
             f"pairs; difference: PIV − CG paired by pair.", "",
             "| | synthetic PIV | coarse-grained, same nodes | difference |", "|---|---|---|---|",
             row("cone angle β", "cone_angle_deg", "°"),
             row("immobile zone", "zone_area_immobile_mm2", "mm²"),
             row("cone zone", "zone_area_cone_mm2", "mm²"),
             row("dragged zone", "zone_area_dragged_mm2", "mm²"), "",
             f"The v* maps differ by {fmt(piv['median_abs_vstar_difference'])} at the median node and "
             f"{fmt(piv['rms_vstar_difference'])} rms (|v − V|/V in the intruder's frame: "
             f"{fmt(piv['rms_vstar_difference_intruder_frame'])} rms). The cg stage on all its nodes, at its "
             f"noise-calibrated level: β = {fmt(cgs.get('cone_angle_deg'))}°, H_c = "
             f"{fmt(cgs.get('wall_mobility_length_mm'))} mm. H_c is not read from PIV: its region of interest leaves "
             f"the walls out, as the paper's, and the camera sees "
             f"{fmt(piv.get('wall_mobility', {}).get('view_above_intruder_mm'))} mm above the intruder, where a cone at "
             f"the PIV's β meets the walls {fmt(piv.get('wall_mobility', {}).get('cone_meets_walls_above_intruder_mm'))} "
             f"mm above it.", "",
             f"**Vortices near the tips (R12)**, swirl strength λ_ci where the rotation dominates, against discs in "
             f"the bed at rest: PIV {v['piv']['verdict']} (a vortex at a tip in {fmt(v['piv'].get('tip_rate'))} of "
             f"the pairs, at rest {fmt(v['piv'].get('control_rate'))}); CG {v['cg']['verdict']} "
             f"({fmt(v['cg'].get('tip_rate'))}, at rest {fmt(v['cg'].get('control_rate'))}). Larger vortices "
             f"(30 nodes above the threshold): PIV "
             f"{fmt(next((r['tip_rate'] for r in v['piv'].get('sensitivity', []) if r['rest_quantile'] == 0.999 and r['min_nodes'] == 30), None))}, "
             f"CG {fmt(next((r['tip_rate'] for r in v['cg'].get('sensitivity', []) if r['rest_quantile'] == 0.999 and r['min_nodes'] == 30), None))} "
             f"of the pairs (piv/metrics.json: vortices.*.sensitivity)."]
    return lines


def fmt(v) -> str:
    if v is None:
        return "—"
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, float):
        return f"{v:.3g}"
    return str(v)


def html_page(markdown_text: str, results: Path, preset: str) -> str:
    """report.md as one self-contained HTML page: the figures embedded (base64 PNG), nothing to fetch."""
    body = markdown.markdown(markdown_text, extensions=["tables", "md_in_html"])

    def embed(m):
        png = results / m.group(1)
        return 'src="data:image/png;base64,' + base64.b64encode(png.read_bytes()).decode("ascii") + '"'

    body = re.sub(r'src="(figures/[^"]+\.png)"', embed, body)
    style = ("body{font-family:sans-serif;max-width:70em;margin:2em auto;padding:0 1em;line-height:1.4}"
             "table{border-collapse:collapse;margin:1em 0;font-size:90%}td,th{border:1px solid #ccc;"
             "padding:.2em .5em;text-align:left}img{max-width:100%}code{background:#f4f4f4}")
    return (f"<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            f"<title>Reproduction report, preset {preset}</title><style>{style}</style></head>\n"
            f"<body>\n{body}\n</body></html>\n")


def headline(preset: str, targets: int, failed: int, undetermined: int = 0) -> str:
    """The verdict the report opens with; none for the small test scene, which is not the paper's system.
    `failed` counts every target that does not pass, `undetermined` those of them whose detector found
    nothing with too little power to call it absent."""
    if preset == "quick":
        return ("**Not comparable with the paper**: preset `quick` is the 200-grain test scene that exercises the "
                f"pipeline; the table below runs the comparisons ({targets - failed} of {targets} within tolerance) "
                "only to test them, and judges nothing.")
    more = f", {undetermined} undetermined" if undetermined else ""
    return f"**{targets - failed} of {targets} paper targets pass** ({failed - undetermined} fail{more})."


def main() -> None:
    if len(sys.argv) != 3:
        fail("usage: python3 -m pipeline.report.report RESULTS_DIR PRESET")
    results, preset = Path(sys.argv[1]), sys.argv[2]
    again = f"make reproduce PRESET={preset}"
    metrics = read_json(results / "metrics.json", again)
    check = read_json(results / "check.json", again)
    index = read_json(results / "figures" / "index.json", again)
    table, rows = targets_table(check)
    failed = [t for t in rows if t.get("verdict") != "pass"]
    run = metrics["pulloff"]
    text = [
        f"# Reproduction report: intruder pull-off, preset `{preset}`",
        "",
        "A 2D DEM reproduction of the pull-off of a horizontal bar from a bed of glass disks "
        "(the study, its parameters and its results: `docs/paper.md`). Written by `make reproduce "
        f"PRESET={preset}` from the files beside it; code version {metrics.get('code_version', 'unknown')}.",
        "",
        headline(preset, len(rows), len(failed), sum(t.get("verdict") == "undetermined" for t in failed)) + f" Pull-off: {run['travel_mm']:.1f} mm of travel, "
        f"drag peak {run['drag_max_N_per_m']:.0f} N/m ({run['drag_max_N']:.2f} N × W) at H = "
        f"{run['height_at_drag_max_mm']:.1f} mm.",
        "",
        "## Metrics against the paper",
        "",
        "Targets, tolerances and their sources: `data/paper_targets.toml`; `make check PRESET="
        f"{preset}` runs the same comparisons as GoogleTest tests.",
        "",
        *table,
        "",
        "## Deviations from the paper",
        "",
        *deviations(preset, failed, metrics),
        "",
        "## Cost",
        "",
        "Wall time of each stage on this machine (`timing.json` in each stage's folder); for the simulations, "
        "the engine's own count of steps.",
        "",
        *cost_table(metrics["cost"]),
        "",
        "## The detectors' evidence",
        "",
        "Each detector is checked on planted truth by `make validate` (results/validate/table.md, \"Planted "
        "truth\"). What this run's detectors found, with the rules and intervals behind the numbers above:",
        "",
        *detectors_section(metrics),
        "",
        "## Synthetic PIV against coarse-graining",
        "",
        *piv_section(metrics),
        "",
        "## Figures",
        "",
        *figures(index),
        "## How the numbers move with the definitions' thresholds",
        "",
        "Every threshold was fixed before the results were seen; these tables show how each number moves when "
        "its threshold moves (definitions: `analysis/<stage>/README.md`).",
        "",
        *sensitivity(metrics),
    ]
    # report.md, make's target, last: a failure before it (a full disk) leaves it to be made again
    write_atomic(results / "report.html", html_page("\n".join(text), results, preset))
    write_atomic(results / "report.md", "\n".join(text) + "\n")
    print(f"report: {len(rows) - len(failed)}/{len(rows)} targets pass -> {results / 'report.md'}", file=sys.stderr)


if __name__ == "__main__":
    main()

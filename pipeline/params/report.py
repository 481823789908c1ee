"""make params' report: a table per sweep (setting, each headline metric with
its interval, cost), the figures, and report.md saying claim by claim what
holds, what does not, and how sure we are (docs/params.md).

    /usr/bin/python3 -m pipeline.params.report RESULTS_DIR     (results/params)

Intervals: a point with n >= 2 members gives mean +- t(0.975, n-1) sd/sqrt(n);
a point run once gives its value +- 1.96 sd_base, sd_base the spread of
single runs at the base point (its members): the noise of one realisation.
"""
import csv
import json
import math
import sys
from pathlib import Path

import h5py
import numpy as np

from pipeline.report.common import save
from pipeline.files import fail, read_json, write_atomic

G = 9.81
BED_HEIGHT_FOR_I = 0.1  # m: P ~ rho g h at the intruder's mid-travel (docs/accuracy.md's inertial number)
# headline metrics: (name, label, unit, how to get it from one member's metrics and the point's settings)
HEADLINE = [
    ("bed_height_mm", "bed height H_f", "mm", lambda m, s: m["fill"]["bed_height_mm"]),
    ("solid_fraction", "Φ", "", lambda m, s: m["fill"]["solid_fraction"]),
    ("drag_max_N_per_m", "peak drag", "N/m", lambda m, s: m["pulloff"]["drag_max_N_per_m"]),
    ("drag_mean_N_per_m", "mean drag", "N/m", None),  # from drag.csv
    ("top_layer_found", "members with a top layer", "", lambda m, s: 1.0 if m["spectrum"]["top_layer_found"] else 0.0),
    ("top_layer_power", "power of a miss", "",
     lambda m, s: float("nan") if m["spectrum"]["top_layer_found"] else m["spectrum"]["top_layer_power"]),
    ("top_layer_depth_mm", "top-layer depth", "mm",
     lambda m, s: m["spectrum"]["bed_height_mm"] - m["spectrum"]["top_layer_height_mm"]),
    ("cone_angle_deg", "β", "°", lambda m, s: m["cg"]["cone_angle_deg"]),
    ("wall_mobility_length_mm", "H_c", "mm", lambda m, s: m["cg"]["wall_mobility_length_mm"]),
    ("wall_mobility_power", "power of an H_c miss", "",
     lambda m, s: float("nan") if m["cg"]["wall_mobility_length_mm"] is not None else m["cg"]["wall_mobility_power"]),
    ("H_c_predicted_mm", "½(L_c−L) tan β", "mm",
     lambda m, s: 0.5 * (s["cell_width_mm"] - s["intruder_length_mm"]) * math.tan(math.radians(m["cg"]["cone_angle_deg"]))),
    ("rupture_spacing_d", "rupture spacing", "d", lambda m, s: m["spectrum"]["rupture_spacing_d"]),
    ("rupture_frequency_hz", "rupture frequency at V", "Hz", lambda m, s: m["spectrum"]["rupture_frequency_hz_at_run_v"]),
    ("slip_fraction", "slip fraction", "", lambda m, s: m["friction"]["slip_fraction"]),
    ("mu_star_bulk", "mean μ* (bulk)", "", lambda m, s: m["friction"]["mean_mu_star_bulk"]),
]
# the paper targets' tolerances, for "how many members would give an interval this narrow"
TOLERANCE = {"top_layer_depth_mm": 10.0, "wall_mobility_length_mm": 10.0, "cone_angle_deg": 10.0,
             "rupture_spacing_d": 0.15, "rupture_frequency_hz": 0.3, "solid_fraction": 0.02, "bed_height_mm": 5.0}


def number(v):
    return float(v) if isinstance(v, (int, float)) and v is not None and math.isfinite(v) else float("nan")


def mean_drag(member: Path) -> float:
    """Mean drag over the whole travel (N/m), from the member's pulloff/drag.csv."""
    with open(member / "pulloff" / "drag.csv") as f:
        rows = list(csv.DictReader(f))
    return float(np.mean([float(r["drag_N_per_m"]) for r in rows])) if rows else float("nan")


def member_values(member: Path, settings: dict) -> dict:
    m = read_json(member / "metrics.json", "make params")
    out = {}
    for name, _, _, get in HEADLINE:
        try:
            out[name] = mean_drag(member) if get is None else number(get(m, settings))
        except (KeyError, TypeError, ValueError):
            out[name] = float("nan")
    # the member's whole cost, as its merged metrics sum it: the simulations and every stage of the registry
    # (this sum named six of them: stress and piv were left out)
    cost = m.get("cost")
    out["wall_s"] = number(cost.get("total_wall_seconds")) if isinstance(cost, dict) else float("nan")
    return out


T975 = [12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179, 2.160, 2.145, 2.131,
        2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042]


def t975(dof: int) -> float:
    """Student's t quantile 0.975 with dof >= 1 degrees of freedom, as make check's (analysis/common/normal.hpp):
    tabulated to 30, then the Cornish-Fisher expansion (error < 1e-4)."""
    if dof <= 30:
        return T975[dof - 1]
    z = 1.959964
    return z + (z ** 3 + z) / (4 * dof) + (5 * z ** 5 + 16 * z ** 3 + 3 * z) / (96 * dof * dof)


def summarise(values: list, sd_base: float) -> tuple:
    """(mean, half-width of the 95 % interval) of a point's members' values."""
    v = np.array([x for x in values if math.isfinite(x)])
    if len(v) == 0:
        return float("nan"), float("nan")
    if len(v) >= 2:
        return float(v.mean()), t975(len(v) - 1) * float(v.std(ddof=1)) / math.sqrt(len(v))
    return float(v[0]), 1.96 * sd_base


def fmt(mean, half, unit=""):
    if not math.isfinite(mean):
        return "—"
    digits = 3 if abs(mean) < 100 else 4
    text = f"{mean:.{digits}g}"
    if math.isfinite(half):
        text += f" ± {half:.2g}"
    return text + (f" {unit}" if unit and unit not in ("",) else "")


def spectrum(member: Path):
    with h5py.File(member / "spectrum" / "spectrum.h5", "r") as f:
        return f["psd/wavenumber_per_d"][...], f["psd/frequency_hz_at_run_v"][...], f["psd/power"][...]


BAND_PER_D = (0.2, 5.0)  # wavenumbers (per d of travel) where spectra are compared: wavelengths 0.2 d to 5 d


def spectral_shape(p: dict, reference=None):
    """The drag spectrum's slope d ln P / d ln f over BAND_PER_D, and (with a reference point's) the rms
    distance of ln(P V) between the two at common wavenumbers: 0 if they collapse when scaled by V."""
    try:
        k, f, power = spectrum(Path(p["members"][0]))
    except (OSError, KeyError):
        return float("nan"), float("nan")
    band = (k >= BAND_PER_D[0]) & (k <= BAND_PER_D[1]) & (power > 0)
    if band.sum() < 5:
        return float("nan"), float("nan")
    slope = float(np.polyfit(np.log(f[band]), np.log(power[band]), 1)[0])
    if reference is None:
        return slope, float("nan")
    kr, _, pr = spectrum(Path(reference["members"][0]))
    grid = np.geomspace(*BAND_PER_D, 40)
    scaled = np.log(np.interp(grid, k[band], power[band] * p["settings"]["pull_speed_mm_s"]))
    ok = (kr > 0) & (pr > 0)
    ref = np.log(np.interp(grid, kr[ok], pr[ok] * reference["settings"]["pull_speed_mm_s"]))
    return slope, float(np.sqrt(np.mean((scaled - ref) ** 2)))


def geometry_points(points: list) -> list:
    """The base and the points that change the cell's or the intruder's size: the geometric claims' points."""
    return [p for p in points if p["sweep"] in ("base", "cell_width", "intruder_length")]


def figures(out: Path, points: list, stamp: str) -> list:
    import matplotlib.pyplot as plt
    made = []
    geo = geometry_points(points)
    if geo:
        fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.5), constrained_layout=True)
        missing = {a: [], b: []}
        for p in geo:
            x = 0.5 * (p["settings"]["cell_width_mm"] - p["settings"]["intruder_length_mm"])
            pm, _ = p["summary"]["H_c_predicted_mm"]
            for ax, xv, (m, h) in ((a, x, p["summary"]["top_layer_depth_mm"]),
                                   (b, pm, p["summary"]["wall_mobility_length_mm"])):
                if not (math.isfinite(m) and math.isfinite(xv)):
                    missing[ax].append(p["point"])
                elif math.isfinite(h):
                    ax.errorbar([xv], [m], yerr=[h], fmt="o", capsize=3, label=p["point"])
                else:  # one member and no spread to borrow: an open marker, no interval
                    ax.plot([xv], [m], "o", mfc="none", label=f"{p['point']} (spread unknown)")
        for ax, what in ((a, "no top layer"), (b, "no significant loss")):
            if missing[ax]:
                ax.text(0.98, 0.02, f"{what}: " + ", ".join(missing[ax]), transform=ax.transAxes, ha="right",
                        va="bottom", fontsize=7)
        lim = [0, max(80, max(0.5 * (p["settings"]["cell_width_mm"] - p["settings"]["intruder_length_mm"]) for p in geo) + 10)]
        a.plot(lim, lim, "k--", lw=1, label="depth = (L_c − L)/2")
        a.set_xlabel("(L_c − L)/2 (mm)")
        a.set_ylabel("top-layer depth (mm)")
        a.legend(fontsize=7)
        top = max([lim[1]] + [p["summary"]["H_c_predicted_mm"][0] for p in geo if math.isfinite(p["summary"]["H_c_predicted_mm"][0])])
        b.plot([0, top], [0, top], "k--", lw=1, label="H_c = ½(L_c − L) tan β")
        b.set_xlabel("½(L_c − L) tan β (mm, β measured)")
        b.set_ylabel("H_c measured (mm)")
        b.legend(fontsize=7)
        save(fig, out, "geometry.png", stamp)
        made.append(("geometry.png", "Top-layer depth against (L_c − L)/2, and H_c against ½(L_c − L) tan β"))
    speed = sorted([p for p in points if p["sweep"] in ("base", "pull_speed")], key=lambda p: p["settings"]["pull_speed_mm_s"])
    if len(speed) > 1:
        fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.5), constrained_layout=True)
        for p in speed:
            try:
                k, f, power = spectrum(Path(p["members"][0]))
            except (OSError, KeyError):
                continue
            v = p["settings"]["pull_speed_mm_s"]
            ok = (f > 0) & (power > 0)
            a.loglog(f[ok], power[ok], lw=0.8, label=f"V = {v:g} mm/s")
            b.loglog(k[ok], power[ok] * v, lw=0.8, label=f"V = {v:g} mm/s")
        ff = np.array([0.05, 50.0])
        a.loglog(ff, 1e2 * ff ** -2.0, "k:", lw=1, label="ω⁻²")
        a.set_xlabel("frequency at V (Hz)")
        a.set_ylabel("drag PSD")
        b.set_xlabel("wavenumber (per d of travel) = f d / V")
        b.set_ylabel("PSD × V (collapses if the slip distance is constant)")
        for ax in (a, b):
            ax.legend(fontsize=7)
        save(fig, out, "spectra_by_speed.png", stamp)
        made.append(("spectra_by_speed.png", "Drag spectra at each pull speed, against frequency and scaled by V"))
    coh = sorted([p for p in points if p["sweep"] in ("base", "cohesion")], key=lambda p: p["settings"]["bond_number"])
    if len(coh) > 1:
        fig, ax = plt.subplots(figsize=(6, 4.5), constrained_layout=True)
        bo = [p["settings"]["bond_number"] for p in coh]
        for key, label in (("drag_mean_N_per_m", "mean drag"), ("drag_max_N_per_m", "peak drag")):
            m = [p["summary"][key][0] for p in coh]
            h = [p["summary"][key][1] for p in coh]
            ax.errorbar(bo, m, yerr=[x if math.isfinite(x) else 0 for x in h], fmt="o-", capsize=3, label=label)
        ax.set_xlabel("Bond number f_c / (m g)")
        ax.set_ylabel("drag (N/m)")
        ax.legend()
        save(fig, out, "cohesion.png", stamp)
        made.append(("cohesion.png", "Drag against the Bond number"))
    return made


def within(mean, half, target, tol, every_member=True):
    """The 95 % interval mean +- half against the claim's band target +- tol: 'holds' if the interval
    lies inside the band, 'fails' if wholly outside it, 'undetermined' if it straddles an edge (more members
    would decide) or its spread is unknown (a single value, no spread to borrow, decides nothing), '?'
    without a value. A member without a value (its detector found nothing) is a result too: without
    every_member the others alone cannot make the claim hold (as the ensemble's verdicts)."""
    if not math.isfinite(mean):
        return "?"
    if not math.isfinite(half):
        return "undetermined"
    lo, hi = mean - half, mean + half
    if lo >= target - tol and hi <= target + tol:
        return "holds" if every_member else "undetermined"
    if hi < target - tol or lo > target + tol:
        return "fails"
    return "undetermined"


def every_member(p: dict, key: str) -> bool:
    """Whether every member of point p has a value of metric key."""
    return all(math.isfinite(v[key]) for v in p["values"])


MIN_POWER = 0.8  # a miss is evidence of absence at this power or more (data/spectrum.toml's and data/cg.toml's min_power)


def misses_confident(p: dict, found: str = "top_layer_found", power: str = "top_layer_power") -> bool:
    """Whether every member of point p that found nothing (metric `found` not positive, or NaN) had the
    power to find it (metric `power` >= MIN_POWER): only then is a miss evidence of absence."""
    return all(v[found] > 0 or v[power] >= MIN_POWER for v in p["values"])


def claims(points: list) -> list:
    lines = []
    geo = geometry_points(points)
    lines += ["### 1. The top layer: depth ≈ (L_c − L)/2", "",
              "| point | (L_c − L)/2 (mm) | members with a top layer | top-layer depth (mm) | verdict (±10 mm, R4's tolerance) |",
              "|---|---|---|---|---|"]
    verdicts = []
    for p in geo:
        x = 0.5 * (p["settings"]["cell_width_mm"] - p["settings"]["intruder_length_mm"])
        m, h = p["summary"]["top_layer_depth_mm"]
        v = within(m, h, x, 10.0, every_member(p, "top_layer_depth_mm"))
        if v == "?":  # no member found a layer: absent only where each miss had the power to find one
            v = "fails" if misses_confident(p) else "undetermined"
        verdicts.append(v)
        lines.append(f"| {p['point']} | {x:g} | {fmt(p['summary']['top_layer_found'][0], float('nan'))} | {fmt(m, h)} | {v} |")
    weak = [p["point"] for p in geo if not misses_confident(p)]
    if geo and not any(p["summary"]["top_layer_found"][0] > 0 for p in geo) and not weak:
        lines += ["", "**Not supported**: no member at any point has a top layer (no significant change point, "
                  f"each miss with a power of at least {MIN_POWER:g} to find one at the paper's depth), so there is "
                  "no depth to follow (L_c − L)/2."]
    elif geo and not any(p["summary"]["top_layer_found"][0] > 0 for p in geo):
        lines += ["", f"**Undetermined**: no member at any point has a top layer, but at {len(weak)} of {len(geo)} "
                  f"points ({', '.join(weak)}) a miss had less than {MIN_POWER:g} power to find one at the paper's "
                  "depth in that member's own drag: absence is not shown there."]
    else:
        none = [p["point"] for p in geo if not p["summary"]["top_layer_found"][0] > 0]
        lines += ["", verdict_line(verdicts, "the top layer's depth follows (L_c − L)/2") +
                  (f" No member has a top layer at {len(none)} of {len(geo)} points ({', '.join(none)})"
                   + (f"; at {', '.join(p for p in none if p in weak)} a miss had less than {MIN_POWER:g} power"
                      if any(p in weak for p in none) else ": each miss with the power to find one") + "."
                   if none else "")]
    xy = [(0.5 * (p["settings"]["cell_width_mm"] - p["settings"]["intruder_length_mm"]), p["summary"]["top_layer_depth_mm"][0])
          for p in geo if math.isfinite(p["summary"]["top_layer_depth_mm"][0])]
    if len({x for x, _ in xy}) >= 3:
        (b, a), cov = np.polyfit([x for x, _ in xy], [y for _, y in xy], 1, cov=True)
        lines += ["", f"A line through the points: depth = {a:.1f} mm + {b:.2f} × (L_c − L)/2 (slope ± {1.96 * math.sqrt(cov[0][0]):.2f}, "
                  f"95 %); the claim is a slope of 1 through 0."]
    lines.append("")
    lines += ["### 2. The wall-mobility length: H_c = ½(L_c − L) tan β", "",
              "| point | β (°) | ½(L_c − L) tan β (mm) | H_c measured (mm) | verdict (±10 mm, R6's tolerance) |",
              "|---|---|---|---|---|"]
    verdicts = []
    for p in geo:
        b, bh = p["summary"]["cone_angle_deg"]
        pm, ph = p["summary"]["H_c_predicted_mm"]
        m, h = p["summary"]["wall_mobility_length_mm"]
        half = math.hypot(h, ph)  # NaN (undetermined) if either spread is unknown
        v = within(m - pm, half, 0.0, 10.0, every_member(p, "wall_mobility_length_mm")) if math.isfinite(pm) else "?"
        if v == "?" and math.isfinite(pm):  # no member found a loss: absent only where each miss had the power
            v = "fails" if misses_confident(p, "wall_mobility_length_mm", "wall_mobility_power") else "undetermined"
        verdicts.append(v)
        lines.append(f"| {p['point']} | {fmt(b, bh)} | {fmt(pm, ph)} | {fmt(m, h)} | {v} |")
    lines += ["", verdict_line(verdicts, "H_c = ½(L_c − L) tan β")]
    ratios = [p["summary"]["wall_mobility_length_mm"][0] / p["summary"]["H_c_predicted_mm"][0] for p in geo
              if math.isfinite(p["summary"]["wall_mobility_length_mm"][0]) and p["summary"]["H_c_predicted_mm"][0] > 0]
    if len(ratios) >= 2:
        mean, half = summarise(ratios, float("nan"))
        lines += ["", f"H_c measured / ½(L_c − L) tan β over the {len(ratios)} points: {mean:.2f} ± {half:.2f} (95 %, "
                  "the points' spread); the claim is 1."]
    lines.append("")
    speed = sorted([p for p in points if p["sweep"] in ("base", "pull_speed")], key=lambda p: p["settings"]["pull_speed_mm_s"])
    base = next(p for p in points if p["point"] == "base")
    lines += ["### 3. Ruptures against the pull speed", "",
              f"Spectra compared over wavelengths of travel from {1 / BAND_PER_D[1]:g} d to {1 / BAND_PER_D[0]:g} d "
              f"(wavenumbers {BAND_PER_D[0]:g}–{BAND_PER_D[1]:g} per d): the slope of ln P against ln f (−2: ω⁻²), and "
              "the rms distance of ln(P V) from the base's at the same wavenumbers (0: the spectra collapse when the "
              "frequency is scaled by V, a constant slip distance; one member each).", "",
              "| V (mm/s) | inertial number I = V/√(g h) | rupture spacing (d) | rupture frequency (Hz) | PSD slope | "
              "distance from the base's scaled spectrum |", "|---|---|---|---|---|---|"]
    for p in speed:
        v = p["settings"]["pull_speed_mm_s"]
        inertial = v * 1e-3 / math.sqrt(G * BED_HEIGHT_FOR_I)
        s, sh = p["summary"]["rupture_spacing_d"]
        f, fh = p["summary"]["rupture_frequency_hz"]
        slope, distance = spectral_shape(p, None if p is base else base)
        lines.append(f"| {v:g} | {inertial:.2g} | {fmt(s, sh)} | {fmt(f, fh)} | {slope:.2f} | "
                     f"{'—' if not math.isfinite(distance) else f'{distance:.2f}'} |")
    pts = [(p["settings"]["pull_speed_mm_s"], p["summary"]["rupture_spacing_d"][0]) for p in speed
           if math.isfinite(p["summary"]["rupture_spacing_d"][0]) and p["summary"]["rupture_spacing_d"][0] > 0]
    if len(pts) >= 3:
        (slope, _), cov = np.polyfit(np.log([v for v, _ in pts]), np.log([s for _, s in pts]), 1, cov=len(pts) > 3)
        half = 1.96 * math.sqrt(cov[0][0]) if len(pts) > 3 else float("nan")
        grows = math.isfinite(half) and slope - half > 0
        flat = math.isfinite(half) and slope - half <= 0 <= slope + half
        lines += ["", f"Rupture spacing against V: a power law of exponent {slope:.2f}"
                  + (f" ± {half:.2f} (95 %)" if math.isfinite(half) else "") +
                  "; 0 is a constant slip distance (the frequency ∝ V, the spectra collapse when scaled by V). "
                  + ("The spacing grows with V: the frequency is not simply ∝ V." if grows else
                     "A constant slip distance is not excluded over this range." if flat else "Too few points to say.")]
    return lines


def cyclic_section(points: list) -> list:
    """Cyclic loading: the drag of each up and down leg, and the bed between cycles (its mean surface height and
    solid fraction at the end of the rise's rest and of each cycle: compaction if they fall and rise)."""
    import dem2d
    from dem2d.measure import surface
    lines = []
    for p in points:
        for member in p["members"]:
            m = read_json(Path(member) / "cyclic" / "metrics.json", "make params")
            legs = m["pulloff"]["cycles"]["legs"]
            lines += [f"### Cyclic loading: {p['point']} ({Path(member).name}), V = {p['settings']['pull_speed_mm_s']:g} mm/s", "",
                      "| cycle | up: mean drag (N/m) | down: mean drag (N/m) |", "|---|---|---|"]
            for c in sorted({leg["cycle"] for leg in legs}):
                up = [leg["drag_mean_N_per_m"] for leg in legs if leg["cycle"] == c and leg["direction"] == "up"]
                down = [leg["drag_mean_N_per_m"] for leg in legs if leg["cycle"] == c and leg["direction"] == "down"]
                lines.append(f"| {c} | {fmt(up[0], float('nan')) if up else '—'} | {fmt(down[0], float('nan')) if down else '—'} |")
            with dem2d.open_run(Path(member) / "cyclic" / "run.h5") as run:
                motion = run.parameters.body("intruder")["motion"]
                t, ends = 0.0, []
                for seg in motion:
                    if seg["kind"] == "triangle":
                        ends += [t + seg["period"] * (k + 1) for k in range(seg.get("cycles", 1))]
                        t += seg["period"] * seg.get("cycles", 1)
                    else:
                        t += seg["duration"]
                        ends.append(t)
                walls = [b for b in run.bodies if b.role in ("left_wall", "right_wall")]
                rows = []
                for k, te in enumerate(ends[1:]):  # after the rise's rest, then after each cycle
                    s = run.snapshot_at(min(te, run.times[-1]))
                    xy, r = s.position[s.active], run.particles.diameter[s.active] / 2
                    top = surface(xy, 2 * r.mean())
                    width = abs(walls[1].core(s.body_vertices)[0, 0] - walls[0].core(s.body_vertices)[0, 0]) - walls[0].thickness
                    height = float(top[:, 1].mean() - run.floor_top())
                    rows.append((k, s.time, height, float(np.pi * (r ** 2).sum() / (width * height))))
            lines += ["", "Cycle 0 is the first rise; the bed, at the end of the rest after it and of each cycle:", "", "| after | t (s) | mean surface height (mm) | bed solid fraction |", "|---|---|---|---|"]
            for k, time, height, phi in rows:
                lines.append(f"| {'the rise and rest' if k == 0 else f'cycle {k}'} | {time:.2f} | {height * 1e3:.2f} | {phi:.4f} |")
            if len(rows) > 1:
                dh = (rows[-1][2] - rows[0][2]) * 1e3
                lines += ["", f"Over the cycles the bed's surface moved by {dh:+.2f} mm "
                          f"({'compaction' if dh < 0 else 'dilation'}; one member: its noise is not measured here)."]
            lines.append("")
    return lines


# what the settled bed is compared on with the study's poured ensemble (results/<preset>/ensemble)
POURED = [("fill.bed_height_mm", "bed height (mm)"), ("fill.solid_fraction", "Φ"),
          ("fill.coordination_number", "coordination number"), ("pulloff.drag_max_N_per_m", "peak drag (N/m)"),
          ("spectrum.top_layer_height_mm", "top layer from (mm)"), ("cg.cone_angle_deg", "β (°)"),
          ("cg.wall_mobility_length_mm", "H_c (mm)"), ("spectrum.rupture_spacing_d", "rupture spacing (d)"),
          ("friction.slip_fraction", "slip fraction")]


def settled_against_poured(plan: dict, base: dict) -> list:
    """The reduced plan's settled beds against the study's hopper-poured ensemble of the same preset, if one was
    made (make ensemble PRESET=<preset>): what the cheaper bed changes."""
    path = Path(f"results/{plan['preset']}/ensemble/stats.json")
    if plan["fill"] != "settle" or not path.exists():
        return []
    ref = read_json(path, f"make ensemble PRESET={plan['preset']}")
    members = [read_json(Path(m) / "metrics.json", "make params") for m in base["members"]]
    lines = ["## The settled bed against the poured one", "",
             f"The base point ({len(members)} members: beds settled from a lattice, pulled at "
             f"{plan['pull_speed_mm_s']:g} mm/s) against the study's ensemble of preset `{plan['preset']}` "
             f"({ref['metrics']['fill.bed_height_mm']['n']} members: hopper-poured beds, 1.2 mm/s; `{path}`). "
             "The speed's own effect is the accuracy study's (docs/accuracy.md); what is left is the bed's.", "",
             "| metric | settled (mean ± 95 %) | poured (mean, 95 % interval) |", "|---|---|---|"]
    for key, label in POURED:
        stage, name = key.split(".")
        values = [number(m.get(stage, {}).get(name)) for m in members]
        mean, half = summarise(values, float("nan"))
        r = ref["metrics"].get(key)
        poured = f"{r['mean']:.4g} [{r['ci95'][0]:.4g}, {r['ci95'][1]:.4g}]" if r and r.get("ci95") else "—"
        lines.append(f"| {label} | {fmt(mean, half)} | {poured} |")
    return lines + [""]


def verdict_line(verdicts: list, claim: str) -> str:
    known = [v for v in verdicts if v != "?"]
    n = {k: sum(v == k for v in known) for k in ("holds", "fails", "undetermined")}
    tally = f"holds at {n['holds']}, fails at {n['fails']}, undetermined at {n['undetermined']} of {len(known)} points"
    if not known:
        return f"**Cannot say** whether {claim}: no point measured it."
    if n["fails"]:
        return f"**Does not hold**: {claim} fails beyond the 95 % interval somewhere ({tally})."
    if n["undetermined"]:
        return f"**Not decided**: no point contradicts {claim}, but the intervals are too wide to confirm it ({tally})."
    return f"**Holds**: {claim}, at every point, intervals inside the tolerance ({tally})."


def main() -> int:
    if len(sys.argv) != 2:
        fail("usage: python3 -m pipeline.params.report RESULTS_DIR")
    out = Path(sys.argv[1])
    plan = read_json(out / "plan.json", "make params")
    # a point whose members are not all done is left out and named (a report of a plan still running)
    def done(p):
        return all((Path(m) / ("cyclic/metrics.json" if p["knob"] == "cycles" else "metrics.json")).exists()
                   for m in p["members"])
    pending = [p["point"] for p in plan["points"] if not done(p)]
    cyclic = [p for p in plan["points"] if p["knob"] == "cycles" and p["point"] not in pending]
    points = [p for p in plan["points"] if p["point"] not in pending and p["knob"] != "cycles"]
    if not any(p["point"] == "base" for p in points):
        fail(f"{out}: the base point is not done yet: run `make params PLAN={plan['plan']}`")
    for p in points:
        p["values"] = [member_values(Path(m), p["settings"]) for m in p["members"]]
    base = next(p for p in points if p["point"] == "base")
    names = [h[0] for h in HEADLINE]
    def spread(values):  # sd of the finite values; NaN below two of them
        v = [x for x in values if math.isfinite(x)]
        return float(np.std(v, ddof=1)) if len(v) >= 2 else float("nan")
    sd_base = {k: spread([v[k] for v in base["values"]]) for k in names}
    for p in points:
        p["summary"] = {k: summarise([v[k] for v in p["values"]], sd_base[k]) for k in names}
        p["wall_s"] = sum(v["wall_s"] for v in p["values"] if math.isfinite(v["wall_s"]))
    version = read_json(Path(base["members"][0]) / "metrics.json", "make params").get("code_version", "unknown")
    made = figures(out, points, f"params plan {plan['plan']} · preset {plan['preset']} · dem2d {version} · {out}")
    total = sum(p["wall_s"] for p in points)
    lines = [f"# Parametric study ({plan['plan']} plan)", "",
             f"Preset `{plan['preset']}`, pull speed {plan['pull_speed_mm_s']:g} mm/s, beds `{plan['fill']}`, "
             f"{plan['members']} member(s) per point and {plan['base_members']} at the base point; "
             f"{len(points)} points, {sum(len(p['members']) for p in points)} runs, {total / 3600:.2f} h of single-core "
             "wall time (each run on one thread). Written by `make params` (data/params.toml, docs/params.md).", "",
             *([f"**Not done yet** (left out here): {', '.join(pending)}.", ""] if pending else []),
             "Intervals: 95 %; a point with one member borrows the spread of single runs at the base point. "
             "Members a point needs for a 95 % interval narrower than the paper target's tolerance, from the spread of "
             "single runs at the base point: " +
             "; ".join(f"{label} (±{TOLERANCE[k]:g}{' ' + unit if unit else ''}): "
                       f"{max(1, math.ceil((1.96 * sd_base[k] / TOLERANCE[k]) ** 2)) if math.isfinite(sd_base[k]) else '?'}"
                       for k, label, unit, _ in HEADLINE if k in TOLERANCE) + ".", "",
             "Verdicts: **holds** where the 95 % interval lies inside the claim's tolerance band, **fails** where it lies "
             "wholly outside, **undetermined** where it straddles an edge or its spread is unknown (more members would decide).", "", "## The claims", ""]
    lines += claims(points)
    lines += [""] + settled_against_poured(plan, base)
    if cyclic:
        lines += ["", "## Cyclic loading", ""] + cyclic_section(cyclic)
    lines += ["", "## Every point", ""]
    sweeps = []
    for p in points:
        if p["sweep"] not in sweeps:
            sweeps.append(p["sweep"])
    for s in sweeps:
        rows = [base] + [p for p in points if p["sweep"] == s and p is not base] if s != "base" else [base]
        knob = next((p["knob"] for p in rows if p["knob"]), None)
        lines += [f"### {s}", "", "| point | " + (f"{knob} | " if knob else "") + " | ".join(
            f"{label} ({unit})" if unit else label for _, label, unit, _ in HEADLINE) + " | wall (s) |",
            "|" + "---|" * (len(HEADLINE) + 2 + (1 if knob else 0))]
        for p in rows:
            cells = [p["point"]] + ([str(p["settings"][knob])] if knob else [])
            cells += [fmt(*p["summary"][k]) for k in names] + [f"{p['wall_s']:.0f}"]
            lines.append("| " + " | ".join(cells) + " |")
        lines.append("")
    lines += ["## Figures", ""] + [f"![{t}]({f})\n\n{t}.\n" for f, t in made]
    write_atomic(out / "report.md", "\n".join(lines) + "\n")
    table = {p["point"]: {"sweep": p["sweep"], "settings": p["settings"], "wall_s": p["wall_s"],
                          "metrics": {k: {"mean": p["summary"][k][0], "half_width_95": p["summary"][k][1],
                                          "values": [v[k] for v in p["values"]]} for k in names}} for p in points}
    write_atomic(out / "table.json", json.dumps(table, indent=1, allow_nan=True) + "\n")
    print(f"params report: {len(points)} points -> {out / 'report.md'}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())

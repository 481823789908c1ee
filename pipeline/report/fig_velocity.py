"""Coarse-grained velocity figures from cg.h5: v* zones (Fig. 8), vertical
velocity on the centre line (Fig. 9), the flow around the tips in the
intruder's frame (Fig. 10)."""

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import BoundaryNorm, ListedColormap, LogNorm

from pipeline.report import events
from pipeline.report.bed import draw_bodies, outline
from pipeline.report.common import MM, ZONE_COLOURS, NoData, band_mm, bed_height_mm, nearest

LETTERS = "abcdefgh"


def _zone_map():
    cmap = ListedColormap(ZONE_COLOURS)
    cmap.set_bad("white")
    return cmap, BoundaryNorm([0, 0.25, 0.75, 1e9], 3)


def pick_heights(inp, cg):
    """Five stored fields for Fig. 8: lower part, three in the upper part, top layer;
    pre-rupture snapshots preferred."""
    hb = bed_height_mm(inp)
    top = inp.metrics("spectrum").get("top_layer_height_mm")
    in_top_layer = (top + hb) / 2 if top and top > 0.7 * hb else 0.85 * hb
    targets = [0.2 * hb, 0.4 * hb, 0.55 * hb, 0.7 * hb, in_top_layer]
    usable = cg.usable_fields(below_mm=hb - 3)
    heights = cg.height[cg.fields]
    chosen = []
    for t in targets:
        free = np.setdiff1d(usable, [c for c in chosen if c is not None])
        pre = free[cg.pre_rupture[cg.fields[free]] >= 0]
        m = nearest(heights, t, pre)
        if m is None or abs(heights[m] - t) > 0.05 * hb:
            m = nearest(heights, t, free)
        chosen.append(m)
    return targets, chosen


def vstar_zones(inp, cg, run, ev):
    panels = sorted(((t, m) for t, m in zip(*pick_heights(inp, cg)) if m is not None), key=lambda p: p[1])
    if not panels:
        raise NoData("cg.h5 has no stored field with the intruder in the bed")
    cmap, norm = _zone_map()
    xe, ye = cg.edges()
    top = min(max(cg.surface) + 6, ye[-1])
    fig, axes = plt.subplots(1, len(panels), figsize=(2.8 * len(panels) + 1, 4.6), constrained_layout=True,
                             sharey=True, squeeze=False)
    axes = axes[0]
    where = []
    for a, ax, (t, m) in zip(LETTERS, axes, panels):
        k = cg.fields[m]
        mesh = ax.pcolormesh(xe, ye, cg.vstar(m), cmap=cmap, norm=norm, rasterized=True)
        draw_bodies(ax, run, k)
        ax.set(xlim=(xe[0], xe[-1]), ylim=(0, top), aspect="equal", xlabel="x (mm)")
        state = events.describe(ev, cg.time[k])
        ax.set_title(f"({a}) H = {cg.height[k]:.1f} mm\n{state}")
        where.append(f"({a}) {cg.height[k]:.1f} mm ({state}; aimed at {t:.0f} mm)")
    axes[0].set_ylabel("height above the floor (mm)")
    cb = fig.colorbar(mesh, ax=axes, shrink=0.7, boundaries=[0, 0.25, 0.75, 1.25], values=[0.1, 0.5, 1.0],
                      ticks=[0.1, 0.5, 1.0])
    cb.ax.set_yticklabels(["v* < 0.25\nimmobile", "0.25–0.75\ncone", "v* > 0.75\ndragged"])
    cb.set_label("zone of v* = |V|/V (-)")
    top = inp.metrics("spectrum").get("top_layer_height_mm")
    if top and cg.height[cg.fields[panels[-1][1]]] < top:
        where[-1] += f"; the stored field nearest to the top layer lies below it (top layer from {top:.1f} mm)"
    caption = (f"Mobility zones of v* = |V|/V (lab frame) at {len(panels)} intruder heights: {'; '.join(where)}. "
               f"Velocities: {cg.describe()}; from cg/cg.h5 /fields, which stores full fields only for "
               f"{len(cg.fields)} snapshots (one every 10 mm, and pre-rupture ones with the two after them for events "
               "spread over the run), so each "
               "panel is the stored snapshot nearest to its aimed height; white: masked (φ below the mask).")
    return fig, caption


def centre_velocity(inp, cg):
    vy = cg.h5.read(f"profiles/centre_vy_{cg.set}") / cg.speed  # [S, NY]
    h = cg.height
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 5), constrained_layout=True,
                                  gridspec_kw={"width_ratios": [3, 1.2]})
    he = np.concatenate([[h[0]], (h[1:] + h[:-1]) / 2, [h[-1]]])
    _, ye = cg.edges()
    mesh = ax.pcolormesh(he, ye, vy.T, cmap="RdBu_r", vmin=-1.5, vmax=1.5, rasterized=True)
    ax.plot(h, h, color="k", lw=1, label="intruder (y = H)")
    ax.plot(h, cg.surface, color="0.4", lw=1, ls="--", label="free surface")
    ax.set(xlabel="intruder height H (mm)", ylabel="y on the centre line, above the floor (mm)",
           ylim=(0, min(cg.surface.max() + 5, ye[-1])), xlim=(he[0], he[-1]))
    ax.legend(loc="lower right")
    fig.colorbar(mesh, ax=ax, extend="both").set_label("vertical velocity V_y / V (-)")

    m = inp.metrics("cg")
    onset = h <= h[0] + 5 * (m.get("dilatancy_travel_after_mm") or 3)
    ax2.plot(h[onset], cg.h5.read("snapshots/phi_region")[onset], ".-", ms=3, lw=0.8)
    dphi = m.get("dilatancy_delta_phi")
    if dphi is not None:
        ax2.axhline(m["dilatancy_phi_before"], color="0.5", ls=":", lw=1)
        ax2.plot(h[0] + m["dilatancy_travel_after_mm"], m["dilatancy_phi_after"], "o", color="#d62728",
                 label=f"ΔΦ = {dphi:+.4f}")
        ax2.legend(loc="upper right")
    ax2.set(xlabel="intruder height H (mm)", ylabel="solid fraction Φ above the intruder (-)",
            title="onset: dilatancy region")
    caption = (f"Vertical velocity V_y/V along the node column through the intruder's centre against the "
               f"intruder height, every snapshot (cg/cg.h5 /profiles/centre_vy_{cg.set}; {cg.describe()}); "
               "blank columns have no velocity of that kind. Right: CG solid fraction in the region following the "
               "intruder (2w to 2w + 10 d above it) at the onset, with the cg stage's ΔΦ.")
    return fig, caption


def tip_velocity(inp, cg, run, ev):
    """Intruder-frame velocity around the intruder at the two largest ruptures with a snapshot."""
    lag = float(np.median(np.diff(cg.time)))
    window = cg.window if cg.set == "piv" else 0.0
    above = np.nan_to_num(band_mm(inp, "bottom")[1])
    picks = events.rupture_snapshots(ev, cg.time, window, lag, cg.usable, above)[:2]
    if not picks:
        raise NoData("no snapshot's velocity window starts during a drop (or within one snapshot interval after it)")
    dx, dy = cg.h5.read("tips/dx") * MM, cg.h5.read("tips/dy") * MM
    fig, axes = plt.subplots(1, len(picks), figsize=(6.2 * len(picks), 3.8), constrained_layout=True, squeeze=False)
    where = []
    for a, ax, (e, k) in zip(LETTERS, axes[0], picks):
        vx = cg.h5.read(f"tips/vx_{cg.set}", k) / cg.speed
        vy = cg.h5.read(f"tips/vy_{cg.set}", k) / cg.speed
        speed = np.hypot(vx, vy)
        mag = ax.pcolormesh(dx, dy, np.clip(speed, 1e-3, None), cmap="magma", norm=LogNorm(0.1, 10),
                            shading="nearest", rasterized=True)
        ax.streamplot(dx, dy, vx, vy, color="w", linewidth=0.7, density=1.3, arrowsize=0.7)
        core = run.core(k, "intruder")
        ax.add_patch(plt.Polygon(outline(core - core.mean(axis=0), run.body["intruder"].thickness / 2) * MM,
                                 fc="0.6", ec="w", zorder=4))
        after = events.seconds(cg.time[k] - ev["peak_time"][e])
        ax.set_title(f"({a}) H = {cg.height[k]:.1f} mm, drop {ev['drop'][e]:.0f} N/m, {after} after its peak")
        ax.set(xlabel="x − x_intruder (mm)", ylabel="y − y_intruder (mm)", aspect="equal")
        where.append(f"({a}) event {e} (drop {ev['drop'][e]:.0f} N/m) at {cg.height[k]:.1f} mm, {after} after "
                     f"the peak ({events.describe(ev, cg.time[k])})")
    fig.colorbar(mag, ax=axes[0].tolist(), extend="both").set_label("|V − V_intruder| / V (log scale, -)")
    caption = ("Velocity in the intruder's frame, (V − V_intruder)/V, around the intruder (streamlines; colour: "
               "speed in log scale; far from the intruder the bed moves at −V in this frame) at the two largest "
               "drops above the bottom zone that have a snapshot whose velocity window starts after the peak and "
               f"at most one snapshot interval after the drop's end: {'; '.join(where)}. "
               f"From cg/cg.h5 /tips ({cg.describe()}).")
    return fig, caption

"""The normal force network drawn on the bed (Fig. 6b) and over the
coarse-grained velocity magnitude (Fig. 11)."""

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import LogNorm

from pipeline.report import events
from pipeline.report.bed import draw_bodies, draw_grains, draw_network, frame
from pipeline.report.common import NoData, bed_height_mm, nearest

LETTERS = "abcd"


def force_network(inp, run, k):
    """Fig. 6b at run snapshot k."""
    seg, fn = run.force_segments(k)
    xy, d = run.grains(k)
    h = run.heights()[k]
    fig, ax = plt.subplots(figsize=(7, 9), constrained_layout=True)
    frame(ax, run, k, top_mm=(xy[:, 1] + d / 2).max() + 3)
    draw_grains(ax, xy, d, face="0.94", edge="0.7")
    lines = draw_network(ax, seg, fn, fn.max(), lw_max=4.0, cmap="inferno_r")
    draw_bodies(ax, run, k, colour="#1f77b4")
    fig.colorbar(lines, ax=ax, shrink=0.6).set_label("normal force F_n (N/m)")
    ax.set_title(f"H = {h:.1f} mm, t = {run.time[k]:.2f} s")
    caption = (f"Normal force network at the snapshot nearest to H = 34 mm (snapshot {k}, H = {h:.1f} mm): "
               f"{len(fn)} contacts with F_n > 0 drawn between grain centres (or to the wall/intruder surface), "
               f"line width ∝ F_n (widest {fn.max():.1f} N/m; mean {fn.mean():.2f} N/m); from pulloff/run.h5.")
    return fig, caption


def _sequence(inp, cg):
    """A stored loading -> drop -> reloading sequence: a pre-rupture field and the fields of the
    snapshots right after it (cg.h5 stores such runs for some events), nearest a quarter of the bed
    height; else four consecutive stored fields there."""
    usable = cg.usable_fields(below_mm=bed_height_mm(inp) - 3)
    k = cg.fields
    runs = [i for i in range(len(usable) - 2)
            if cg.pre_rupture[k[usable[i]]] >= 0 and k[usable[i + 2]] == k[usable[i]] + 2]
    target = 0.25 * bed_height_mm(inp)
    if runs:
        i = min(runs, key=lambda i: abs(cg.height[k[usable[i]]] - target))
        return list(usable[i:i + 3])
    first = nearest(cg.height[k], target, usable)
    if first is None:
        return []
    i = int(np.searchsorted(usable, first))
    return list(usable[max(0, min(i, len(usable) - 4)):][:4])


def force_on_velocity(inp, cg, run, ev):
    ms = _sequence(inp, cg)
    if not ms:
        raise NoData("cg.h5 has no stored field with the intruder in the bed")
    ks = [int(cg.fields[m]) for m in ms]
    segs = [run.force_segments(k) for k in ks]
    fn_max = max(fn.max() for _, fn in segs)
    xe, ye = cg.edges()
    norm = LogNorm(1e-2, 10)
    fig, axes = plt.subplots(1, len(ks), figsize=(3.6 * len(ks) + 0.8, 3.5), constrained_layout=True, squeeze=False)
    where = []
    for a, ax, m, k, (seg, fn) in zip(LETTERS, axes[0], ms, ks, segs):
        v = np.clip(cg.vstar(m), 1e-3, None)
        mesh = ax.pcolormesh(xe, ye, v, norm=norm, cmap="viridis", rasterized=True)
        draw_network(ax, seg, fn, fn_max, lw_max=3.0, colour="w")
        draw_bodies(ax, run, k, colour="#ff4040")
        h = cg.height[k]
        ax.set(xlim=(xe[0], xe[-1]), ylim=(max(0, h - 25), min(h + 55, cg.surface[k] + 5)), aspect="equal",
               xlabel="x (mm)", ylabel="height above the floor (mm)")
        state = events.describe(ev, cg.time[k])
        ax.set_title(f"({a}) H = {h:.1f} mm, t = {cg.time[k]:.2f} s\n{state}")
        where.append(f"({a}) {h:.1f} mm, {state}")
    fig.colorbar(mesh, ax=axes[0].tolist(), extend="both", shrink=0.8).set_label("v* = |V|/V (log scale, -)")
    caption = (f"Normal force network (white, width ∝ F_n, widest {fn_max:.0f} N/m; pulloff/run.h5) over the "
               f"coarse-grained speed v* = |V|/V in log scale (cg/cg.h5 /fields; {cg.describe()}) at {len(ks)} "
               f"consecutive snapshots: {'; '.join(where)}.")
    return fig, caption

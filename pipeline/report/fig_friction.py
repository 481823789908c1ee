"""Friction mobilisation μ* = |F_t|/(μ F_n) from friction.h5: on the bed, the
Coulomb cone and the distribution (Fig. 12b, c), the means against height (Fig. 13)."""

import matplotlib.pyplot as plt
import numpy as np

from pipeline.report.bed import draw_bodies, draw_grains, frame
from pipeline.report.common import MM, mark_heights, nearest

CLASSES = [((0,), "grain–grain (bulk)", "0.35"), ((1, 2), "side walls", "#2ca02c"),
           ((3,), "floor", "#1f77b4"), ((4,), "intruder", "#d62728")]


def mobilisation(inp, run, target_mm=34.0):
    m = inp.metrics("friction")
    with inp.h5("friction", "friction.h5") as f:
        snaps = f.read("figure/snapshot")
        heights = f.read("snapshots/height")[snaps] * MM
        i = nearest(heights, target_mm)
        a, b = f.read("figure/start")[i:i + 2]
        c = {n: f.read(f"figure/{n}", slice(a, b)) for n in ("x", "y", "fn", "ft", "mu_star", "partner")}
        hist = {n: f.read(f"histogram/{n}") for n in ("edges", "bulk", "wall")}
    k = int(snaps[i])
    fig, (ax1, ax2, ax3) = plt.subplots(1, 3, figsize=(16, 6.2), constrained_layout=True,
                                        gridspec_kw={"width_ratios": [1.1, 1, 0.8]})
    xy, d = run.grains(k)
    frame(ax1, run, k, top_mm=(xy[:, 1] + d / 2).max() + 3)
    draw_grains(ax1, xy, d, face="0.95", edge="0.8")
    draw_bodies(ax1, run, k)
    order = np.argsort(c["mu_star"])
    sc = ax1.scatter(c["x"][order] * MM, (c["y"][order] - run.floor_y) * MM, c=c["mu_star"][order], s=5,
                     cmap="plasma", vmin=0, vmax=1, lw=0, zorder=3)
    fig.colorbar(sc, ax=ax1, shrink=0.6).set_label("μ* = |F_t| / (μ F_n) (-)")
    ax1.set_title(f"(b) μ* at the contact points, H = {run.heights()[k]:.1f} mm")

    for codes, label, colour in CLASSES:
        sel = np.isin(c["partner"], codes)
        ax2.plot(c["fn"][sel], c["ft"][sel], ".", ms=2.5, color=colour, label=f"{label} ({sel.sum()})")
    fmax = c["fn"].max()
    mus = sorted({m["mu_grain"], m["mu_wall"]})
    for mu in mus:
        ax2.plot([0, fmax], [0, mu * fmax], "k:", [0, fmax], [0, -mu * fmax], "k:", lw=1)
    ax2.text(fmax, mus[-1] * fmax, f" |F_t| = {' / '.join(f'{x:g}' for x in mus)} F_n", va="bottom", ha="right")
    ax2.set(xlabel="normal force F_n (N/m)", ylabel="tangential force F_t (N/m)", title="(c) Coulomb cone")
    ax2.legend(loc="lower left", markerscale=3)

    centres = (hist["edges"][1:] + hist["edges"][:-1]) / 2
    width = np.diff(hist["edges"])
    for n, colour in (("bulk", "0.35"), ("wall", "#2ca02c")):
        ax3.step(centres, hist[n] / max(hist[n].sum(), 1) / width, where="mid", color=colour, label=n)
    ax3.axvline(m["slip_threshold"], color="#d62728", ls="--", lw=1,
                label=f"slip μ* ≥ {m['slip_threshold']:g}: {100 * m['slip_fraction']:.1f} % (mean)")
    ax3.set(xlabel="μ* (-)", ylabel="probability density (-)", title="μ* distribution, every snapshot in the bed")
    ax3.legend(loc="upper left")
    caption = (f"Friction mobilisation at run snapshot {k} (H = {run.heights()[k]:.1f} mm, the stored snapshot "
               f"nearest to {target_mm:g} mm): μ* per contact point on the bed, the (F_n, F_t) cloud with the "
               f"Coulomb lines |F_t| = μ F_n (μ = {', '.join(f'{x:g}' for x in mus)}), and the μ* distribution "
               f"over every snapshot with the intruder in the bed (friction/friction.h5 /figure, /histogram; "
               f"grains from pulloff/run.h5). Mean slip fraction {100 * m['slip_fraction']:.1f} %.")
    return fig, caption


def mean_mu_star(inp):
    m = inp.metrics("friction")
    with inp.h5("friction", "friction.h5") as f:
        h = f.read("snapshots/height") * MM
        snap = {n: f.read(f"snapshots/mean_mu_star_{n}") for n in ("bulk", "wall")}
        lo, hi = f.read("profile/lower") * MM, f.read("profile/upper") * MM
        prof = {n: f.read(f"profile/mean_mu_star_{n}") for n in ("bulk", "wall")}
    fig, ax = plt.subplots(figsize=(8, 5), constrained_layout=True)
    centre = (lo + hi) / 2
    for n, colour, label in (("bulk", "#e377c2", "bulk (grain–grain)"), ("wall", "#2ca02c", "side walls")):
        ax.plot(h, snap[n], ".", ms=2, color=colour, alpha=0.35)
        ax.plot(centre, prof[n], "o-", ms=4, lw=1, color=colour, label=f"{label}, mean per {hi[0] - lo[0]:.0f} mm bin")
    spec = inp.metrics("spectrum")
    mark_heights(ax, [(m.get("critical_height_mm"), f"H_c = {m.get('critical_height_mm', 0):.1f} mm", "k"),
                      (m["lower_band_mm"][1], "top of the lower part", "0.5"),
                      (spec.get("top_layer_height_mm"), "top layer (spectrum)", "#ff7f0e"),
                      (m.get("initial_bed_height_mm"), "initial surface", "#8c564b")])
    ax.axhline(0.24, color="0.3", ls=":", lw=1, label="paper: ≈ 0.24 near the top")
    ax.set(xlabel="intruder height H (mm)", ylabel="mean μ* (-)", ylim=(0, None))
    ax.legend(loc="lower left", ncol=2)
    caption = (f"Mean friction mobilisation μ* of the grain–grain (bulk) and grain–side-wall contacts against "
               f"intruder height: per snapshot (dots) and per height bin (friction/friction.h5 /snapshots, /profile); "
               f"lower-part means {m['mean_mu_star_lower']:.3f} (bulk) / {m['mean_mu_star_lower_wall']:.3f} (walls), "
               f"upper-part {m['mean_mu_star_upper']:.3f} / {m['mean_mu_star_upper_wall']:.3f}.")
    return fig, caption

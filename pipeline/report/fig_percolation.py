"""Percolation of the force network from the intruder to the side walls, and
the fabric anisotropy above the intruder, against height (network.h5)."""

import matplotlib.pyplot as plt

from pipeline.report.common import MM, binned_fraction, fmt, mark_heights

VARIANTS = [("strong", "strong (F_n > mean)", "#d62728", 1.6), ("strong_x0.8", "strong, 0.8 × mean", "#ff9896", 0.9),
            ("strong_x1.2", "strong, 1.2 × mean", "#8c1d1d", 0.9), ("whole", "whole network (F_n > 0)", "k", 1.6)]


def percolation(inp):
    m = inp.metrics("network")
    with inp.h5("network", "network.h5") as f:
        h = f.read("snapshots/height") * MM
        lo, hi = f.read("profile/lower") * MM, f.read("profile/upper") * MM
        perc = {v: f.read(f"percolation/{v}/left") & f.read(f"percolation/{v}/right")
                for v, *_ in VARIANTS if f.has(f"percolation/{v}/left")}
        an = {n: f.read(f"anisotropy/{n}") for n in ("strong", "strong_noise", "strong_debiased", "all")}
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(9, 7.5), sharex=True, constrained_layout=True)
    centre = (lo + hi) / 2
    for v, label, colour, lw in VARIANTS:
        if v in perc:
            ax1.plot(centre, binned_fraction(h, perc[v], lo, hi), "-", drawstyle="steps-mid", color=colour,
                     lw=lw, label=label)
    ax1.plot(h, perc["strong"] + 0.03, "|", ms=4, color="#d62728")
    ax1.plot(h, perc["whole"] - 0.03, "|", ms=4, color="k")
    ax1.set(ylabel="percolating fraction (both walls, -)", ylim=(-0.1, 1.1),
            title="percolation intruder → both side walls, floor excluded (ticks at 0/1: each snapshot's flag)")
    marks = [(m.get("percolation_loss_height_mm"), "percolation loss (strong)", "#d62728"),
             (m.get("top_layer_height_mm"), "top layer", "#ff7f0e"),
             (m.get("initial_bed_height_mm"), "initial surface", "#8c564b")]
    mark_heights(ax1, marks)
    ax1.legend(loc="center left", fontsize=7)

    ax2.plot(h, an["strong"], ".", ms=3, color="#d62728", label="strong contacts")
    ax2.plot(h, an["strong_debiased"], ".", ms=3, color="#ff9896", label="strong, debiased")
    ax2.plot(h, an["strong_noise"], "-", lw=0.8, color="0.5", label="isotropic noise √(π/n)")
    ax2.plot(h, an["all"], ".", ms=3, color="k", label="all grain–grain contacts")
    mark_heights(ax2, marks[1:])
    ax2.set(xlabel="intruder height H (mm)", ylabel="fabric anisotropy 2(λ1−λ2)/(λ1+λ2) (-)",
            title="fabric of the grain–grain contacts above the intruder")
    ax2.legend(loc="upper left", fontsize=7)
    caption = (f"Top: fraction of snapshots per {hi[0] - lo[0]:.0f} mm height bin in which the force network "
               f"connects the intruder to both side walls (strong network at three thresholds and the whole "
               f"network; ticks: per-snapshot flags); percolation loss at "
               f"{fmt(m.get('percolation_loss_height_mm'))}. Bottom: fabric anisotropy above the intruder with the "
               f"isotropic noise level; top layer at {fmt(m.get('top_layer_height_mm'))}, from the "
               f"{m.get('top_layer_source', 'network stage')}. From network/network.h5.")
    return fig, caption

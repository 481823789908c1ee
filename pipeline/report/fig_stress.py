"""Coarse-grained stress from stress.h5 (paper Fig. 5's stress fields): the
pressure and shear maps at a few instants, and the force the stress carries
onto the intruder against the recorded one."""

import matplotlib.pyplot as plt
import numpy as np

from pipeline.report.common import MM, NoData


def maps(inp):
    m = inp.metrics("stress")
    with inp.h5("stress", "stress.h5") as f:
        x, y = f.read("grid/x") * MM, f.read("grid/y") * MM
        snap = f.read("maps/snapshot")
        p, s = f.read("maps/pressure"), f.read("maps/shear")
        left, right, floor = (f.attr(k) * MM for k in ("cell_left", "cell_right", "cell_floor"))
        series_snap, height = f.read("series/snapshot"), f.read("series/body_height") * MM
    if len(snap) == 0:
        raise NoData("stress.h5 keeps no maps (stress.toml: maps = 0)")
    show = [q for q in np.linspace(0, len(snap) - 1, min(4, len(snap))).round().astype(int)]
    fig, axes = plt.subplots(2, len(show), figsize=(3 * len(show), 7), constrained_layout=True, squeeze=False)
    top = max(float(np.nanmax(p[show])), 1e-12)
    stop = max(float(np.nanmax(s[show])), 1e-12)
    inside = (x >= left) & (x <= right)
    rows = y >= floor
    for col, q in enumerate(show):
        k = int(np.searchsorted(series_snap, snap[q]))
        h = height[k] if k < len(height) and m["body_role"] == "intruder" else np.nan
        for row, (field, vmax, label) in enumerate(((p, top, "pressure (Pa)"), (s, stop, "shear (Pa)"))):
            ax = axes[row][col]
            im = ax.imshow(field[q][np.ix_(rows, inside)], origin="lower", vmin=0, vmax=vmax, cmap="magma",
                           extent=(x[inside][0], x[inside][-1], y[rows][0] - floor, y[rows][-1] - floor))
            ax.set_title(f"snapshot {snap[q]}" + (f", H = {h:.0f} mm" if np.isfinite(h) else ""))
            ax.set(xlabel="x (mm)", ylabel="height (mm)" if col == 0 else None)
            if col == len(show) - 1:
                fig.colorbar(im, ax=ax, label=label, shrink=0.8)
    caption = (f"Coarse-grained stress (contact + kinetic, Gaussian kernel w = {m['kernel_w_mm']:.2f} mm, "
               f"branch-integrated): pressure (σ_xx + σ_yy)/2 (top) and shear (bottom) at {len(show)} instants "
               f"(stress/stress.h5 /maps). The bed at rest has a lateral ratio K = σ_xx/σ_yy of "
               f"{m.get('rest_lateral_ratio_at_intruder', float('nan')):.2f} at the intruder.")
    return fig, caption


def force(inp):
    m = inp.metrics("stress")
    c, body = m["force_check"], m["body_role"]
    with inp.h5("stress", "stress.h5") as f:
        h = f.read("series/body_height") * MM
        rec, st = f.read("series/force_recorded")[:, 1], f.read("series/force_stress")[:, 1]
    if c["snapshots_used"] == 0:
        raise NoData(f"no snapshot with a load on the body of role '{body}'")
    fig, ax = plt.subplots(figsize=(8, 4.5), constrained_layout=True)
    ax.plot(h, -rec, ".-", ms=2, lw=0.6, color="0.3", label=f"recorded: the {body}'s contacts")
    ax.plot(h, -st, ".", ms=3, color="#d62728", alpha=0.7, label="from the stress around it (quasi-static)")
    ax.set(xlabel=f"{body} height H (mm)", ylabel=f"downward force on the {body} (N/m)")
    ax.legend(loc="upper right")
    caption = (f"The grains' vertical force on the {body}, recorded (the sum of its contacts' forces) and "
               f"carried by the coarse-grained stress on a box around it plus the weight inside "
               f"(stress/stress.h5 /series). Means over {c['snapshots_used']} snapshots: "
               f"{c['mean_stress_n']:.3g} against {c['mean_recorded_n']:.3g} N/m "
               f"({100 * c['mean_relative_error']:.1f} % ± {100 * c['mean_relative_standard_error']:.1f} %): "
               f"{c['verdict']} at ±{100 * c['tolerance']:.0f} %. Per snapshot they differ by the grains' "
               f"acceleration in the box ({100 * c['inertia_share']:.0f} % of the load).")
    return fig, caption

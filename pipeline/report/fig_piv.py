"""Synthetic PIV beside coarse-graining from piv.h5 (the paper's Fig. 10a
against 10b): |v - V| / V in the intruder's frame at a few instants, the
same colour scale, the nodes both have; and a frame the PIV read."""

import matplotlib.pyplot as plt
import numpy as np

from pipeline.report.common import MM, NoData


def maps(inp):
    m = inp.metrics("piv")
    with inp.h5("piv", "piv.h5") as f:
        snap = f.read("maps/snapshot")
        vp, vc = f.read("maps/vstar_piv"), f.read("maps/vstar_cg")
        x0, y0 = f.read("maps/x0") * MM, f.read("maps/y0") * MM
        left, right, top, centre = (f.read(f"maps/intruder_{k}") * MM for k in ("left", "right", "top", "centre"))
        dx, floor = f.attr("maps_dx") * MM, f.attr("cell_floor") * MM
    if len(snap) == 0:
        raise NoData("piv.h5 keeps no maps (piv.toml: snapshots.maps = 0)")
    show = [q for q in np.linspace(0, len(snap) - 1, min(3, len(snap))).round().astype(int)]
    fig, axes = plt.subplots(2, len(show), figsize=(3.6 * len(show), 6.5), constrained_layout=True, squeeze=False)
    ny, nx = vp.shape[1:]
    for col, q in enumerate(show):
        # the intruder's frame: x from its centre, y from its centre (mm)
        xc = 0.5 * (left[q] + right[q])
        ext = (x0[q] - xc - 0.5 * dx, x0[q] - xc + (nx - 0.5) * dx, y0[q] - centre[q] - 0.5 * dx,
               y0[q] - centre[q] + (ny - 0.5) * dx)
        for row, (field, label) in enumerate(((vp, "synthetic PIV"), (vc, "coarse-grained"))):
            ax = axes[row][col]
            im = ax.imshow(field[q], origin="lower", extent=ext, vmin=0, vmax=1.2, cmap="jet")
            half = top[q] - centre[q]
            ax.add_patch(plt.Rectangle((left[q] - xc, -half), right[q] - left[q], 2 * half, color="k"))
            ax.set_title(f"{label}, H = {centre[q] - floor:.0f} mm", fontsize=9)
            ax.set(xlabel="x - x_intruder (mm)", ylabel="y - y_intruder (mm)" if col == 0 else None)
            if col == len(show) - 1:
                fig.colorbar(im, ax=ax, label="|v - V| / V", shrink=0.8)
    b = m["cone_angle_deg"]
    caption = (f"The velocity in the intruder's frame, |v − V|/V, from synthetic PIV of the rendered front face "
               f"(top: {m['config']['camera']['px_per_diameter']:.0f} px a bead, windows "
               f"{' → '.join(str(w) for w in m['config']['piv']['windows_px'])} px at "
               f"{100 * m['config']['piv']['overlap']:.0f} % overlap, a vector every {m['vector_spacing_d']:.2f} d) "
               f"and coarse-grained from the grains' displacements over the same "
               f"{1e3 * m['frame_interval_s']:.3g} ms (bottom, w = {m['kernel_w_mm']:.2f} mm), same colour scale, "
               f"on the nodes both have (piv/piv.h5 /maps). Over {m['pairs']} pairs the maps differ by "
               f"{m['rms_vstar_difference_intruder_frame']:.2f} rms; the cone angle reads "
               f"{b['piv']['mean']:.1f}° by PIV and {b['cg']['mean']:.1f}° by coarse-graining on the same nodes.")
    return fig, caption


def frame(inp):
    m = inp.metrics("piv")
    frames = sorted(inp.path("piv", "frames").glob("frame_*_b.png")) if inp.path("piv", "frames").is_dir() else []
    if not frames:
        raise NoData("no PNG frame (piv.toml: snapshots.png_frames = 0)")
    img = plt.imread(frames[0])
    fig, ax = plt.subplots(figsize=(7, 7 * img.shape[0] / img.shape[1]), constrained_layout=True)
    ax.imshow(img, cmap="gray")
    ax.set_axis_off()
    caption = (f"A frame the synthetic PIV reads ({frames[0].name}; {img.shape[1]} × {img.shape[0]} px, the "
               f"camera centred on the intruder): glass beads rendered as the paper's camera sees them, "
               f"{m['config']['camera']['px_per_diameter']:.0f} px a mean diameter.")
    return fig, caption

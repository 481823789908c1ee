"""Fig. 6a: the drag profile with its loading/rupture events, trend and top
layer, and the event amplitudes against height (inset)."""

import matplotlib.pyplot as plt
import numpy as np

from pipeline.report.common import MM, band_mm, intruder_depth


def drag_profile(inp, mark_mm=None):
    """mark_mm: the height of the force-network snapshot (Fig. 6b), marked by a red dot."""
    m = inp.metrics("spectrum")
    w = intruder_depth(inp)
    with inp.h5("spectrum", "spectrum.h5") as f:
        h = f.read("profile/height") * MM
        drag, trend = f.read("profile/drag"), f.read("profile/trend")
        ev = {n: f.read(f"events/{n}") for n in ("peak_height", "peak_drag", "drop_end_height", "drop")}
        top_h, top_fit = f.read("top_layer/height") * MM, f.read("top_layer/fit_drag")
    peak_h, drop_h = ev["peak_height"] * MM, ev["drop_end_height"] * MM

    fig, ax = plt.subplots(figsize=(9, 5.2), constrained_layout=True)
    ax.plot(h, drag, lw=0.6, color="#1f5fb4", label="drag (interval mean)")
    ax.plot(h, trend, lw=1.4, color="k", label="trend (running median)")
    ax.plot(peak_h, ev["peak_drag"], "^", ms=3.5, color="#d62728", label=f"event peaks ({len(peak_h)})")
    ax.plot(drop_h, ev["peak_drag"] - ev["drop"], "v", ms=3.5, color="#2ca02c", label="drop ends")
    if len(top_h):
        ax.plot(top_h, top_fit, lw=1.6, color="#ff7f0e", label="top layer: linear fit against depth")
    top = m.get("top_layer_height_mm")
    if top is not None:
        ax.axvspan(top, h[-1], color="#ff7f0e", alpha=0.08, lw=0)
        ax.axvline(top, ls="--", lw=0.9, color="#ff7f0e")
        ax.text(top, 0.3, f" top layer\n {top:.1f} mm", transform=ax.get_xaxis_transform(), fontsize=8)
    bottom = m.get("bottom") or {}
    for key, label in (("first_peak", "bottom peak"), ("collapse", "collapse"), ("next_loading", "new loading")):
        b = bottom.get(key)
        if b:
            ax.annotate(label, (b["height_mm"], b["drag_N_per_m"]), xytext=(8, 4), textcoords="offset points",
                        fontsize=7, arrowprops=dict(arrowstyle="-", lw=0.5))
    if mark_mm is not None:
        k = int(np.argmin(np.abs(h - mark_mm)))
        ax.plot(h[k], drag[k], "o", ms=7, color="red", mec="k", zorder=6, label=f"H = {h[k]:.1f} mm (Fig. 6b)")
    ax.set_xlim(0, h[-1])
    ax.set_ylim(bottom=min(0, drag.min()))
    ax.set_xlabel("intruder height H (mm)")
    ax.set_ylabel("drag (N/m)")
    sec = ax.secondary_yaxis("right", functions=(lambda f: f * w, lambda n: n / w))
    sec.set_ylabel(f"drag × W (N), W = {w * MM:.0f} mm")
    ax.legend(loc="upper right")
    fit_text = _inset(ax, inp, peak_h, ev["drop"])

    caption = (f"Drag on the intruder (N/m, right axis × W = {w * MM:.0f} mm in N) against its height, with the "
               f"spectrum stage's {len(peak_h)} loading/rupture events (peaks, drop ends), the running-median trend "
               f"and the top layer's linear fit (spectrum/spectrum.h5, spectrum/metrics.json); inset: event "
               f"drop against peak height with the linear fit over the upper part ({fit_text}).")
    return fig, caption


def _inset(ax, inp, peak_h, drop):
    """Event amplitude against height, with the fit over the upper band; returns the fit's text."""
    ins = ax.inset_axes([0.36, 0.42, 0.3, 0.36])
    ins.plot(peak_h, drop, ".", ms=3, color="0.3")
    lo, hi = band_mm(inp, "upper")
    fit = inp.metrics("spectrum").get("amplitude_fit_upper") or {}
    text, title = "no fit (fewer than 3 events in the upper part)", "upper part: no fit"
    if fit.get("slope") is not None and np.isfinite(lo):
        sel = (peak_h >= lo) & (peak_h < hi)
        ins.plot(peak_h[sel], drop[sel], ".", ms=4, color="#d62728")
        x = np.array([lo, hi])
        ins.plot(x, fit["intercept"] + fit["slope"] * x, color="#d62728", lw=1.2)
        title = f"upper-part fit: {fit['slope']:.3f} N/m per mm, R² {fit['r2']:.2f}"
        text = f"{lo:.0f}–{hi:.0f} mm, {fit['slope']:.3f} N/m per mm, R² = {fit['r2']:.2f}, {fit['points']} events"
    ins.set_title(title, fontsize=7)
    ins.set_xlabel("peak height (mm)", fontsize=7)
    ins.set_ylabel("drop (N/m)", fontsize=7)
    ins.tick_params(labelsize=7)
    return text

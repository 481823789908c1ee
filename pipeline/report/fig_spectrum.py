"""The drag spectrum: Welch PSD of the drag fluctuation against wavelength
(travel), for the loading/rupture part and per height band."""

import matplotlib.pyplot as plt

from pipeline.report.common import MM

BANDS = [("psd", "loading/rupture part", "k", 1.6),
         ("psd/bands/bottom", "bottom", "#1f77b4", 0.9), ("psd/bands/middle", "middle", "#2ca02c", 0.9),
         ("psd/bands/upper", "upper", "#d62728", 0.9), ("psd/bands/top_layer", "top layer", "#ff7f0e", 0.9)]


def drag_spectrum(inp):
    m = inp.metrics("spectrum")
    fig, ax = plt.subplots(figsize=(7.5, 5), constrained_layout=True)
    notes = []
    with inp.h5("spectrum", "spectrum.h5") as f:
        d_mm = f.attr("mean_diameter_m") * MM
        for group, name, colour, lw in BANDS:
            if not f.has(group):
                notes.append(f"no {name} band")
                continue
            lam, power = f.read(f"{group}/wavelength_d"), f.read(f"{group}/power")
            a = f.f[group].attrs
            lo, hi = a.get("low_m", float("nan")) * MM, a.get("high_m", float("nan")) * MM
            ok = lam > 0
            ax.loglog(lam[ok], power[ok], color=colour, lw=lw, label=f"{name} ({lo:.0f}–{hi:.0f} mm)")
            per = a.get("dominant_period_d")
            if per is not None and per > 0:
                k = abs(lam[ok] - per).argmin()
                sig = bool(a.get("significant", 0))
                ax.plot(per, power[ok][k], "o", ms=6, color=colour, mfc=colour if sig else "none")
    ax.axvline(0.5, color="0.3", ls="--", lw=1)
    ax.text(0.5, 0.02, " d/2 (paper)", transform=ax.get_xaxis_transform(), fontsize=8)
    ax.set_xlabel("wavelength λ (d of travel)")
    ax.set_ylabel("PSD of the drag fluctuation ((N/m)² per cycle per d)")
    sec = ax.secondary_xaxis("top", functions=(lambda x: x * d_mm, lambda x: x / d_mm))
    sec.set_xlabel(f"wavelength (mm of travel), d = {d_mm:.3f} mm")
    ax.legend(loc="lower right", title="band (intruder heights)")
    psd = m.get("psd", {})
    caption = ("Welch power spectral density of the drag fluctuation (drag minus trend) against wavelength in "
               "mean diameters of travel, for the loading/rupture part and each height band "
               f"(spectrum/spectrum.h5); circles mark each band's dominant period (filled only if significant: "
               f"main part {m.get('dominant_period_d', float('nan')):.3f} d, "
               f"{'significant' if m.get('dominant_period_significant') else 'not significant'}; background "
               f"exponent {psd.get('background_exponent', float('nan')):.2f}); the dashed line is the paper's d/2.")
    if notes:
        caption += " Missing: " + ", ".join(notes) + "."
    return fig, caption

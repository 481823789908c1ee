"""The validation figures (matplotlib, headless), from the cases' figure data:
impacts.png (Chung & Ooi), numerics.png (energy error order, stability
limit), bulk.png (Janssen, Beverloo, repose). A panel whose case did not run
is left out."""
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def save(fig, path: Path) -> None:
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def figure_data(results: dict) -> dict:
    out = {}
    for r in results.values():
        out.update(r["figures"])
    return out


def impacts(f: dict, path: Path) -> None:
    panels = [k for k in ("restitution", "oblique_wall", "oblique_pair") if k in f]
    if not panels:
        return
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.2))
    if "restitution" in f:
        ax = axes[0]
        for label in dict.fromkeys(r[0] for r in f["restitution"]):
            pts = np.array([(e, m) for lab, e, m in f["restitution"] if lab == label])
            ax.plot(pts[:, 0], pts[:, 1], "o", ms=4, label=label)
        ax.plot([0, 1], [0, 1], "k-", lw=0.8, label="e' = e")
        ax.set(xlabel="restitution asked, e", ylabel="measured e'", title="C&O 3: restitution")
        ax.legend(fontsize=8)
    if "oblique_wall" in f:
        ax = axes[1]
        rows = [r for r in f["oblique_wall"] if r["test"] in ("4", "5")]
        for mu in sorted({r["mu"] for r in rows}):
            sel = sorted((r for r in rows if r["mu"] == mu), key=lambda r: r["psi"])
            psi = [r["psi"] for r in sel]
            ax.plot(psi, [r["vx"] / r["vt"] for r in sel], "o", ms=4, label=f"dem2d, mu = {mu}")
            ax.plot(psi, [r["ref_vx"] / r["vt"] for r in sel], "-", lw=0.8, label=f"fine-step reference, mu = {mu}")
            ax.plot(psi, [r["rigid_vx"] / r["vt"] for r in sel], "--", lw=0.8, label=f"rigid body, mu = {mu}")
        ax.set(xscale="log", xlabel="incidence psi = v_t / v_n", ylabel="v_t' / v_t",
               title="C&O 4-5: oblique impacts on a wall (e = 0.9)")
        ax.legend(fontsize=7)
    ax = axes[2]
    if "oblique_wall" in f:
        sel = sorted((r for r in f["oblique_wall"] if r["test"] == "6"), key=lambda r: r["w0"])
        ax.plot([r["w0"] for r in sel], [r["vx"] for r in sel], "o", ms=4, label="C&O 6 (wall): dem2d v_t'")
        ax.plot([r["w0"] for r in sel], [r["ref_vx"] for r in sel], "-", lw=0.8, label="fine-step reference")
    for test, marker in (("7", "s"), ("8", "^")):
        sel = sorted((r for r in f.get("oblique_pair", []) if r["test"] == test), key=lambda r: r["w0"])
        if sel:
            ax.plot([r["w0"] for r in sel], [r["vy1"] for r in sel], marker, ms=4, label=f"C&O {test} (pair): dem2d v_1'")
            ax.plot([r["w0"] for r in sel], [r["ref_vy1"] for r in sel], "-", lw=0.8)
    ax.set(xlabel="spin before impact (rad/s)", ylabel="tangential velocity after (m/s)", title="C&O 6-8: spin")
    ax.legend(fontsize=7)
    save(fig, path)


def numerics(f: dict, path: Path) -> None:
    if "elastic_gas" not in f and "stability" not in f:
        return
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    if "elastic_gas" in f:
        div = np.array(sorted(float(k) for k in f["elastic_gas"]))
        err = np.array([f["elastic_gas"].get(int(k), f["elastic_gas"].get(str(int(k)))) for k in div])
        ax = axes[0]
        ax.loglog(1 / div, err, "o-", label="dem2d")
        ax.loglog(1 / div, err[0] * (div[0] / div) ** 2, "k--", lw=0.8, label="slope 2")
        ax.set(xlabel="dt / dt_c", ylabel="largest integration error / kinetic energy", title="elastic gas")
        ax.legend()
    if "stability" in f:
        ax = axes[1]
        for k, (label, limit, below, above) in enumerate(f["stability"]):
            ax.semilogy([0.99, 1.03], [below, min(above, 1e30)], "o-", label=f"{label} ({limit:.3f} dt_c)")
        ax.axvline(1.0, color="k", lw=0.8)
        ax.set(xlabel="dt / stability limit", ylabel="kinetic energy growth over 4000 steps",
               title="dense packing: stability limit")
        ax.legend(fontsize=7)
    save(fig, path)


def bulk(f: dict, path: Path) -> None:
    if not any(k in f for k in ("janssen", "beverloo", "repose")):
        return
    fig, axes = plt.subplots(1, 4, figsize=(20, 4.2))
    if "janssen_stress" in f:
        j, ax = f["janssen_stress"], axes[3]
        depth = 1e3 * np.array(j["depth"])
        ax.plot(depth, j["sigma_yy"], "o-", ms=3, label="sigma_yy, mean across the silo (stage stress)")
        ax.plot(depth, j["janssen"], "-", label="Janssen with the floor loads' M_sat")
        ax.set(xlabel="depth below the surface (mm)", ylabel="vertical stress (Pa)", title="the tallest column's stress")
        k = ax.twinx()
        k.plot(depth, j["K"], "k:", lw=1)
        k.set_ylabel("K = sigma_xx / sigma_yy (dotted)")
        ax.legend(fontsize=8, loc="lower right")
    if "janssen" in f:
        j, ax = f["janssen"], axes[0]
        m = np.linspace(0, max(j["mass"]), 100)
        ax.plot(j["mass"], j["floor"], "o", label="dem2d (floor sinking at 1 mm/s)")
        ax.plot(m, j["m_sat"] * (1 - np.exp(-m / j["m_sat"])), "-", label=f"Janssen, M_sat = {j['m_sat']:.3g} kg/m")
        ax.plot(m, m, "k:", lw=0.8, label="hydrostatic")
        ax.set(xlabel="mass in the silo (kg/m)", ylabel="mass the floor carries (kg/m)", title="Janssen (W = 60 mm)")
        ax.legend(fontsize=8)
    if "beverloo" in f:
        b, ax = f["beverloo"], axes[1]
        dd = np.array(b["outlet"])
        ax.plot(1e3 * dd, b["rate"], "o", label="dem2d")
        x = np.linspace(dd.min(), dd.max(), 100)
        c = np.polyfit(np.log(dd - b["k"] * 3e-3), np.log(b["rate"]), 1)
        ax.plot(1e3 * x, np.exp(np.polyval(c, np.log(x - b["k"] * 3e-3))), "-",
                label=f"(D - {b['k']:.2f} d)^{b['exponent']:.2f}")
        ax.set(xlabel="outlet width D (mm)", ylabel="discharge (kg/m/s)", title="Beverloo 2D")
        ax.legend(fontsize=8)
    if "repose" in f:
        ax = axes[2]
        rows = f["repose"]
        mu_sweep = sorted((mu, a) for mu, rr, a in rows if rr == 0.1)
        rr_sweep = sorted((rr, a) for mu, rr, a in rows if mu == 0.5)
        ax.plot([m for m, a in mu_sweep], [a for m, a in mu_sweep], "o-", label="against mu (mu_r/r = 0.1)")
        ax.plot([r for r, a in rr_sweep], [a for r, a in rr_sweep], "s-", label="against mu_r/r (mu = 0.5)")
        ax.set(xlabel="mu, or mu_r/r", ylabel="angle of repose (deg)", title="heap on a fixed base")
        ax.legend(fontsize=8)
    save(fig, path)


def detectors(f: dict, path: Path) -> None:
    """One panel per detector: each judged case's bias over its tolerance against the noise (error bar: the
    replicas' sd), the definitions before in grey; cases with nothing planted as the fraction of replicas that
    found something over the fraction allowed. Inside the band |y| <= 1 a case passes."""
    rows = f.get("planted")
    if not rows:
        return
    names = list(dict.fromkeys(r["detector"] for r in rows))
    cols = min(4, len(names))
    fig, axes = plt.subplots((len(names) + cols - 1) // cols, cols, figsize=(4.2 * cols, 3.4 * ((len(names) + cols - 1) // cols)),
                             squeeze=False)
    for ax, name in zip(axes.flat, names):
        mine = [r for r in rows if r["detector"] == name]
        levels = sorted({r["noise"] for r in mine})
        x = {v: i for i, v in enumerate(levels)}
        cases = list(dict.fromkeys(r["case"] for r in mine))
        for c, case in enumerate(cases):
            pts = [r for r in mine if r["case"] == case]
            dx = 0.6 * (c / max(1, len(cases) - 1) - 0.5) if len(cases) > 1 else 0.0
            for r in pts:
                if r["planted"] is None:
                    y = (r["found"] / r["replicas"]) / max(r["max_false"], 1e-9)
                    ax.plot(x[r["noise"]] + dx, min(y, 3.0), "v", color="C3" if r["judged"] else "0.6", ms=5)
                elif r["mean"] is not None:
                    t = max(r["tolerance"], 1e-12)
                    ax.errorbar(x[r["noise"]] + dx, (r["mean"] - r["planted"]) / t, yerr=(r["sd"] or 0.0) / t,
                                fmt="o" if r["judged"] else "s", ms=3.5, mfc="C0" if r["judged"] else "none",
                                color="C0" if r["judged"] else "0.6", lw=0.8)
        ax.axhspan(-1, 1, color="C2", alpha=0.12, lw=0)
        ax.axhline(0, color="k", lw=0.6)
        ax.set_xticks(range(len(levels)), [f"{v:g}" for v in levels])
        ax.set_xlabel(f"noise ({mine[0]['noise_unit']})", fontsize=8)
        ax.set_ylabel("bias / tolerance;  ▼ found / allowed", fontsize=8)
        ax.set_ylim(-3.2, 3.2)
        ax.set_title(name, fontsize=9)
    for ax in list(axes.flat)[len(names):]:
        ax.axis("off")
    fig.suptitle("Planted truth: green band = within tolerance; grey = the definitions before (for comparison)",
                 fontsize=10)
    save(fig, path)


def draw(results: dict, out: Path) -> None:
    f = figure_data(results)
    impacts(f, out / "impacts.png")
    numerics(f, out / "numerics.png")
    bulk(f, out / "bulk.png")
    detectors(f, out / "detectors.png")

"""Bulk behaviour against established laws: Janssen's saturation of the
load on a silo's floor, Beverloo's 2D discharge law, and the angle of
repose of a heap against sliding and rolling friction. Grains: the paper's glass,
d uniform in [2, 4] mm, k_n = 1.92e6 N/m (preset fast: the bulk laws do not
depend on the stiffness), dt = dt_c/20."""
import math

import numpy as np
from dem2d.measure import heap_angle

from pipeline.validate.checks import Check
from pipeline.validate.runner import DENSITY, glass_contact, run

G = 9.81
KN = 1.92e6
D_MIN, D_MAX, D_MEAN = 2e-3, 4e-3, 3e-3


def law(mu=0.5, mu_r=0.0):
    out = glass_contact(KN, 0.9, mu)
    if mu_r > 0.0:
        out.update(rolling_friction=mu_r, rolling_stiffness=D_MEAN * D_MEAN * KN * 1e-4)
    return out


def scene(name, n, region, bodies, duration, mu=0.5, mu_r=0.0, seed=1, stop=None, domain=None, output=None,
          cohesion=None):
    """cohesion: (f_c in N/m, delta_c in m), or None."""
    effects = {"gravity": True, "normal_damping": True, "friction": True, "walls": True}
    if mu_r > 0.0:
        effects["rolling_resistance"] = True
    if cohesion:
        effects["cohesion"] = True
    xs, ys = [p[0] for p in region], [p[1] for p in region]
    s = {"name": name, "effects": effects, "gravity": {"g": [0.0, -G]}, "material": {"density": DENSITY},
         "contact": law(mu, mu_r), "time": {"duration": duration, "dt_over_critical": 0.05},
         "domain": domain or {"xmin": min(xs) - 0.05, "xmax": max(xs) + 0.05, "ymin": -0.05, "ymax": max(ys) + 0.05},
         "output": output or {"series_interval": 0.01},
         "generator": [{"kind": "triangular_lattice", "count": n, "seed": seed,
                        "diameter": {"min": D_MIN, "max": D_MAX}, "region": region}],
         "body": bodies}
    if cohesion:
        s["contact"].update(cohesion_force=cohesion[0], cohesion_range=cohesion[1])
    if stop:
        s["stop"] = stop
    return s


def wall(name, a, b, t=2e-3, **extra):
    return {"name": name, "a": list(a), "b": list(b), "thickness": t, **extra}


def janssen(ctx) -> list:
    """A silo of width W = 60 mm (20 d) (walls' friction mu_w = 0.5) filled with N
    grains whose floor sinks slowly (1 mm/s, as the piston of Janssen tests:
    the walls' friction is then fully mobilised), the floor's load averaged
    over the last 0.4 s: it carries M_app of the mass M. Janssen: M_app =
    M_sat (1 - exp(-M/M_sat)) with M_sat = rho_b W^2 / (2 K mu_w); K between
    Rankine's active and passive values for the grains' friction angle."""
    width, mu_w, sink, duration = 0.06, 0.5, 1e-3, 1.4
    loads = []
    for n in ctx.config["janssen"]["grains"]:
        height = n * D_MAX * D_MAX / width * 1.3 + 0.01
        region = [[0.0, 0.0], [width, 0.0], [width, height], [0.0, height]]
        bodies = [wall("floor", (-1e-3, -1e-3), (width + 1e-3, -1e-3), velocity=[0.0, -sink], role="floor"),
                  wall("left", (-1e-3, -0.01), (-1e-3, height + 0.01), role="left_wall"),
                  wall("right", (width + 1e-3, -0.01), (width + 1e-3, height + 0.01), role="right_wall")]
        s = scene("janssen", n, region, bodies, duration)
        s["effects"]["moving_bodies"] = True
        r = run(ctx.dem2d, s, ctx.out / "bulk" / f"janssen_{n}")
        mass = float(r.read("particles/mass").sum())
        t, f = r.read("series/time"), r.read("series/body_force_mean")[:, 0, 1]
        floor = -float(f[t > duration - 0.4].mean()) / G  # kg/m the floor carries
        top = float(np.sort(r.read("snapshots/position")[-1][:, 1])[-max(3, n // 50):].mean())
        loads.append((mass, floor, top))
    m, m_app, top = (np.array(v) for v in zip(*loads))
    # one-parameter fit of M_sat (grid, then refined): least squares on M_app
    grid = np.geomspace(0.2 * m.max(), 20 * m.max(), 4000)
    err = [np.sum((m_app - ms * (1 - np.exp(-m / ms))) ** 2) for ms in grid]
    m_sat = float(grid[int(np.argmin(err))])
    fit = m_sat * (1 - np.exp(-m / m_sat))
    rms = float(np.sqrt(np.mean(((m_app - fit) / m_app) ** 2)))
    rho_b = float(m[-1] / (width * top[-1]))  # the tallest column's bulk density (kg/m^3)
    k = rho_b * width ** 2 / (2 * mu_w * m_sat)
    ctx.figures["janssen"] = {"mass": m.tolist(), "floor": m_app.tolist(), "m_sat": m_sat, "width": width, "rho_b": rho_b,
                              "tallest_run": str(ctx.out / "bulk" / f"janssen_{ctx.config['janssen']['grains'][-1]}"),
                              "tallest_top": float(top[-1])}
    phi = math.atan(0.5)  # grains' friction angle: Rankine's bounds of K
    ka, kp = (1 - math.sin(phi)) / (1 + math.sin(phi)), (1 + math.sin(phi)) / (1 - math.sin(phi))
    case = f"Janssen: {len(m)} fills of a {1e3 * width:.0f} mm silo (mu_w = {mu_w})"
    return [Check(case, "rms deviation of the floor loads from Janssen's curve", 0.05, rms, 0.0, kind="below",
                  reference="M_app = M_sat (1 - exp(-M/M_sat))"),
            Check(case, "share of the tallest column's weight on the floor", 0.7, float(m_app[-1] / m[-1]), 0.0,
                  kind="below", reference="saturation: the walls carry the rest"),
            Check(case, "Janssen's K (from M_sat and the bulk density) >= Rankine active", ka, k, 0.0, kind="above",
                  reference=f"(1 - sin phi)/(1 + sin phi), tan phi = 0.5"),
            Check(case, "Janssen's K <= Rankine passive", kp, k, 0.0, kind="below",
                  reference="(1 + sin phi)/(1 - sin phi)")]


def beverloo(ctx) -> list:
    """A flat-bottomed silo (100 mm wide) of 1200 grains, settled on a gate
    that is removed at 0.6 s; grains leaving through the outlet of width D
    leave the domain (and are recorded): the discharge rate from the steady
    part. Beverloo in 2D: W = C rho_2D sqrt(g) (D - k d)^(3/2), k ~ 1-2."""
    width, n = 0.1, 1200
    rates = []
    for ratio in ctx.config["beverloo"]["outlet_over_d"]:
        outlet = ratio * D_MEAN
        half = outlet / 2
        height = 0.2
        region = [[0.0, 0.0], [width, 0.0], [width, height], [0.0, height]]
        x0 = width / 2
        bodies = [wall("bottom_left", (-1e-3, -1e-3), (x0 - half - 1e-3, -1e-3)),
                  wall("bottom_right", (x0 + half + 1e-3, -1e-3), (width + 1e-3, -1e-3)),
                  wall("gate", (x0 - half - 2e-3, -3.2e-3), (x0 + half + 2e-3, -3.2e-3), remove_at=0.6),
                  wall("left", (-1e-3, -1e-3), (-1e-3, height + 0.01)),
                  wall("right", (width + 1e-3, -1e-3), (width + 1e-3, height + 0.01))]
        s = scene("beverloo", n, region, bodies, 0.6 + ctx.config["beverloo"]["discharge_s"],
                  domain={"xmin": -0.02, "xmax": width + 0.02, "ymin": -0.02, "ymax": height + 0.02},
                  output={"snapshot_interval": 0.1})
        r = run(ctx.dem2d, s, ctx.out / "bulk" / f"beverloo_{ratio}")
        lost = r.read("lost/step") * float(r.attr("dt"))
        mass = r.read("particles/mass")[r.read("lost/id")]
        order = np.argsort(lost)
        t, out = lost[order], np.cumsum(mass[order])
        total = float(r.read("particles/mass").sum())
        steady = (out > 0.1 * total) & (out < 0.5 * total)
        rate = float(np.polyfit(t[steady], out[steady], 1)[0]) if steady.sum() > 10 else float("nan")
        rates.append((outlet, rate))
    dd, w = (np.array(v) for v in zip(*rates))
    # W^(2/3) is linear in D: D - k d from the intercept; then the exponent with k fixed
    slope, intercept = np.polyfit(dd, w ** (2.0 / 3.0), 1)
    k = -intercept / slope / D_MEAN
    n_exp = float(np.polyfit(np.log(dd - k * D_MEAN), np.log(w), 1)[0])
    rho_2d = 0.82 * DENSITY  # the packing's areal density (Phi ~ 0.82)
    c = float(slope ** 1.5 / (rho_2d * math.sqrt(G)))
    ctx.figures["beverloo"] = {"outlet": dd.tolist(), "rate": w.tolist(), "k": k, "exponent": n_exp, "c": c}
    case = f"Beverloo: discharge of {n} grains through {len(dd)} outlets, D/d = {dd.min() / D_MEAN:.0f}-{dd.max() / D_MEAN:.0f}"
    return [Check(case, "exponent of D - k d", 1.5, n_exp, 0.15, kind="abs", reference="Beverloo 2D: 3/2"),
            Check(case, "k (outlet reduction, grain diameters)", 1.5, float(k), 0.75, kind="abs",
                  reference="k ~ 1-2 (2D disks, e.g. Mankoc et al. 2007)"),
            Check(case, "C (with Phi = 0.82)", 0.8, c, 0.5, kind="abs", reference="C ~ 0.5-1 in 2D")]


def repose(ctx) -> list:
    """The fixed-base heap: 400 grains settled in a box as wide as its 100 mm
    base, whose side walls are then taken away (at 0.8 s): the grains run off
    the base's edges and out of the domain, and what stays on the base
    stands at the angle of repose. Its angle: lines fitted to both flanks of
    the free surface between 20 % and 80 % of the heap's height, averaged
    over a few grain arrangements (seeds). Sliding and
    rolling friction both raise it (Zhou et al. 2001, Phys. Rev. E 64,
    021301; PFC2D's rolling-resistance examples). Without rolling resistance
    disks roll off a smooth base and leave no heap (0 deg, measured).
    Cohesion (a case [mu, mu_r/r, Bo]: pull-off force f_c = Bo m g of a mean
    grain, range delta_c = 0.05 d) holds a steeper heap than the dry one."""
    n, base = 400, 0.1
    angles = {}
    weight = DENSITY * math.pi * D_MEAN ** 2 / 4 * G  # N/m
    for mu, mu_r_over_r, *bond in ctx.config["repose"]["cases"]:
        bond = bond[0] if bond else 0.0
        cohesion = (bond * weight, 0.05 * D_MEAN) if bond > 0.0 else None
        height = 0.08
        region = [[-base / 2, 0.0], [base / 2, 0.0], [base / 2, height], [-base / 2, height]]
        bodies = [wall("base", (-base / 2, -1e-3), (base / 2, -1e-3)),
                  wall("left", (-base / 2 - 1e-3, 0.0), (-base / 2 - 1e-3, height + 0.01), remove_at=0.8),
                  wall("right", (base / 2 + 1e-3, 0.0), (base / 2 + 1e-3, height + 0.01), remove_at=0.8)]
        s = scene("repose", n, region, bodies, 5.0, mu=mu, mu_r=mu_r_over_r * D_MEAN / 2,
                  stop={"kinetic_energy_per_grain_below": 1e-10, "check_interval": 0.02, "min_time": 1.2},
                  domain={"xmin": -0.2, "xmax": 0.2, "ymin": -0.02, "ymax": 0.12},
                  output={"snapshot_interval": 5.0}, cohesion=cohesion)
        seeds = []
        for seed in ctx.config["repose"]["seeds"]:  # one heap's angle scatters by ~1 deg (sd of 6 seeds)
            s["generator"][0]["seed"] = seed
            tag = f"_bond{bond}" if bond else ""
            r = run(ctx.dem2d, s, ctx.out / "bulk" / f"repose_{mu}_{mu_r_over_r}{tag}_{seed}")
            active = r.read("snapshots/active")[-1] > 0
            pos = r.read("snapshots/position")[-1][active]
            seeds.append(heap_angle(pos[pos[:, 1] > 0], D_MEAN))
        angles[(mu, mu_r_over_r, bond)] = float(np.mean(seeds))
    ctx.figures["repose"] = [(mu, rr, a) for (mu, rr, bo), a in angles.items() if bo == 0.0]
    checks = []
    case = "angle of repose of a heap on a fixed base"
    ref = "Zhou et al. 2001: rises with mu and mu_r"
    rr0 = ctx.config["repose"]["mu_sweep_at_mu_r_over_r"]
    mus = sorted(mu for mu, rr, bo in angles if rr == rr0 and bo == 0.0)
    for lo, hi in zip(mus, mus[1:]):
        checks.append(Check(case, f"rises with mu: {hi} against {lo} (mu_r/r = {rr0}), deg", angles[(lo, rr0, 0.0)],
                            angles[(hi, rr0, 0.0)], 0.0, "deg", "above", ref))
    rolls = sorted(rr for mu, rr, bo in angles if mu == 0.5 and bo == 0.0)
    for lo, hi in zip(rolls, rolls[1:]):
        checks.append(Check(case, f"rises with mu_r/r: {hi} against {lo} (mu = 0.5), deg", angles[(0.5, lo, 0.0)],
                            angles[(0.5, hi, 0.0)], 0.0, "deg", "above", ref))
    # a cohesive heap stands steeper than the dry one, by more than one heap's scatter (~1 deg)
    for (mu, rr, bo), a in angles.items():
        if bo > 0.0 and (mu, rr, 0.0) in angles:
            checks.append(Check(case, f"cohesion (Bond number {bo}) against dry (mu = {mu}, mu_r/r = {rr}), deg",
                                angles[(mu, rr, 0.0)] + 1.0, a, 0.0, "deg", "above",
                                "cohesion steepens a heap (e.g. Nase et al. 2001; Luding 2008)"))
    return checks

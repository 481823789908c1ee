"""The particle-impact benchmarks of Chung & Ooi (2011, Granular Matter 13,
643), adapted to disks with the linear spring-dashpot law: each impact is a
scene run with dem2d, compared with the analytic solution of the law (normal
impacts), the rigid-body solution where it holds (gross sliding), and an
independent fine-step integration of the same law (impact_ode.py).

Disks are the paper's glass (rho = 2500 kg/m^3, d = 3 mm unless said),
k_n = 1.92e7 N/m (the default preset), k_t = k_n/2, dt = dt_c/200."""
import math

import numpy as np

from pipeline.validate.checks import Check
from pipeline.validate.impact_ode import impact
from pipeline.validate.runner import disk_mass, glass_contact, run

KN = 1.92e7
D = 3e-3
KAPPA = 2.0  # m r^2 / I of a disk


def base_scene(name: str, laws: dict, particles: list, duration: float, dt: float, walls: list = (),
               damped: bool = True, friction: bool = True, series: bool = False) -> dict:
    effects = {"normal_damping": damped, "friction": friction, "walls": bool(walls)}
    scene = {"name": name, "effects": {k: v for k, v in effects.items() if v}, "material": {"density": 2500},
             "contact": laws, "time": {"duration": duration, "dt": dt},
             "domain": {"xmin": -0.1, "xmax": 0.1, "ymin": -0.1, "ymax": 0.1},
             "output": {"snapshot_interval": duration},
             "particle": particles}
    if series:
        scene["output"]["series_interval"] = dt
    if walls:
        scene["body"] = list(walls)
    return scene


def law(e: float, mu: float = 0.5, kn: float = KN, damped: bool = True, friction: bool = True) -> dict:
    full = glass_contact(kn, e, mu)
    keep = ["kn"] + (["restitution"] if damped else []) + (["kt", "friction"] if friction else [])
    return {k: full[k] for k in keep}


FLOOR = {"name": "floor", "a": [-1.0, -1e-3], "b": [1.0, -1e-3], "thickness": 2e-3}  # face at y = 0


def dt_for(d_min: float, kn: float) -> float:
    return math.sqrt(disk_mass(d_min) / kn) / 200.0


def contact_time(kn: float, meff: float) -> float:
    return math.pi * math.sqrt(meff / kn)


def final(r) -> tuple:
    v, w = r.read("snapshots/velocity")[-1], r.read("snapshots/omega")[-1]
    return v, w


def normal(ctx) -> list:
    """C&O 1 (equal disks, elastic), 2 (disk on walls of two stiffnesses,
    elastic) and 3 (restitution over e, equal and unequal disks and walls)."""
    checks = []
    cases = [("1: normal impact of equal disks", "1_equal", D, D, KN, False),
             ("1: normal impact of unequal disks (2 and 4 mm)", "1_unequal", 2e-3, 4e-3, KN, False),
             ("2: normal impact on a wall, k_wall = k_n", "2_wall", D, None, KN, True),
             ("2: normal impact on a stiffer wall, k_wall = 4 k_n", "2_stiff_wall", D, None, 4 * KN, True)]
    for name, slug, d1, d2, kw, on_wall in cases:
        v = 0.2
        m1 = disk_mass(d1)
        meff = m1 if on_wall else m1 * disk_mass(d2) / (m1 + disk_mass(d2))
        k = kw
        tc = contact_time(k, meff)
        dt = dt_for(min(d1, d2 or d1), k)
        if on_wall:
            parts = [{"x": 0.0, "y": d1 / 2, "d": d1, "vy": -v}]
            laws = law(1.0, kn=KN, damped=False, friction=False)
            laws["wall"] = {"kn": kw}
            scene = base_scene("normal_wall", laws, parts, 2.0 * tc, dt, [FLOOR], damped=False, friction=False, series=True)
            vrel = v
        else:
            parts = [{"x": -d1 / 2, "y": 0.0, "d": d1, "vx": v}, {"x": d2 / 2, "y": 0.0, "d": d2, "vx": -v}]
            scene = base_scene("normal_pair", law(1.0, damped=False, friction=False), parts, 2.0 * tc, dt, damped=False,
                               friction=False, series=True)
            vrel = 2 * v
        r = run(ctx.dem2d, scene, ctx.out / "impacts" / slug)
        touching = r.read("series/contacts") > 0
        duration = touching.sum() * dt
        case = f"Chung & Ooi {name}"
        checks.append(Check(case, "contact duration", tc, duration, 0.01, "s", reference="pi sqrt(m_eff/k)"))
        dmax = vrel * math.sqrt(meff / k)
        checks.append(Check(case, "largest overlap", dmax, float(r.read("series/max_overlap").max()), 0.005, "m",
                            reference="v_rel sqrt(m_eff/k)"))
        if on_wall:
            fmax = float(np.abs(r.read("series/body_force")[:, 0, 1]).max())
            checks.append(Check(case, "largest force", k * dmax, fmax, 0.005, "N/m", reference="k v sqrt(m/k)"))
        v_after, _ = final(r)
        rebound = (v_after[0, 1] / v) if on_wall else (v_after[1, 0] - v_after[0, 0]) / vrel
        checks.append(Check(case, "restitution (elastic)", 1.0, rebound, 1e-4, reference="energy conserved"))
    # C&O 3: restitution over e
    ctx.figures["restitution"] = []
    for label, d1, d2 in (("equal disks", D, D), ("unequal disks (2 and 4 mm)", 2e-3, 4e-3), ("disk on a wall", D, None)):
        for e in ctx.config["impacts"]["restitutions"]:
            m1 = disk_mass(d1)
            meff = m1 if d2 is None else m1 * disk_mass(d2) / (m1 + disk_mass(d2))
            tc = contact_time(KN, meff)
            dt = dt_for(min(d1, d2 or d1), KN) / 4.0  # dt_c/800: the dashpot's half-step velocity errs by O(dt)
            if d2 is None:
                scene = base_scene("restitution", law(e, friction=False), [{"x": 0.0, "y": d1 / 2, "d": d1, "vy": -0.2}],
                                   3.0 * tc, dt, [FLOOR], friction=False)
            else:
                scene = base_scene("restitution", law(e, friction=False),
                                   [{"x": -d1 / 2, "y": 0.0, "d": d1, "vx": 0.2}, {"x": d2 / 2, "y": 0.0, "d": d2}],
                                   3.0 * tc, dt, friction=False)
            r = run(ctx.dem2d, scene, ctx.out / "impacts" / "3" / f"{label.split()[0]}_{e}")
            v_after, _ = final(r)
            measured = v_after[0, 1] / 0.2 if d2 is None else (v_after[1, 0] - v_after[0, 0]) / 0.2
            checks.append(Check(f"Chung & Ooi 3: restitution, {label}", f"e' for e = {e}", e, measured, 0.005,
                                reference="scene's e"))
            ctx.figures["restitution"].append((label, e, measured))
    return checks


def rigid_body(u0: float, vn: float, e: float, mu: float, meff_over_m1: float = 1.0):
    """Impulses of a rigid-body impact (Coulomb friction, restitution e):
    the change of disk 1's tangential velocity and spin (times r), given the
    contact point's tangential velocity u0 and the normal approach speed vn.
    Gross sliding throughout iff |u0| >= mu (1 + e) vn (1 + kappa)."""
    jn = meff_over_m1 * (1.0 + e) * vn  # normal impulse / m1
    sliding = abs(u0) >= mu * (1.0 + e) * vn * (1.0 + KAPPA)
    jt = -math.copysign(mu * jn, u0) if sliding else -u0 * meff_over_m1 / (1.0 + KAPPA)
    return jt, KAPPA * jt, sliding


def oblique_wall(ctx) -> list:
    """C&O 4 (constant speed, incident angle swept), 5 (constant normal speed,
    tangential speed swept) and 6 (spin swept): a disk on a wall. dem2d
    against the fine-step reference; against rigid-body theory where it
    holds (gross sliding throughout)."""
    checks = []
    cfg = ctx.config["impacts"]
    e = cfg["oblique_restitution"]
    r = D / 2
    rows = []
    sweeps = []
    for mu in cfg["oblique_friction"]:
        for angle in cfg["angles_deg"]:
            v = 0.2
            sweeps.append(("4", mu, v * math.sin(math.radians(angle)), v * math.cos(math.radians(angle)), 0.0,
                           f"angle {angle} deg"))
        for vt in cfg["tangential_speeds"]:
            sweeps.append(("5", mu, vt, 0.1, 0.0, f"v_t = {vt} m/s"))
    for w0 in cfg["spins_rad_s"]:
        sweeps.append(("6", cfg["spin_friction"], 0.05, 0.1, w0, f"omega = {w0} rad/s"))
    dt = dt_for(D, KN)
    tc = contact_time(KN, disk_mass(D))
    for test, mu, vt, vn, w0, label in sweeps:
        laws = law(e, mu)
        scene = base_scene("oblique", laws, [{"x": 0.0, "y": r, "d": D, "vx": vt, "vy": -vn, "omega": w0}],
                           3.0 * tc, dt, [FLOOR])
        run_ = run(ctx.dem2d, scene, ctx.out / "impacts" / test / f"mu{mu}_{label.replace(' ', '_').replace('=', '')}")
        v_after, w_after = final(run_)
        vx, vy, w = float(v_after[0, 0]), float(v_after[0, 1]), float(w_after[0])
        ref_v, ref_w, _, _ = impact(D, (vt, -vn), w0, {**laws, "restitution": e})
        u0 = vt + w0 * r
        jt, jw, sliding = rigid_body(u0, vn, e, mu)
        case = f"Chung & Ooi {test}: oblique impact on a wall, mu = {mu}"
        # the engine's dashpot sees the half-step velocity: first order in dt,
        # measured <= 0.1 % of the impact's speed scale at dt_c/200
        scale = max(abs(vt), vn, abs(w0) * r)
        checks.append(Check(case, f"{label}: v_t' (fine-step reference)", ref_v[0], vx, 2e-3 * scale, "m/s", "abs",
                            "the same law integrated at t_c/4000"))
        checks.append(Check(case, f"{label}: omega' r (fine-step reference)", ref_w * r, w * r, 2e-3 * scale, "m/s",
                            "abs", "the same law integrated at t_c/4000"))
        if sliding:
            checks.append(Check(case, f"{label}: v_t' (rigid body, sliding)", vt + jt, vx, 1e-2 * scale, "m/s",
                                "abs", "v_t - mu (1+e) v_n"))
            checks.append(Check(case, f"{label}: omega' r (rigid body, sliding)", w0 * r + jw, w * r, 1e-2 * scale,
                                "m/s", "abs", "omega r - kappa mu (1+e) v_n"))
        rows.append({"test": test, "mu": mu, "psi": u0 / vn, "vt": vt, "vn": vn, "w0": w0, "vx": vx, "vy": vy, "w": w,
                     "ref_vx": float(ref_v[0]), "ref_w": float(ref_w), "rigid_vx": vt + jt, "rigid_w": w0 + jw / r,
                     "sliding": sliding})
    ctx.figures["oblique_wall"] = rows
    return checks


def oblique_pair(ctx) -> list:
    """C&O 7 (equal disks) and 8 (unequal disks, 2 and 4 mm): head-on along
    x at a constant normal speed, spins swept."""
    checks = []
    cfg = ctx.config["impacts"]
    e, mu = cfg["oblique_restitution"], cfg["spin_friction"]
    rows = []
    for test, d1, d2 in (("7", D, D), ("8", 2e-3, 4e-3)):
        m1, m2 = disk_mass(d1), disk_mass(d2)
        meff = m1 * m2 / (m1 + m2)
        dt = dt_for(min(d1, d2), KN)
        tc = contact_time(KN, meff)
        for w0 in cfg["spins_rad_s"]:
            v = 0.1
            laws = law(e, mu)
            scene = base_scene("pair", laws, [{"x": -d1 / 2, "y": 0.0, "d": d1, "vx": v, "omega": w0},
                                              {"x": d2 / 2, "y": 0.0, "d": d2, "vx": -v, "omega": w0}], 3.0 * tc, dt)
            run_ = run(ctx.dem2d, scene, ctx.out / "impacts" / test / f"w{w0}")
            v_after, w_after = final(run_)
            ref1, refw1, ref2, refw2 = impact(d1, (v, 0.0), w0, {**laws, "restitution": e}, d2, (-v, 0.0), w0)
            case = f"Chung & Ooi {test}: {'equal' if d1 == d2 else 'unequal'} disks with spin, mu = {mu}"
            scale = 2e-3 * max(2 * v, abs(w0) * max(d1, d2) / 2)  # as for the wall: first order, <= 0.1 %
            checks.append(Check(case, f"omega = {w0} rad/s: v_y' of disk 1 (fine-step reference)", ref1[1],
                                float(v_after[0, 1]), scale, "m/s", "abs", "the same law integrated at t_c/4000"))
            checks.append(Check(case, f"omega = {w0} rad/s: omega_1' r_1 (fine-step reference)", refw1 * d1 / 2,
                                float(w_after[0]) * d1 / 2, scale, "m/s", "abs", "the same law integrated at t_c/4000"))
            checks.append(Check(case, f"omega = {w0} rad/s: omega_2' r_2 (fine-step reference)", refw2 * d2 / 2,
                                float(w_after[1]) * d2 / 2, scale, "m/s", "abs", "the same law integrated at t_c/4000"))
            # rigid body: contact point's relative tangential velocity u0 = r1 w1 + r2 w2 (along y)
            u0 = w0 * (d1 + d2) / 2
            jt, _, sliding = rigid_body(u0, 2 * v, e, mu, meff / m1)
            if sliding:
                checks.append(Check(case, f"omega = {w0} rad/s: v_y' of disk 1 (rigid body, sliding)", jt,
                                    float(v_after[0, 1]), 5 * scale, "m/s", "abs", "-mu (1+e) m_eff v_rel / m_1"))
            rows.append({"test": test, "w0": w0, "psi": u0 / (2 * v), "vy1": float(v_after[0, 1]), "ref_vy1": float(ref1[1]),
                         "rigid_vy1": jt, "sliding": sliding})
    ctx.figures["oblique_pair"] = rows
    return checks

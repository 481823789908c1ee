"""Single grains against rigid-body mechanics, and a pile at rest against
statics: slide-to-roll, rolling down an incline with and without rolling
resistance, and the force balance of a settled pile. The paper's glass disks
(d = 3 mm) and law at k_n = 1.92e7 N/m; gravity 9.81 m/s^2."""
import math

import numpy as np

from pipeline.validate.checks import Check
from pipeline.validate.runner import disk_mass, glass_contact, run

G = 9.81
KN = 1.92e7
D = 3e-3
FLOOR = {"name": "floor", "a": [-1.0, -1e-3], "b": [1.0, -1e-3], "thickness": 2e-3}  # face at y = 0


def disk_on_floor(name, duration, vx=0.0, omega=0.0, tilt_deg=0.0, mu_r=None, snapshots=1e-4, mu=0.5):
    """A disk resting on the floor (at its static overlap), gravity tilted by
    tilt_deg (an incline of that angle, down the slope = +x)."""
    effects = {"gravity": True, "normal_damping": True, "friction": True, "walls": True}
    law = glass_contact(KN, 0.9, mu)
    if mu_r is not None:
        effects["rolling_resistance"] = True
        law.update(rolling_friction=mu_r, rolling_stiffness=D * D * KN * 1e-4)
    a = math.radians(tilt_deg)
    gx, gy = G * math.sin(a), -G * math.cos(a)
    rest = disk_mass(D) * -gy / KN
    return {"name": name, "allow_initial_overlap": True, "effects": effects, "gravity": {"g": [gx, gy]},
            "material": {"density": 2500},
            "contact": law, "time": {"duration": duration, "dt_over_critical": 0.02},
            "domain": {"xmin": -0.5, "xmax": 0.5, "ymin": -0.1, "ymax": 0.1},
            "output": {"snapshot_interval": snapshots},
            "particle": [{"x": 0.0, "y": D / 2 - rest, "d": D, "vx": vx, "omega": omega}], "body": [FLOOR]}


def slide_to_roll(ctx) -> list:
    """Launched sliding without spin, friction mu m g slows the disk and spins
    it up until v = omega r: v = v0/(1 + I/(m r^2)) = 2/3 v0 at t* = v0/(3 mu g)."""
    v0, mu = 0.1, 0.5
    t_star = v0 / (3 * mu * G)
    r = run(ctx.dem2d, disk_on_floor("slide_to_roll", 3 * t_star, vx=v0), ctx.out / "single" / "slide_to_roll")
    t, v, w = r.read("snapshots/time"), r.read("snapshots/velocity")[:, 0, 0], r.read("snapshots/omega")[:, 0]
    # the wall contact of each snapshot (one per snapshot): sliding while |F_t| = mu F_n
    start, ft, fn = r.read("snapshots/contact_start"), r.read("contacts/ft"), r.read("contacts/fn")
    sliding = np.array([k1 > k0 and abs(ft[k0]) >= mu * fn[k0] * (1 - 1e-9) for k0, k1 in zip(start[:-1], start[1:])])
    after = t > 0.1 * t_star  # (at t = 0 the spring has not loaded yet)
    stick = float(t[after][np.argmax(~sliding[after])])
    rolling = t > 1.5 * t_star
    case = "slide to roll (disk on a floor)"
    return [Check(case, "time sliding stops", t_star, stick, 0.02, "s", reference="v0 / (3 mu g)"),
            Check(case, "rolling speed", 2 * v0 / 3, float(np.mean(v[rolling])), 0.01, "m/s", reference="2/3 v0"),
            Check(case, "rolls without slip: omega r / v", -1.0, float(np.mean(w[rolling] * D / 2 / v[rolling])), 0.01,
                  reference="v = -omega r")]


def incline(ctx) -> list:
    """Rolling from rest down an incline: a = 2/3 g (sin a - (mu_r/r) cos a)
    (I = m r^2/2), and at rest if tan a < mu_r/r."""
    checks = []
    ctx.figures["incline"] = []
    for tilt, mu_r_over_r in ((10.0, 0.0), (20.0, 0.0), (10.0, 0.05), (20.0, 0.05)):
        mu_r = mu_r_over_r * D / 2
        r = run(ctx.dem2d, disk_on_floor("incline", 0.05, tilt_deg=tilt, mu_r=mu_r if mu_r > 0 else None, snapshots=1e-3),
                ctx.out / "single" / f"incline_{tilt}_{mu_r_over_r}")
        t, v = r.read("snapshots/time"), r.read("snapshots/velocity")[:, 0, 0]
        late = t > 0.01  # after the rolling spring has loaded
        a = float(np.polyfit(t[late], v[late], 1)[0])
        a_expected = 2.0 / 3.0 * G * (math.sin(math.radians(tilt)) - mu_r_over_r * math.cos(math.radians(tilt)))
        case = f"rolling down a {tilt:.0f} deg incline, mu_r/r = {mu_r_over_r}"
        checks.append(Check(case, "acceleration", a_expected, a, 0.01, "m/s^2",
                            reference="2/3 g (sin a - mu_r/r cos a)"))
        ctx.figures["incline"].append((tilt, mu_r_over_r, a_expected, a))
    tilt, mu_r_over_r = 2.0, 0.05  # tan 2 deg = 0.035 < 0.05: held by rolling resistance
    r = run(ctx.dem2d, disk_on_floor("incline_held", 0.2, tilt_deg=tilt, mu_r=mu_r_over_r * D / 2, snapshots=1e-3),
            ctx.out / "single" / "incline_held")
    travel = float(np.ptp(r.read("snapshots/position")[:, 0, 0]))
    checks.append(Check(f"a disk on a {tilt:.0f} deg incline, mu_r/r = {mu_r_over_r} > tan a", "travel over 0.2 s",
                        0.01 * D, travel, 0.0, "m", "below", "at rest (only the rolling spring's give)"))
    return checks


def static_pile(ctx) -> list:
    """A pile settled in a box: the floor and walls carry its weight, and the
    side walls' pushes cancel."""
    n, width = 300, 0.04
    pitch = 1.05 * 4e-3
    scene = {"name": "pile", "effects": {"gravity": True, "normal_damping": True, "friction": True,
                                         "rolling_resistance": True, "walls": True},
             "gravity": {"g": [0.0, -G]}, "material": {"density": 2500},
             "contact": {**glass_contact(KN / 10), "rolling_friction": 1.5e-5, "rolling_stiffness": D * D * KN / 10 * 1e-4},
             "time": {"duration": 3.0, "dt_over_critical": 0.05},
             "stop": {"kinetic_energy_per_grain_below": 1e-12, "check_interval": 0.01},
             "domain": {"xmin": -0.01, "xmax": width + 0.01, "ymin": -0.01, "ymax": 0.3},
             "output": {"series_interval": 0.01},
             "generator": [{"kind": "triangular_lattice", "count": n, "seed": 3, "diameter": {"min": 2e-3, "max": 4e-3},
                            "region": [[0.0, 0.0], [width, 0.0], [width, 0.25], [0.0, 0.25]], "spacing": pitch}],
             "body": [{"name": "floor", "a": [-1e-3, -1e-3], "b": [width + 1e-3, -1e-3], "thickness": 2e-3,
                       "role": "floor"},
                      {"name": "left", "a": [-1e-3, -1e-3], "b": [-1e-3, 0.3], "thickness": 2e-3, "role": "left_wall"},
                      {"name": "right", "a": [width + 1e-3, -1e-3], "b": [width + 1e-3, 0.3], "thickness": 2e-3,
                       "role": "right_wall"}]}
    r = run(ctx.dem2d, scene, ctx.out / "single" / "pile")
    weight = float(r.read("particles/mass").sum()) * G
    force = r.read("series/body_force")[-1]  # [body, 2]: what the grains exert on each body (N/m)
    case = f"static pile ({n} grains in a {1e3 * width:.0f} mm box, at rest)"
    return [Check(case, "vertical load on floor and walls / weight", 1.0, float(-force[:, 1].sum()) / weight,
                  1e-3, reference="statics: sum F_y = m g"),
            Check(case, "side walls' horizontal pushes, summed / weight", 0.0, float(force[:, 0].sum()) / weight, 1e-3,
                  kind="abs", reference="statics: sum F_x = 0"),
            Check(case, "stopped at rest", 1.0, float(r.attr("stopped_by") == "kinetic_energy"), 0.0,
                  kind="abs", reference="per-grain kinetic energy criterion")]

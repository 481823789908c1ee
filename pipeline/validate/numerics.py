"""The integrator: the energy error of an elastic gas against dt (second
order), the energy ledger's closure, and the dense-packing stability limit
(docs/contact_law.md): a hexagonal crystal at rest stays at rest just below
the limit dem2d computes and blows up just above it."""
import math

import numpy as np

from pipeline.validate.checks import Check
from pipeline.validate.runner import check, glass_contact, ledger_terms, run

KN = 1.92e6
D = 2e-3


def crystal(name: str, law: dict, effects: dict, duration: float, spacing: float = 0.999, seed_speed: float = 0.0):
    """A hexagonal crystal of 2 mm disks, 24 x 20, `spacing` x d apart, in a
    closed box whose walls touch the outer rows."""
    p, nx, ny = spacing * D, 24, 20
    row = p * math.sqrt(3) / 2
    rng = np.random.default_rng(11)
    parts = []
    for r in range(ny):
        for c in range(nx - r % 2):
            v = rng.uniform(-seed_speed, seed_speed, 2)
            parts.append({"x": (0.5 + c + 0.5 * (r % 2)) * p, "y": 0.5 * p + r * row, "d": D,
                          "vx": float(v[0]), "vy": float(v[1])})
    width, height, t = nx * p, p + (ny - 1) * row, 2e-3
    walls = [{"name": "floor", "a": [-t, -t / 2], "b": [width + t, -t / 2], "thickness": t},
             {"name": "lid", "a": [-t, height + t / 2], "b": [width + t, height + t / 2], "thickness": t},
             {"name": "left", "a": [-t / 2, -t], "b": [-t / 2, height + t], "thickness": t},
             {"name": "right", "a": [width + t / 2, -t], "b": [width + t / 2, height + t], "thickness": t}]
    return {"name": name, "allow_initial_overlap": True, "effects": {**effects, "walls": True},
            "material": {"density": 2500}, "contact": law, "time": {"duration": duration, "dt_over_critical": 0.05},
            "domain": {"xmin": -0.01, "xmax": width + 0.01, "ymin": -0.01, "ymax": height + 0.01},
            "output": {"series_interval": duration / 100}, "particle": parts, "body": walls}


def energy_total(dem2d: str, r) -> tuple:
    """The energy ledger's terms in r, every one the program names (its run-file schema), and their conserved
    total (each term with its sign in it)."""
    signs = ledger_terms(dem2d)
    terms = {t: r.read(f"series/energy/{t}") for t in signs}
    return terms, sum(signs[t] * v for t, v in terms.items())


def elastic_gas(ctx) -> list:
    """An elastic gas: the compressed crystal vibrating (random velocities
    up to 5 cm/s), undamped and frictionless. Its only energy loss is the
    integrator's; velocity Verlet's is second order in dt."""
    law = {"kn": KN}
    errors = {}
    closure = 0.0
    divisors = (20, 40, 80, 160)
    for divisor in divisors:
        scene = crystal("elastic_gas", law, {}, 0.02, spacing=0.9975, seed_speed=0.05)
        scene["time"]["dt_over_critical"] = 1.0 / divisor
        scene["output"]["energy_balance"] = True
        r = run(ctx.dem2d, scene, ctx.out / "numerics" / f"gas_{divisor}")
        e, total = energy_total(ctx.dem2d, r)
        scale = max(np.max(np.abs(v)) for v in e.values())
        closure = max(closure, float(np.max(np.abs(total - total[0])) / scale))
        errors[divisor] = float(np.max(np.abs(e["integration_error"])) / e["kinetic"][0])
    ctx.figures["elastic_gas"] = errors
    # the largest error over a run picks an oscillation's phase, so one ratio
    # of two dt scatters: the slope over four dt
    order = float(np.polyfit(np.log([1.0 / k for k in divisors]), np.log([errors[k] for k in divisors]), 1)[0])
    case = "elastic gas (a vibrating crystal, undamped, frictionless)"
    return [Check(case, "order of the energy error (slope over dt_c/20 ... /160)", 2.0, order, 0.15, kind="abs",
                  reference="velocity Verlet: O(dt^2)"),
            Check(case, "energy error at dt_c/20 / kinetic energy", 1e-3, errors[20], 0.0, kind="below",
                  reference="small at the presets' dt"),
            Check(case, "energy ledger: the sum of its terms moves by (/ largest term)", 1e-10, closure, 0.0, kind="below",
                  reference="closes to round-off (docs/energy.md)")]


def stability_limit(ctx) -> list:
    """The crystal compressed by 0.1 % of d, settled with damping (e = 0.5),
    every grain then given a random velocity of up to 1 nm/s (the dynamics
    stay linear: no contact opens), and run for 4000 steps at 0.99 and
    1.03 x the stability limit dem2d computes for each law."""
    settle = crystal("crystal_settle", {"kn": KN, "restitution": 0.5}, {"normal_damping": True}, 0.3)
    settled = run(ctx.dem2d, settle, ctx.out / "numerics" / "crystal_settle")
    position = settled.read("snapshots/position")[-1]
    rng = np.random.default_rng(11)
    parts = [{"x": float(x), "y": float(y), "d": D, "vx": float(rng.uniform(-1e-9, 1e-9)),
              "vy": float(rng.uniform(-1e-9, 1e-9))} for x, y in position]
    checks = []
    laws = [("undamped normal springs", {"kn": KN}, {}, 2.0),
            ("normal springs and dashpots, e = 0.5", {"kn": KN, "restitution": 0.5}, {"normal_damping": True}, 1.0),
            ("the paper's law (mu = 0.5, k_t = k_n/2, e = 0.9)", {**glass_contact(KN)}, {"normal_damping": True, "friction": True},
             1.0)]
    ctx.figures["stability"] = []
    for label, law, effects, stable_below in laws:
        scene = crystal("crystal", law, effects, 1.0)
        scene["particle"] = parts
        limit = check(ctx.dem2d, scene, ctx.out / "numerics" / "crystal_check")
        growth = {}
        for fraction in (0.99, 1.03):
            dt = fraction * limit["stable_dt_s"]
            scene["time"] = {"duration": 4000 * dt, "dt": dt, "force_dt": True}
            scene["output"] = {"series_interval": 1000 * dt}
            try:
                r = run(ctx.dem2d, scene, ctx.out / "numerics" / f"crystal_{len(checks)}_{fraction}")
                ke = r.read("series/kinetic_energy")
                growth[fraction] = math.inf if int(r.attr("lost_particles")) else float(ke[-1] / ke[0])
            except RuntimeError:  # a non-finite state: blown up
                growth[fraction] = math.inf
        case = f"dense-packing stability limit: {label} (limit {limit['stable_dt_over_critical']:.3f} dt_c)"
        checks.append(Check(case, "kinetic energy growth over 4000 steps at 0.99 x the limit", stable_below,
                            growth[0.99], 0.0, kind="below", reference="stays at rest"))
        checks.append(Check(case, "kinetic energy growth over 4000 steps at 1.03 x the limit", 1e3, growth[1.03], 0.0,
                            kind="above", reference="blows up"))
        ctx.figures["stability"].append((label, limit["stable_dt_over_critical"], growth[0.99], growth[1.03]))
    return checks

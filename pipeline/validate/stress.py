"""The coarse-grained stress (the stage `stress`, analysis/stress/) on runs
whose statics are known: a pile at rest, whose floor load the stress around
the floor must give, and the tallest Janssen column, whose vertical stress
must follow Janssen's profile with the saturation the floor loads of all
the columns give (bulk.janssen). Each runs after the case that made its run
file (validate.py's registry) and reads the run with the stage's program of
the same build tree."""
import math
from pathlib import Path

import h5py
import numpy as np

from pipeline.validate.checks import Check
from pipeline.validate.runner import run_stage

G = 9.81


def stage(ctx, run_dir: Path, role: str) -> Path:
    """The stress stage on run_dir/run.h5, its first and last snapshots, the force check on the body of
    `role`: run_dir/stress/stress.h5."""
    config = run_dir / "stress.toml"
    config.write_text(f'every = 1000000000\nmaps = 2\n[body]\nrole = "{role}"\n')
    out = run_dir / "stress"
    run_stage(ctx.dem2d, "stress", run_dir / "run.h5", out, config)
    return out / "stress.h5"


def last_force(h5: Path):
    """The last snapshot's recorded and stress-borne forces on the body (N/m, [2] each)."""
    with h5py.File(h5, "r") as f:
        return f["series/force_recorded"][-1], f["series/force_stress"][-1], f["series/force_exact"][-1]


def pile(ctx) -> list:
    """The static pile of single.static_pile (300 grains at rest in a 40 mm box): the force the stress
    around the floor carries (quasi-static: the grains at rest) against the floor's recorded load."""
    h5 = stage(ctx, ctx.out / "single" / "pile", "floor")
    rec, st, exact = last_force(h5)
    case = "stress: the static pile's floor"
    return [Check(case, "the floor's load from the stress around it / recorded", 1.0, float(st[1] / rec[1]), 2e-3,
                  reference="statics: the stress field balances the contact forces (Weinhart et al. 2012)"),
            Check(case, "the fields' identity: exact balance / recorded", 1.0, float(exact[1] / rec[1]), 2e-3,
                  reference="d_b sigma_ab = b_a - net_a, to the grid's quadrature")]


def fraction_above(h, w: float, cutoff: float):
    """The part of the truncated Gaussian kernel (width w, cut off at `cutoff`) that lies more than h above
    its centre (h an array, m): the weight a grain or contact h below a line puts above it."""
    t = np.linspace(-cutoff, cutoff, 4001)
    # the kernel's marginal along y: exp(-t^2/2w^2) x int over the chord |x| < sqrt(R^2 - t^2) of exp(-x^2/2w^2)
    chord = np.sqrt(np.maximum(cutoff * cutoff - t * t, 0.0))
    marginal = np.exp(-t * t / (2 * w * w)) * np.array([math.erf(c / (math.sqrt(2) * w)) for c in chord])
    cdf = np.concatenate([[0.0], np.cumsum((marginal[1:] + marginal[:-1]) / 2 * np.diff(t))])
    return 1.0 - np.interp(h, t, cdf / cdf[-1])


def slices(h5: Path, run_file: Path, heights) -> tuple:
    """The Janssen slice balance of the last snapshot at each height z: the vertical stress integrated
    across the cell, int sigma_yy dx (the grains below carrying those above), against the weight above z
    less the walls' vertical push on the grains above z (quasi-static), and that plus the grains'
    acceleration above z, sum m a_y (exact): each with the kernel's share above z (N/m)."""
    with h5py.File(h5, "r") as f:
        y, dx = f["grid/y"][:], float(f["grid/x"][1] - f["grid/x"][0])
        syy = f["maps/sigma"][-1, 3]
        w = float(f.attrs["kernel_w"])
        cutoff = w * float(f.attrs["kernel_cutoff_over_w"])
    with h5py.File(run_file, "r") as r:
        k = r["snapshots/time"].shape[0] - 1
        pos, mass = r["snapshots/position"][k], r["particles/mass"][:]
        active = r["snapshots/active"][k].astype(bool)
        a, b = r["snapshots/contact_start"][k], r["snapshots/contact_start"][k + 1]
        c = {n: r["contacts/" + n][a:b] for n in ("i", "j", "fn", "ft", "nx", "ny", "overlap")}
        diameter = r["particles/diameter"][:]
        roles = [x.decode() if isinstance(x, bytes) else str(x) for x in r["bodies/role"][:]]
    fy = c["fn"] * c["ny"] + c["ft"] * c["nx"]  # each contact's force on grain i, y
    net = np.zeros(len(mass))  # each grain's net contact force, y
    np.add.at(net, c["i"], fy)
    grain = c["j"] >= 0
    np.add.at(net, c["j"][grain], -fy[grain])
    on_wall = np.isin(c["j"], [-1 - b for b, role in enumerate(roles) if role in ("left_wall", "right_wall")])
    i = c["i"][on_wall]
    cy = pos[i, 1] - c["ny"][on_wall] * (0.5 * diameter[i] - 0.5 * c["overlap"][on_wall])  # contact points
    carried, quasi, exact = [], [], []
    for z in heights:
        j = int(np.argmin(np.abs(y - z)))
        share = fraction_above(y[j] - pos[active, 1], w, cutoff)
        weight = float((mass[active] * G * share).sum())
        push = float((fy[on_wall] * fraction_above(y[j] - cy, w, cutoff)).sum())
        accel = float(((net[active] - mass[active] * G) * share).sum())
        carried.append(float(syy[j].sum() * dx))
        quasi.append(weight - push)
        exact.append(weight - push + accel)
    return np.array(carried), np.array(quasi), np.array(exact)


def janssen(ctx) -> list:
    """The tallest column of bulk.janssen at its end (floor sinking at 1 mm/s, walls' friction mobilised):
    the slice balance of statics at every height (the stress across the silo carries the weight above less
    the walls' push), the floor's load from the stress around it; and Janssen's profile, with M_sat and
    rho_b from the floor loads of every column, beside the measured one (shown, not judged: Janssen's
    constant K does not hold along this column, its K = sigma_xx/sigma_yy runs from ~0.8 to ~1.4)."""
    j = ctx.figures["janssen"]
    run_dir = Path(j["tallest_run"])
    h5 = stage(ctx, run_dir, "floor")
    width, m_sat, rho_b, surface = j["width"], j["m_sat"], j["rho_b"], j["tallest_top"]
    with h5py.File(h5, "r") as f:
        x, y = f["grid/x"][:], f["grid/y"][:]
        left, right, floor = (float(f.attrs[k]) for k in ("cell_left", "cell_right", "cell_floor"))
        sxx, syy = f["maps/sigma"][-1, 0], f["maps/sigma"][-1, 3]
        cutoff = float(f.attrs["kernel_w"]) * float(f.attrs["kernel_cutoff_over_w"])
    # heights beyond the floor's kernel, below the surface by a kernel's reach, every 10 mm
    heights = np.arange(floor + cutoff, surface - cutoff, 0.01)
    carried, quasi, exact = slices(h5, run_dir / "run.h5", heights)
    inside = (x > left) & (x < right)
    rows = [int(np.argmin(np.abs(y - z))) for z in heights]
    profile = syy[:, inside].mean(axis=1)[rows]
    ratio_k = sxx[:, inside].mean(axis=1)[rows] / profile
    depth = surface - heights
    janssen_profile = m_sat * G / width * (1.0 - np.exp(-depth * rho_b * width / m_sat))
    ctx.figures["janssen_stress"] = {"depth": depth.tolist(), "sigma_yy": profile.tolist(),
                                     "janssen": janssen_profile.tolist(), "K": ratio_k.tolist()}
    rec, st, _ = last_force(h5)
    case = f"stress: the tallest Janssen column ({1e3 * (surface - floor):.0f} mm of grains in the {1e3 * width:.0f} mm silo)"
    worst = lambda a, b: float(np.max(np.abs(a / b - 1.0)))  # noqa: E731
    return [Check(case, "slice balance, exact: int sigma_yy dx over weight above - walls' push + sum m a, worst height",
                  0.0, worst(carried, exact), 2e-3, kind="abs",
                  reference="statics of the slab above each height (Janssen's slice), the kernel's share above it"),
            Check(case, "slice balance, quasi-static (without sum m a), worst height", 0.0, worst(carried, quasi), 0.02,
                  kind="abs", reference="the column slips on its walls: its grains accelerate at ~0.4 % of g"),
            Check(case, "the floor's load from the stress around it / recorded", 1.0, float(st[1] / rec[1]), 1e-2,
                  reference="quasi-static: the floor sinks at 1 mm/s")]

"""The rotating drum: its dynamic angle of repose and the torque that turns it.

    dem2d run examples/drum/scene.toml --out /tmp/drum
    python3 examples/drum/plot.py /tmp/drum/run.h5 /tmp/drum/drum.png

The drum is every body of the run; its axis is the mean of their vertices, its
radius the walls' inner face, its angular velocity read off their vertices.
Once it has turned `--settle` rad (default 1.5) the bed is taken as steady:

- the angle of repose: the free surface is a chord of the drum, so the bed's
  centre of mass lies on the chord's perpendicular through the axis; the
  angle between the axis-to-centre-of-mass line and the downward vertical is
  the surface's slope (the mean over the steady snapshots);
- the torque: in steady rotation the drum's torque on the bed (about the axis)
  balances gravity's, g M x_com, with x_com the centre of mass's horizontal
  offset from the axis; the run's torque series (grains on the walls, about
  their pivot) must be its opposite.
"""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
import matplotlib  # noqa: E402
import numpy as np  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import dem2d  # noqa: E402
from dem2d.plot import draw_bodies, draw_grains  # noqa: E402


def measure(run, settle):
    """The drum's axis, radius (m), angular velocity (rad/s), Froude number, the steady snapshots'
    angles of repose (deg) and their mean's standard error (five successive blocks' means: the
    snapshots of an avalanche are not independent), the torques (N): the walls' series against g M x_com, and the bed's
    mean angular velocity about the axis and its grains' mean spin (rad/s, mass-weighted)."""
    vertices = run.dataset("snapshots/body_vertices")  # [S, B, K, 2] (whole datasets: one read each)
    axis = vertices[0].reshape(-1, 2).mean(axis=0)
    wall = run.bodies[0]
    mid = vertices[0, 0, :wall.vertex_count].mean(axis=0)
    radius = float(np.hypot(*(mid - axis)) - wall.thickness / 2)
    times, v = run.times, vertices[:, 0, 0] - axis
    turned = np.unwrap(np.arctan2(v[:, 1], v[:, 0]))
    turned -= turned[0]
    omega = float(np.polyfit(times[-4:], turned[-4:], 1)[0])
    g = float(np.hypot(*run.parameters.gravity))
    steady = np.flatnonzero(np.abs(turned) >= settle)
    position, velocity = run.dataset("snapshots/position")[steady], run.dataset("snapshots/velocity")[steady]
    spin, active = run.dataset("snapshots/omega")[steady], run.dataset("snapshots/active")[steady].astype(bool)
    m = run.parameters.density * math.pi * run.particles.diameter ** 2 / 4 * active  # kg/m [S, N]
    com = (m[..., None] * position).sum(axis=1) / m.sum(axis=1)[:, None] - axis
    angles = np.degrees(np.arctan2(com[:, 0], -com[:, 1])) * np.sign(omega)
    com_x = g * m.sum(axis=1) * com[:, 0]
    r = position - axis  # the bed's angular momentum about the axis over its moment of inertia there
    momentum = (m * (r[..., 0] * velocity[..., 1] - r[..., 1] * velocity[..., 0])).sum(axis=1)
    bed = momentum / (m * (r ** 2).sum(axis=2)).sum(axis=1)
    spin = (m * spin).sum(axis=1) / m.sum(axis=1)
    if not len(angles):
        sys.exit(f"drum: the drum turned {abs(turned[-1]):.2f} rad, less than --settle {settle} rad: no steady state")
    t0 = times[steady[0]]
    series = run.series
    rows = series.time >= t0
    drum = sum(series.body_torque(b)[rows] for b in run.bodies)
    blocks = [b.mean() for b in np.array_split(angles, 5)] if len(angles) >= 10 else [np.nan]
    return dict(axis=axis, radius=radius, omega=omega, froude=omega ** 2 * radius / g, angles=angles,
                angle_se=float(np.std(blocks, ddof=1) / math.sqrt(len(blocks))) if len(blocks) > 1 else math.nan,
                torque=float(drum.mean()), gravity_torque=float(np.mean(com_x)), steady=steady,
                bed_omega=float(np.mean(bed)), spin=float(np.mean(spin)))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run")
    ap.add_argument("png")
    ap.add_argument("--settle", type=float, default=1.5, help="rad the drum turns before the bed counts as steady")
    args = ap.parse_args()
    with dem2d.open_run(args.run) as run:
        m = measure(run, args.settle)
        a = m["angles"]
        print(f"drum: R = {m['radius'] * 1e3:.1f} mm, omega = {m['omega']:.4f} rad/s, Fr = {m['froude']:.4g}: "
              f"dynamic angle of repose {a.mean():.2f} +- {m['angle_se']:.2f} deg (sd {a.std():.2f} over {len(a)} "
              f"snapshots); "
              f"torque of the grains on the drum {m['torque']:.5f} N against -g M x_com {-m['gravity_torque']:.5f} N")
        s = run.snapshot(int(m["steady"][-1]))
        fig, ax = plt.subplots(figsize=(6, 6.4), constrained_layout=True)
        reach = m["radius"] + 2 * run.bodies[0].thickness
        ax.set_xlim(m["axis"][0] - reach, m["axis"][0] + reach)  # (before the walls: their width in points)
        ax.set_ylim(m["axis"][1] - reach, m["axis"][1] + reach)
        ax.set_aspect("equal")
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        draw_grains(ax, run, s, colour="0.85", edge="0.6")
        draw_bodies(ax, run, s)
        # the mean slope through this snapshot's surface: the top grains' mean height across it
        slope = math.radians(a.mean()) * np.sign(m["omega"])
        along, across = np.array([math.cos(slope), math.sin(slope)]), np.array([-math.sin(slope), math.cos(slope)])
        h = (s.position[s.active] - m["axis"]) @ across
        top = np.sort(h)[-max(3, int(math.sqrt(s.active.sum()))):].mean()
        half = math.sqrt(max(m["radius"] ** 2 - top ** 2, 0.0))
        chord = np.array([top * across - half * along, top * across + half * along])
        ax.plot(*(m["axis"] + chord).T, "r--", lw=1.5, label=f"mean slope {a.mean():.1f}°")
        ax.set_title(f"drum at Fr = {m['froude']:.3g}: dynamic angle of repose {a.mean():.1f}°")
        ax.legend(loc="upper right")
        fig.savefig(args.png, dpi=120)


if __name__ == "__main__":
    main()

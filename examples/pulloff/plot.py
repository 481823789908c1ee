"""The pull-off: the drag on the bar against its height, and the force network halfway up.

    dem2d run examples/pulloff/fill.toml --out /tmp/fill
    dem2d run examples/pulloff/pulloff.toml --initial /tmp/fill/run.h5 --out /tmp/pulloff
    python3 examples/pulloff/plot.py /tmp/pulloff/run.h5 /tmp/pulloff/pulloff.png
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import dem2d  # noqa: E402
from dem2d.plot import draw_bodies, draw_contacts, draw_grains, frame  # noqa: E402


def main(path, out):
    with dem2d.open_run(path) as run:
        bar = run.body("intruder")
        # drag: the grains' force on the bar against its motion (up), mean over each series interval
        drag = -run.series.body_force(bar)[:, 1]
        height = run.series.body_vertices(bar)[:, :, 1].mean(axis=1) - run.floor_top()  # m, its centre
        k = int(np.argmax(drag))
        print(f"pulloff: {run.n_particles} grains; largest drag {drag[k]:.2f} N/m at H = {height[k] * 1e3:.1f} mm, "
              f"clear of the bed at H = {height[-1] * 1e3:.1f} mm ({run.stop_reason})")
        fig, (a, b) = plt.subplots(1, 2, figsize=(11, 5), constrained_layout=True)
        a.plot(height * 1e3, drag, lw=0.8)
        a.set_xlabel("bar height H (mm)")
        a.set_ylabel(f"drag ({run.units('series/body_force_mean')})")
        a.set_title("drag on the bar")
        s = run.snapshot_at(run.times[-1] / 2)
        draw_grains(b, run, s, colour="0.92", edge="0.75")
        frame(b, run, s)
        lines = draw_contacts(b, s)
        draw_bodies(b, run, s)
        fig.colorbar(lines, ax=b, shrink=0.6).set_label("F_n (N/m)")
        b.set_title(f"force network at t = {s.time:.2f} s")
        fig.savefig(out, dpi=110)


if __name__ == "__main__":
    main(*sys.argv[1:3])

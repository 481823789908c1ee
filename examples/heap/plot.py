"""The heap: its angle of repose (lines fitted to both flanks) and its force network.

    dem2d run examples/heap/scene.toml --out /tmp/heap
    python3 examples/heap/plot.py /tmp/heap/run.h5 /tmp/heap/heap.png
"""
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import dem2d  # noqa: E402
from dem2d.measure import heap_angle, surface  # noqa: E402
from dem2d.plot import draw_bodies, draw_contacts, draw_grains, frame  # noqa: E402


def main(path, out):
    with dem2d.open_run(path) as run:
        s = run.snapshot(-1)
        d = run.particles.diameter.mean()
        on_base = s.active & (s.position[:, 1] > 0)
        angle = heap_angle(s.position[on_base], d)
        print(f"heap: {on_base.sum()} of {run.n_particles} grains stay on the base "
              f"({run.attrs['lost_particles']} ran off); angle of repose {angle:.1f} deg ({run.stop_reason})")
        fig, ax = plt.subplots(figsize=(8, 4), constrained_layout=True)
        draw_grains(ax, run, s, colour="0.92", edge="0.75")
        frame(ax, run, s)
        draw_contacts(ax, s)
        draw_bodies(ax, run, s)
        top = surface(s.position[on_base], d)
        ax.plot(top[:, 0], top[:, 1], "g.", ms=4, label="free surface")
        ax.set_title(f"{run.parameters.name}: angle of repose {angle:.1f}° (tan = {math.tan(math.radians(angle)):.2f})")
        ax.legend(loc="upper right")
        fig.savefig(out, dpi=120)


if __name__ == "__main__":
    main(*sys.argv[1:3])

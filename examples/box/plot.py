"""The settled box: the grains, the force network, and who carries the weight.

    dem2d run examples/box/scene.toml --out /tmp/box
    python3 examples/box/plot.py /tmp/box/run.h5 /tmp/box/box.png
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


def load_on(snap, body):
    """Force of the grains on `body` (N/m): minus the contact forces it exerts on them."""
    c = snap.contacts
    on = c.with_body(body)
    n, fn, ft = c.normal[on], c.fn[on], c.ft[on]
    t = np.stack([-n[:, 1], n[:, 0]], axis=1)  # t = z x n
    return -(fn[:, None] * n + ft[:, None] * t).sum(axis=0)


def main(path, out):
    with dem2d.open_run(path) as run:
        s = run.snapshot(-1)
        g = -run.parameters.gravity[1]
        weight = run.particles.mass[s.active].sum() * g
        floor = -load_on(s, run.body("floor"))[1] / weight  # the share of the weight it carries
        sides = [run.body(w) for w in ("left_wall", "right_wall")]
        walls = -sum(load_on(s, w)[1] for w in sides) / weight
        # The walls' share is static friction: anything within +-mu times their normal load holds the bed,
        # and which value it takes is the last slip along them (settling down along them gives the Janssen
        # sign; the bed's rebound after landing, the opposite). Not a material property.
        mu = run.parameters.contact["grain_body"]["friction"]
        bound = mu * sum(abs(load_on(s, w)[0]) for w in sides) / weight
        # The snapshot catches the bed's elastic sway; the mean force over the last series interval does not.
        mean = run.dataset("series/body_force_mean")[-1]
        held = -sum(mean[b.index][1] for b in [run.body("floor"), *sides]) / weight
        print(f"box: {s.active.sum()} grains at t = {s.time:.3f} s ({run.stop_reason}): the floor carries "
              f"{floor:.4f} of their weight, the side walls {walls:.4f} (static friction: at most {bound:.3f} either "
              f"way, mu times their normal load; its sign is the last slip along them); averaged over the last "
              f"{1e3 * run.parameters.output['series_interval']:.0f} ms floor and walls carry {held:.4f}")
        fig, ax = plt.subplots(figsize=(5, 6), constrained_layout=True)
        draw_grains(ax, run, s, colour="0.92", edge="0.75")
        frame(ax, run, s)
        lines = draw_contacts(ax, s)
        draw_bodies(ax, run, s)
        fig.colorbar(lines, ax=ax, shrink=0.6).set_label(f"F_n ({run.units('contacts/fn')})")
        ax.set_title(f"{run.parameters.name}: floor {floor:.3f}, walls {walls:.3f} of the weight")
        fig.savefig(out, dpi=120)


if __name__ == "__main__":
    main(*sys.argv[1:3])

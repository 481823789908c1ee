"""The silo's discharge: grains left in the silo over time (the flow rate is its slope), and the
final state in the box below.

    dem2d run examples/silo/scene.toml --out /tmp/silo
    python3 examples/silo/plot.py /tmp/silo/run.h5 /tmp/silo/silo.png
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import dem2d  # noqa: E402
from dem2d.plot import draw_bodies, draw_grains, frame  # noqa: E402


def main(path, out):
    with dem2d.open_run(path) as run:
        outlet = run.parameters.jam["outlet_height"]  # m: the funnel's outlet
        above = np.array([(s.position[s.active, 1] > outlet).sum() for s in run])
        flowing = (above < above[0]) & (above > 0)
        # the mean flow rate while the silo empties (grains per second)
        rate = (above[0] - above[flowing][-1]) / (run.times[flowing][-1] - run.times[0]) if flowing.any() else 0.0
        print(f"silo: {above[0]} grains above the outlet at t = 0, {above[-1]} at t = {run.times[-1]:.2f} s; "
              f"mean discharge {rate:.0f} grains/s ({run.stop_reason})")
        fig, (a, b) = plt.subplots(1, 2, figsize=(10, 5), constrained_layout=True)
        a.plot(run.times, above, "o-", ms=3)
        a.set_xlabel("t (s)")
        a.set_ylabel(f"grains above the outlet (y > {outlet * 1e3:.0f} mm)")
        a.set_title(f"discharge: {rate:.0f} grains/s")
        s = run.snapshot(-1)
        speed = np.hypot(*s.velocity.T)
        discs = draw_grains(b, run, s, values=speed)
        frame(b, run, s)
        draw_bodies(b, run, s)
        fig.colorbar(discs, ax=b, shrink=0.6).set_label("speed (m/s)")
        b.set_title(f"t = {s.time:.2f} s")
        fig.savefig(out, dpi=110)


if __name__ == "__main__":
    main(*sys.argv[1:3])

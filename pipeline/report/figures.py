"""The study's figures from one results directory.

    /usr/bin/python3 -m pipeline.report.figures RESULTS_DIR      (e.g. results/default)

Reads the stage outputs RESULTS_DIR/{fill,pulloff,spectrum,cg,network,friction,stress,piv}/,
writes RESULTS_DIR/figures/*.png and, last, RESULTS_DIR/figures/index.json
(file, figure, title, caption per PNG); every file is written under a
temporary name and renamed. Exit status: 0 done; 2 an input is missing or
unreadable (the message names the file and the make target that makes it).
"""

import argparse
import os
import sys
import time

import matplotlib.pyplot as plt
import numpy as np

from pipeline.report import (events, fig_drag, fig_friction, fig_network, fig_percolation, fig_piv, fig_spectrum,
                             fig_stress, fig_velocity)
from pipeline.report.bed import Run
from pipeline.report.cgdata import CG
from pipeline.report.common import InputError, Inputs, NoData, nearest, save, write_json

NETWORK_HEIGHT_MM = 34.0  # paper Fig. 6b

# file, figure, title, drawing function of the context
FIGURES = [
    ("drag_profile.png", "Fig. 6a", "Drag force profile, loading/rupture events and their amplitude",
     lambda c: fig_drag.drag_profile(c.inp, c.run.heights()[c.k34])),
    ("force_network.png", "Fig. 6b", "Normal force network at H ≈ 34 mm",
     lambda c: fig_network.force_network(c.inp, c.run, c.k34)),
    ("vstar_zones.png", "Fig. 8", "Mobility zones of v* at five intruder heights",
     lambda c: fig_velocity.vstar_zones(c.inp, c.cg, c.run, c.ev)),
    ("centre_velocity.png", "Fig. 9", "Vertical velocity on the centre line against intruder height",
     lambda c: fig_velocity.centre_velocity(c.inp, c.cg)),
    ("tip_velocity.png", "Fig. 10", "Flow around the intruder tips in its frame after a rupture",
     lambda c: fig_velocity.tip_velocity(c.inp, c.cg, c.run, c.ev)),
    ("force_on_velocity.png", "Fig. 11", "Force network over the CG velocity magnitude (log scale)",
     lambda c: fig_network.force_on_velocity(c.inp, c.cg, c.run, c.ev)),
    ("friction_mobilisation.png", "Fig. 12b,c", "Friction mobilisation μ* on the bed and the Coulomb cone",
     lambda c: fig_friction.mobilisation(c.inp, c.run, NETWORK_HEIGHT_MM)),
    ("mean_mu_star.png", "Fig. 13", "Mean μ* of bulk and wall contacts against height",
     lambda c: fig_friction.mean_mu_star(c.inp)),
    ("drag_spectrum.png", "Drag spectrum (R3, no paper figure)", "Drag spectrum per height band",
     lambda c: fig_spectrum.drag_spectrum(c.inp)),
    ("stress_maps.png", "Fig. 5 (stress)", "Coarse-grained pressure and shear at four instants",
     lambda c: fig_stress.maps(c.inp)),
    ("stress_force.png", "Stress balance (no paper figure)", "The force on the intruder from the stress around it",
     lambda c: fig_stress.force(c.inp)),
    ("piv_maps.png", "Fig. 10a/10b", "Synthetic PIV beside coarse-graining, the intruder's frame",
     lambda c: fig_piv.maps(c.inp)),
    ("piv_frame.png", "Fig. 1c (camera)", "A rendered frame the PIV reads",
     lambda c: fig_piv.frame(c.inp)),
    ("percolation_fabric.png", "Percolation and fabric (R4, R10, no paper figure)",
     "Force-network percolation and fabric anisotropy against height",
     lambda c: fig_percolation.percolation(c.inp)),
]


class Context:
    """The inputs shared by several figures, opened once."""

    def __init__(self, inp):
        self.inp = inp
        self.run = Run(inp)
        self.cg = CG(inp)
        self.ev = events.read(inp)
        self.k34 = nearest(self.run.heights(), NETWORK_HEIGHT_MM)
        self.check_same_run()

    def check_same_run(self):
        """cg, network and friction index the run's snapshots: they must come from this run file."""
        t = self.run.time
        for stage, name, series in (("cg", "cg.h5", self.cg.time), ("network", "network.h5", None),
                                    ("friction", "friction.h5", None)):
            if series is None:
                with self.inp.h5(stage, name) as f:
                    series = f.read("snapshots/time")
            if len(series) != len(t) or not np.allclose(series, t):
                raise InputError(f"{self.inp.path(stage, name)} was made from another run than "
                                 f"{self.run.path} ({len(series)} snapshots against {len(t)}): "
                                 f"run `{self.inp.target(stage)}`")

    def close(self):
        self.run.close()
        self.cg.close()


def placeholder(reason):
    fig, ax = plt.subplots(figsize=(6, 2))
    ax.axis("off")
    ax.text(0.5, 0.5, f"not drawn: {reason}", ha="center", va="center", wrap=True)
    return fig, f"Not drawn: {reason}."


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("results_dir", help="e.g. results/default")
    parser.add_argument("--preset", default="", help="the preset, stamped on every figure with the code version")
    args = parser.parse_args(argv)
    start = time.monotonic()
    inp = Inputs(args.results_dir)
    outdir = os.path.join(args.results_dir, "figures")
    index_path = os.path.join(outdir, "index.json")
    try:
        inp.check()
        os.makedirs(outdir, exist_ok=True)
        if os.path.exists(index_path):
            os.remove(index_path)  # index.json exists only for a complete set
        ctx = Context(inp)
        stamp = " · ".join(x for x in (f"preset {args.preset}" if args.preset else "",
                                       f"dem2d {ctx.run.code_version}", os.path.normpath(args.results_dir)) if x)
        index = []
        for name, label, title, draw in FIGURES:
            try:
                fig, caption = draw(ctx)
            except NoData as e:
                print(f"figures: {label}: {e}", file=sys.stderr)
                fig, caption = placeholder(str(e))
            save(fig, outdir, name, stamp)
            index.append({"file": name, "figure": label, "title": title, "caption": caption})
        ctx.close()
    except InputError as e:
        print(f"figures: {e}", file=sys.stderr)
        return 2
    write_json(index, index_path)
    print(f"figures: {len(index)} figures -> {outdir} ({time.monotonic() - start:.1f} s)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())

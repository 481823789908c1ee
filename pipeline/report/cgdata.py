"""The cg stage's cg.h5 (analysis/cg/README.md): grid, per-snapshot series,
full fields, and which velocity set the figures use (PIV-like if the run has
displacements, else instantaneous)."""

import numpy as np

from pipeline.report.common import MM


class CG:
    def __init__(self, inp):
        self.h5 = inp.h5("cg", "cg.h5")
        m = inp.metrics("cg")
        f = self.h5
        self.floor_y = float(f.attr("floor_y", 0.0))
        self.x = f.read("grid/x") * MM
        self.y = (f.read("grid/y") - self.floor_y) * MM
        self.time = f.read("snapshots/time")
        self.height = f.read("snapshots/intruder_height") * MM
        self.surface = f.read("snapshots/surface_height") * MM
        self.pre_rupture = f.read("snapshots/pre_rupture_event")
        self.piv_valid = f.read("snapshots/piv_valid").astype(bool)
        self.fields = f.read("fields/snapshot")
        self.speed = m["intruder_speed_mm_s"] / MM  # V, m/s
        self.window = m.get("displacement_window_s") or 0.0
        self.set = "piv" if self.piv_valid.any() else "instantaneous"
        self.usable = self.piv_valid if self.set == "piv" else np.ones(len(self.time), bool)

    def close(self):
        self.h5.f.close()

    def describe(self):
        """What the velocities are, for captions."""
        if self.set == "piv":
            return (f"PIV-like velocities (grain displacements over the {self.window * 1e3:.0f} ms before the "
                    "snapshot / window), coarse-grained")
        return ("instantaneous grain velocities, coarse-grained (this run has no PIV-like displacements, so "
                "the bed's ringing shows as noise at v* ≈ 0.25)")

    def field(self, m):
        """Lab-frame (vx, vy) (m/s) of stored field m, NaN where masked."""
        return (self.h5.read(f"fields/vx_{self.set}", m), self.h5.read(f"fields/vy_{self.set}", m))

    def vstar(self, m):
        vx, vy = self.field(m)
        return np.hypot(vx, vy) / self.speed

    def usable_fields(self, below_mm=np.inf):
        """Indices m of the stored fields with the chosen velocity set and the intruder below below_mm."""
        k = self.fields
        return np.flatnonzero(self.usable[k] & (self.height[k] < below_mm))

    def edges(self):
        """Node-cell edges (mm) for pcolormesh."""
        def e(c):
            h = np.diff(c) / 2
            return np.concatenate([[c[0] - h[0]], c[:-1] + h, [c[-1] + h[-1]]])
        return e(self.x), e(self.y)

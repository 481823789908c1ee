"""The pull-off run file (docs/run_file.md): one snapshot's grains, bodies and
contacts, and how to draw them (mm, heights above the floor's face)."""

import numpy as np
from matplotlib.collections import EllipseCollection, LineCollection
from matplotlib.patches import Polygon

from common import MM, InputError, study


class Run:
    """pulloff/run.h5, opened for the whole drawing (close with close())."""

    def __init__(self, inp):
        self.h5 = inp.h5("pulloff", "run.h5")
        self.path = self.h5.path
        names = [str(n) for n in self.h5.dset("bodies/name").asstr()[...]]
        want = study()["bodies"]
        try:
            self.body = {role: names.index(want[role]) for role in ("left", "right", "floor", "intruder")}
        except ValueError as e:
            raise InputError(f"{self.path}: bodies {names} lack one of {dict(want)} (data/study.toml)") from e
        self.thickness = self.h5.read("bodies/thickness")
        self.diameter = self.h5.read("particles/diameter")
        self.time = self.h5.read("snapshots/time")
        self.ends = self.h5.read("snapshots/body_ends")  # [S, B, 4] (ax, ay, bx, by), m
        self.start = self.h5.read("snapshots/contact_start")
        fl = self.ends[0, self.body["floor"]]
        self.floor_y = max(fl[1], fl[3]) + self.thickness[self.body["floor"]] / 2
        vel = self.h5.read("bodies/velocity")[self.body["intruder"]]
        self.speed = float(np.hypot(*vel))  # V, m/s

    def close(self):
        self.h5.f.close()

    def heights(self):
        """Intruder centre above the floor's face at every snapshot (mm)."""
        e = self.ends[:, self.body["intruder"]]
        return ((e[:, 1] + e[:, 3]) / 2 - self.floor_y) * MM

    def grains(self, k):
        """Positions (mm, y above the floor) and diameters (mm) of the active grains."""
        pos = self.h5.read("snapshots/position", k)
        act = self.h5.read("snapshots/active", k).astype(bool)
        xy = pos[act] * MM
        xy[:, 1] -= self.floor_y * MM
        return xy, self.diameter[act] * MM

    def contacts(self, k):
        """Contacts with F_n > 0 of snapshot k: dict of i, j, fn, ft, nx, ny, overlap."""
        a, b = self.start[k], self.start[k + 1]
        c = {n: self.h5.read(f"contacts/{n}", slice(a, b)) for n in ("i", "j", "fn", "ft", "nx", "ny", "overlap")}
        keep = c["fn"] > 0
        return {n: v[keep] for n, v in c.items()}

    def force_segments(self, k):
        """Segments of the normal force network (mm): grain centre to partner centre,
        or to the body's surface; with F_n (N/m)."""
        pos = self.h5.read("snapshots/position", k)
        c = self.contacts(k)
        i, j = c["i"], c["j"]
        p0 = pos[i]
        p1 = np.empty_like(p0)
        grain = j >= 0
        p1[grain] = pos[j[grain]]
        reach = self.diameter[i[~grain]] / 2 - c["overlap"][~grain]  # centre to the body's surface
        n = np.stack([c["nx"], c["ny"]], axis=1)[~grain]
        p1[~grain] = p0[~grain] - n * reach[:, None]
        seg = np.stack([p0, p1], axis=1) * MM
        seg[..., 1] -= self.floor_y * MM
        return seg, c["fn"]

    def body_lines(self, k):
        """[(name, (x0, y0, x1, y1) mm, thickness mm)] of the bodies at snapshot k."""
        out = []
        for role, b in self.body.items():
            ax_, ay, bx, by = self.ends[k, b] * MM
            f = self.floor_y * MM
            out.append((role, (ax_, ay - f, bx, by - f), self.thickness[b] * MM))
        return out


def draw_grains(ax, xy, d, face="0.85", edge="0.55", lw=0.3, alpha=1.0, zorder=1):
    ax.add_collection(EllipseCollection(d, d, np.zeros_like(d), units="xy", offsets=xy,
                                        offset_transform=ax.transData, facecolors=face,
                                        edgecolors=edge, linewidths=lw, alpha=alpha, zorder=zorder))


def stadium(x0, y0, x1, y1, r, n=12):
    """Outline of a sphero-line: the segment with round caps of radius r."""
    phi = np.arctan2(y1 - y0, x1 - x0)
    arc = np.linspace(np.pi / 2, 3 * np.pi / 2, n)
    cap0 = np.stack([x0 + r * np.cos(phi + arc), y0 + r * np.sin(phi + arc)], axis=1)
    cap1 = np.stack([x1 + r * np.cos(phi + arc + np.pi), y1 + r * np.sin(phi + arc + np.pi)], axis=1)
    return np.concatenate([cap0, cap1])


def draw_bodies(ax, run, k, colour="k", zorder=5):
    """Walls, floor and intruder as their sphero-line outlines (walls grey)."""
    for role, (x0, y0, x1, y1), t in run.body_lines(k):
        ax.add_patch(Polygon(stadium(x0, y0, x1, y1, t / 2), closed=True, lw=0, zorder=zorder,
                             facecolor=colour if role == "intruder" else "0.45"))


def draw_network(ax, seg, fn, fn_max, lw_max=3.0, cmap=None, colour="k", zorder=3):
    """Force network: line width proportional to F_n (lw_max at fn_max);
    coloured by F_n if cmap is given. Returns the LineCollection."""
    lines = LineCollection(seg, linewidths=lw_max * fn / fn_max, zorder=zorder, capstyle="round")
    if cmap is not None:
        lines.set_array(fn)
        lines.set_cmap(cmap)
        lines.set_clim(0, fn_max)
    else:
        lines.set_color(colour)
    ax.add_collection(lines)
    return lines


def frame(ax, run, k, top_mm, bottom_mm=0.0):
    """Axes limits on the cell (inner faces) from bottom_mm to top_mm, equal aspect, labels."""
    left = run.ends[k, run.body["left"]]
    right = run.ends[k, run.body["right"]]
    xl = (max(left[0], left[2]) + run.thickness[run.body["left"]] / 2) * MM
    xr = (min(right[0], right[2]) - run.thickness[run.body["right"]] / 2) * MM
    ax.set_xlim(xl - 1, xr + 1)
    ax.set_ylim(bottom_mm - 1, top_mm)
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("height above the floor (mm)")

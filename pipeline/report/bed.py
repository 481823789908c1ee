"""The pull-off run file (docs/run_file.md): one snapshot's grains, bodies and
contacts, and how to draw them (mm, heights above the floor's face)."""

import numpy as np
from matplotlib.collections import EllipseCollection, LineCollection
from matplotlib.patches import Polygon

import dem2d
from pipeline.report.common import MM, InputError


class Run:
    """pulloff/run.h5 through the run-file reader (python/dem2d), opened for the
    whole drawing (close with close())."""

    def __init__(self, inp):
        self.path = inp.path("pulloff", "run.h5")
        if not self.path.is_file():
            raise inp.missing("pulloff", "run.h5")
        try:
            self.run = dem2d.Run(self.path)
        except (OSError, ValueError) as e:
            raise InputError(f"{e}: run `{inp.target('pulloff')}`") from e
        bodies = self.run.bodies
        want = ("left_wall", "right_wall", "floor", "intruder")
        try:
            self.body = {role: self.run.body(role) for role in want}  # role -> dem2d.Body
        except KeyError as e:
            raise InputError(f"{self.path}: no body has one of the roles {list(want)} "
                             f"(bodies {[b.name for b in bodies]}, roles {[b.role for b in bodies]}); "
                             "the scene declares them: [[body]] role") from e
        self.code_version = str(self.run.attrs["code_version"])  # the engine that made the run
        self.diameter = self.run.particles.diameter
        self.time = self.run.times
        self.vertices = self.run.dataset("snapshots/body_vertices")  # [S, B, K, 2] m
        self.floor_y = self.run.floor_top()
        vel = self.run.dataset("bodies/velocity")[self.body["intruder"].index]
        self.speed = float(np.hypot(*vel))  # V, m/s

    def close(self):
        self.run.close()

    def core(self, k, role):
        """The core outline (m) of the body with this role at snapshot k: [n, 2]."""
        return self.body[role].core(self.vertices[k])

    def heights(self):
        """Intruder centre (mean of its core's vertices) above the floor's face at every snapshot (mm)."""
        return self.run.heights("intruder") * MM

    def grains(self, k):
        """Positions (mm, y above the floor) and diameters (mm) of the active grains."""
        s = self.run.snapshot(k)
        xy = s.position[s.active] * MM
        xy[:, 1] -= self.floor_y * MM
        return xy, self.diameter[s.active] * MM

    def contacts(self, k):
        """Contacts with F_n > 0 of snapshot k: dict of i, j, fn, ft, nx, ny, overlap."""
        c = self.run.contacts(k)
        keep = c.fn > 0
        return {"i": c.i[keep], "j": c.j[keep], "fn": c.fn[keep], "ft": c.ft[keep], "nx": c.normal[keep, 0],
                "ny": c.normal[keep, 1], "overlap": c.overlap[keep]}

    def force_segments(self, k):
        """Segments of the normal force network (mm): grain centre to partner centre,
        or to the body's surface; with F_n (N/m)."""
        pos = self.run.snapshot(k).position
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

    def body_outlines(self, k):
        """[(role, outline [m, 2] in mm, y above the floor)] of the bodies at snapshot k."""
        out = []
        for role, b in self.body.items():
            xy = outline(b.core(self.vertices[k]), b.thickness / 2) * MM
            xy[:, 1] -= self.floor_y * MM
            out.append((role, xy))
        return out


def outline(core, r, n=16):
    """Outline of a convex sphero-polygon (docs/run_file.md): the convex hull of
    circles of radius r about the core's vertices [m, 2]."""
    phi = np.linspace(0, 2 * np.pi, n, endpoint=False)
    ring = np.stack([np.cos(phi), np.sin(phi)], axis=1) * r
    pts = (core[:, None, :] + ring[None, :, :]).reshape(-1, 2) if r > 0 else np.asarray(core, float)
    pts = np.unique(pts, axis=0)  # sorted by x, then y: Andrew's monotone chain
    if len(pts) < 3:
        return pts

    def half(points):
        h = []
        for p in points:
            while len(h) >= 2 and ((h[-1][0] - h[-2][0]) * (p[1] - h[-2][1])
                                   - (h[-1][1] - h[-2][1]) * (p[0] - h[-2][0])) <= 0:
                h.pop()
            h.append(p)
        return h[:-1]

    return np.array(half(pts) + half(pts[::-1]))


def draw_grains(ax, xy, d, face="0.85", edge="0.55", lw=0.3, alpha=1.0, zorder=1):
    ax.add_collection(EllipseCollection(d, d, np.zeros_like(d), units="xy", offsets=xy,
                                        offset_transform=ax.transData, facecolors=face,
                                        edgecolors=edge, linewidths=lw, alpha=alpha, zorder=zorder))


def draw_bodies(ax, run, k, colour="k", zorder=5):
    """Walls, floor and intruder as their outlines (walls grey)."""
    for role, xy in run.body_outlines(k):
        ax.add_patch(Polygon(xy, closed=True, lw=0, zorder=zorder,
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
    xl = (run.core(k, "left_wall")[:, 0].max() + run.body["left_wall"].thickness / 2) * MM
    xr = (run.core(k, "right_wall")[:, 0].min() - run.body["right_wall"].thickness / 2) * MM
    ax.set_xlim(xl - 1, xr + 1)
    ax.set_ylim(bottom_mm - 1, top_mm)
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("height above the floor (mm)")

"""Drawing a snapshot with matplotlib (imported only when this module is):
grains as discs, bodies as their rounded outlines' cores, contacts as lines."""
import numpy as np
from matplotlib.collections import EllipseCollection, LineCollection
from matplotlib.patches import Circle, Polygon


def draw_grains(ax, run, snap, colour="0.85", edge="0.6", values=None, cmap="viridis"):
    """The active grains of `snap` as discs of their diameters (m); coloured by `values` [N] if given."""
    act = snap.active
    d = run.particles.diameter[act]
    discs = EllipseCollection(d, d, np.zeros_like(d), units="xy", offsets=snap.position[act],
                              offset_transform=ax.transData, edgecolors=edge, linewidths=0.3)
    if values is None:
        discs.set_facecolor(colour)
    else:
        discs.set_array(np.asarray(values)[act])
        discs.set_cmap(cmap)
    ax.add_collection(discs)
    ax.set_aspect("equal")
    return discs


def draw_bodies(ax, run, snap, colour="#1f77b4"):
    """Every body as it is in data units (m): its core swept by a disc of its thickness (a segment a
    stadium, a polygon with rounded corners), so that the drawing does not depend on the axes' limits
    or on when it is drawn. A body of zero thickness is its core's outline."""
    for b in run.bodies:
        core = np.asarray(b.core(snap.body_vertices), dtype=float)
        closed = b.vertex_count >= 3
        if b.thickness <= 0:
            ring = np.vstack([core, core[:1]]) if closed else core
            ax.plot(ring[:, 0], ring[:, 1], color=colour, lw=1.0)
            continue
        half = b.thickness / 2
        if closed:
            ax.add_patch(Polygon(core, closed=True, facecolor=colour, edgecolor="none", zorder=2))
        ends = range(len(core) if closed else len(core) - 1)
        for k in ends:
            a, c = core[k], core[(k + 1) % len(core)]
            length = np.hypot(*(c - a))
            if length > 0:
                n = np.array([a[1] - c[1], c[0] - a[0]]) * (half / length)
                ax.add_patch(Polygon([a + n, c + n, c - n, a - n], closed=True, facecolor=colour, edgecolor="none", zorder=2))
        for v in core:
            ax.add_patch(Circle(v, half, facecolor=colour, edgecolor="none", zorder=2))


def draw_contacts(ax, snap, width_max=3.0, cmap="inferno_r"):
    """Contacts with F_n > 0 as lines (centre to centre, or to the contact point on a body), width and
    colour growing with F_n."""
    c = snap.contacts
    pressing = c.fn > 0
    fn = c.fn[pressing]
    lines = LineCollection(c.line[pressing], linewidths=0.2 + width_max * fn / max(fn.max(initial=0), 1e-300),
                           cmap=cmap)
    lines.set_array(fn)
    ax.add_collection(lines)
    return lines


def frame(ax, run, snap, margin=0.003):
    """Limits around the active grains and the bodies (m)."""
    act = snap.active
    r = run.particles.diameter[act] / 2
    xy = snap.position[act]
    v = snap.body_vertices.reshape(-1, 2)
    ax.set_xlim(min((xy[:, 0] - r).min(), v[:, 0].min()) - margin, max((xy[:, 0] + r).max(), v[:, 0].max()) + margin)
    ax.set_ylim(min((xy[:, 1] - r).min(), v[:, 1].min()) - margin, (xy[:, 1] + r).max() + 4 * margin)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")

"""Drawing a snapshot with matplotlib (imported only when this module is):
grains as discs, bodies as their rounded outlines' cores, contacts as lines."""
import numpy as np
from matplotlib.collections import EllipseCollection, LineCollection


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
    """Every body's core, drawn with its rounding's thickness (a segment is a line, a polygon closed)."""
    for b in run.bodies:
        core = b.core(snap.body_vertices)
        if b.vertex_count >= 3:
            core = np.vstack([core, core[:1]])
        width_pt = max(1.0, b.thickness * points_per_metre(ax))
        ax.plot(core[:, 0], core[:, 1], color=colour, lw=width_pt, solid_capstyle="round")


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


def points_per_metre(ax):
    """How many typographic points one metre of data spans in x (for line widths in data units)."""
    ax.figure.canvas.draw_idle()
    x0, x1 = ax.get_xlim()
    width_in = ax.get_window_extent().width / ax.figure.dpi
    return 72.0 * width_in / max(x1 - x0, 1e-300)


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

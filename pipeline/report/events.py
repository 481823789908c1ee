"""The spectrum stage's loading/rupture events (spectrum.h5 /events) and the
phase of the drag cycle a snapshot falls in."""

import numpy as np

NAMES = ("load_start_time", "peak_time", "drop_end_time", "peak_height", "drop")


def read(inp):
    with inp.h5("spectrum", "spectrum.h5") as f:
        return {n: f.read(f"events/{n}") for n in NAMES}


def phase(ev, t):
    """('loading' | 'drop' | 'between', event index or -1) of time t (s)."""
    k = int(np.searchsorted(ev["load_start_time"], t, side="right")) - 1
    if k < 0:
        return "between", -1
    if t <= ev["peak_time"][k]:
        return "loading", k
    if t <= ev["drop_end_time"][k]:
        return "drop", k
    return "between", k


def seconds(dt):
    """A time interval for a title: ms below one second."""
    return f"{dt * 1e3:.0f} ms" if abs(dt) < 1 else f"{dt:.2f} s"


def describe(ev, t):
    what, k = phase(ev, t)
    if what == "loading":
        return f"loading, {seconds(ev['peak_time'][k] - t)} before peak {k}"
    if what == "drop":
        return f"during drop {k}"
    return "between events" if k < 0 else f"{seconds(t - ev['drop_end_time'][k])} after drop {k}"


def rupture_snapshots(ev, times, window, lag, usable, min_height_mm=0.0):
    """For each event (largest drop first, peak above min_height_mm): the first usable snapshot
    whose velocity window [t - window, t] starts after the peak and at most lag after the drop's
    end. Returns [(event, snapshot)]."""
    out = []
    start = times - window
    for e in np.argsort(-ev["drop"]):
        if ev["peak_height"][e] * 1e3 < min_height_mm:
            continue
        sel = np.flatnonzero(usable & (start > ev["peak_time"][e]) & (start <= ev["drop_end_time"][e] + lag))
        if len(sel):
            out.append((int(e), int(sel[0])))
    return out

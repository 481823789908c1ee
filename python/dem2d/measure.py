"""Small measurements on a snapshot's grains."""
import math

import numpy as np


def surface(pos, d):
    """The free surface of a packing: the highest grain centre in each bin of width d (m), as [bins, 2]."""
    x, y = pos[:, 0], pos[:, 1]
    idx = np.digitize(x, np.arange(x.min(), x.max() + d, d))
    return np.array([(x[idx == k][np.argmax(y[idx == k])], y[idx == k].max()) for k in np.unique(idx)])


def heap_angle(pos, d):
    """A heap's angle of repose (deg): the mean of its two flanks' slopes, lines fitted to the free
    surface (bins of width d) where it lies between 20 % and 80 % of the peak's height; 0 if there
    is no heap (fewer than 3 surface points on each flank)."""
    top = surface(pos, d)
    peak = top[:, 1].max()
    xp = top[np.argmax(top[:, 1]), 0]
    band = (top[:, 1] > 0.2 * peak) & (top[:, 1] < 0.8 * peak)
    angles = []
    for side in (top[:, 0] < xp, top[:, 0] > xp):
        sel = band & side
        if sel.sum() >= 3:
            angles.append(abs(math.degrees(math.atan(np.polyfit(top[sel, 0], top[sel, 1], 1)[0]))))
    return float(np.mean(angles)) if angles else 0.0

"""An independent reference for single impacts: the contact law of
docs/contact_law.md as a continuous ODE, integrated with fourth-order
Runge-Kutta at a step far below dt_c (default t_c / 4000), the Coulomb cap
applied after each step. Two disks, or a disk and a flat wall (the face
y = 0, infinite mass). No gravity, no rolling resistance: the impact
benchmarks' setting."""
import math

import numpy as np


def nu_of_e(e: float) -> float:
    """The damping ratio of the non-attractive linear law for restitution e
    (docs/contact_law.md): e = exp(-2 nu g(nu)), g = arccos(nu)/sqrt(1 - nu^2)."""
    def restitution(nu):
        if nu == 0.0:
            return 1.0
        s = nu * nu - 1.0
        g = 1.0 - s / 6.0 if abs(s) < 1e-6 else (math.acos(nu) / math.sqrt(-s) if s < 0 else math.acosh(nu) / math.sqrt(s))
        return math.exp(-2.0 * nu * g)
    if e >= 1.0:
        return 0.0
    lo, hi = 0.0, 1.0
    while restitution(hi) > e:
        hi *= 2.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if restitution(mid) > e else (lo, mid)
    return 0.5 * (lo + hi)


def impact(d1, v1, w1, law, d2=None, v2=(0.0, 0.0), w2=0.0, density=2500.0, steps_per_contact=4000):
    """Disk 1 (diameter d1, velocity v1, spin w1) hits disk 2 (d2, v2, w2) along
    x (disk 2 to its right, both at y = 0, just touching), or, with d2 None,
    falls on the wall y = 0 (it starts just above, v1 pointing down).
    law: kn, kt, restitution, friction (SI). Returns the velocities and spins
    once the two have parted: (v1', w1', v2', w2')."""
    wall = d2 is None
    m1 = density * math.pi * d1 * d1 / 4
    i1 = m1 * d1 * d1 / 8
    m2 = math.inf if wall else density * math.pi * d2 * d2 / 4
    i2 = math.inf if wall else m2 * d2 * d2 / 8
    meff = m1 if wall else m1 * m2 / (m1 + m2)
    kn, kt, mu = law["kn"], law["kt"], law["friction"]
    c = 2.0 * nu_of_e(law["restitution"]) * math.sqrt(meff * kn)
    r1, r2 = d1 / 2, (0.0 if wall else d2 / 2)
    # state: x1 y1 vx1 vy1 w1 x2 y2 vx2 vy2 w2 S
    s = np.array([0.0, r1 if wall else 0.0, *v1, w1, r1 + r2, 0.0, *v2, w2, 0.0])
    if wall:
        s[5:10] = 0.0

    def contact(s):
        if wall:
            n = np.array([0.0, 1.0])
            gap = s[1] - r1
        else:
            dx = s[0:2] - s[5:7]
            dist = math.hypot(*dx)
            n = dx / dist
            gap = dist - r1 - r2
        return n, gap

    def derivative(s):
        n, gap = contact(s)
        out = np.zeros_like(s)
        out[0:2], out[5:7] = s[2:4], s[7:9]
        out[4] = 0.0
        if gap >= 0.0:
            return out
        overlap = -gap
        t = np.array([-n[1], n[0]])
        rv = s[2:4] - s[7:9]
        a1, a2 = r1 - overlap / 2, (0.0 if wall else r2 - overlap / 2)
        vn, vt = rv @ n, rv @ t - (a1 * s[4] + a2 * s[9])
        fn = max(0.0, kn * overlap - c * vn)
        f = fn * n + s[10] * t
        out[2:4] = f / m1
        out[4] = -a1 * s[10] / i1
        if not wall:
            out[7:9] = -f / m2
            out[9] = -a2 * s[10] / i2
        out[10] = -kt * vt
        return out

    tc = math.pi * math.sqrt(meff / kn)
    h = tc / steps_per_contact
    touched = False
    for _ in range(50 * steps_per_contact):
        k1 = derivative(s)
        k2 = derivative(s + 0.5 * h * k1)
        k3 = derivative(s + 0.5 * h * k2)
        k4 = derivative(s + h * k3)
        s = s + h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)
        n, gap = contact(s)
        if gap < 0.0:
            touched = True
            fn = max(0.0, kn * -gap - c * ((s[2:4] - s[7:9]) @ n))
            s[10] = min(max(s[10], -mu * fn), mu * fn)  # the Coulomb cap
        else:
            s[10] = 0.0
            if touched:
                break
    return s[2:4].copy(), s[4], s[7:9].copy(), s[9]

#!/usr/bin/env python3
"""Reference impacts of a 2-DOF chain with a stop on each coordinate, at 30
digits (python3-mpmath), for tests/sim/test_exact_stops.c.

Written independently of the library: the modes of M = I, K = [[2, -1],
[-1, 2]] are known in closed form (psi = (1, 1)/sqrt 2, lambda = 1 and
psi = (1, -1)/sqrt 2, lambda = 3); with C = 0.05 K each mode is a damped
oscillator q'' + d q' + lambda q = F cos(Omega t), d = 0.05 lambda, whose
motion is the harmonic particular solution plus the underdamped free
oscillation.  Contacts are found by sampling both gaps g_k(t) = w_k.x(t) -
x_k on a fine grid (0.02, some 180 points per period of the fastest mode)
and refining each sign change, and each maximum of g_k inside a grid step
(a graze), by mpmath.findroot at 30 digits.  The impact law for one stop,
M = I, |w| = 1: v+ = v - (1 + r) (w.v) w.

Scene: forcing a = (1, 0) cos(1.3 t); stop 0: x_1 <= 0.3, r = 0.8; stop 1:
-x_2 <= 0.25 (x_2 >= -0.25), r = 0.6; start at rest at the origin, t = 0.

Prints, per impact: time, stop, approach speed w.v-, and the velocity after.
Run: python3 tests/stress/ref/exact_two_stops.py [N]
"""
import sys

import mpmath as mp

mp.mp.dps = 30

OM = mp.mpf("1.3")
S2 = mp.sqrt(2)
PSI = [[1 / S2, 1 / S2], [1 / S2, -1 / S2]]  # PSI[j] = mode j's shape
LAM = [mp.mpf(1), mp.mpf(3)]
DMP = [mp.mpf("0.05") * l for l in LAM]
A = [mp.mpf(1), mp.mpf(0)]
FM = [PSI[j][0] * A[0] + PSI[j][1] * A[1] for j in range(2)]
W = [[mp.mpf(1), mp.mpf(0)], [mp.mpf(0), mp.mpf(-1)]]
XS = [mp.mpf("0.3"), mp.mpf("0.25")]
R = [mp.mpf("0.8"), mp.mpf("0.6")]


def particular(j, t):
    """Harmonic particular solution of mode j and its rate at t."""
    p = LAM[j] - OM ** 2
    s = DMP[j] * OM
    det = p * p + s * s
    a = p * FM[j] / det
    b = s * FM[j] / det
    c, sn = mp.cos(OM * t), mp.sin(OM * t)
    return a * c + b * sn, OM * (b * c - a * sn)


def homogeneous(j, u0, v0, tau):
    """Free damped oscillation of mode j from (u0, v0) after tau."""
    h = DMP[j] / 2
    mu = mp.sqrt(LAM[j] - h * h)
    e = mp.exp(-h * tau)
    c, sn = mp.cos(mu * tau), mp.sin(mu * tau)
    u = e * (u0 * c + (v0 + h * u0) * sn / mu)
    ud = e * (v0 * c - (h * v0 + LAM[j] * u0) * sn / mu)
    return u, ud


class Flight:
    def __init__(self, t0, x, v):
        self.t0 = t0
        self.u0, self.v0 = [], []
        for j in range(2):
            q = PSI[j][0] * x[0] + PSI[j][1] * x[1]
            qd = PSI[j][0] * v[0] + PSI[j][1] * v[1]
            qp, qpd = particular(j, t0)
            self.u0.append(q - qp)
            self.v0.append(qd - qpd)

    def state(self, t):
        x, v = [mp.mpf(0)] * 2, [mp.mpf(0)] * 2
        for j in range(2):
            qp, qpd = particular(j, t)
            u, ud = homogeneous(j, self.u0[j], self.v0[j], t - self.t0)
            for i in range(2):
                x[i] += PSI[j][i] * (qp + u)
                v[i] += PSI[j][i] * (qpd + ud)
        return x, v

    def gap(self, k, t):
        x, v = self.state(t)
        return (W[k][0] * x[0] + W[k][1] * x[1] - XS[k],
                W[k][0] * v[0] + W[k][1] * v[1])


def first_crossing(f, k, a, b, ga, gda, gb, gdb):
    """First t in (a, b] with g_k(t) = 0 rising, grazes included."""
    lo, hi = a, b
    if gda > 0 and gdb < 0:  # a maximum inside: the rising piece [a, tm]
        tm = mp.findroot(lambda t: f.gap(k, t)[1], (a, b), solver="anderson")
        if f.gap(k, tm)[0] >= 0:
            hi = tm
        elif gb < 0:
            return None
    if ga < 0 and f.gap(k, hi)[0] >= 0:
        return mp.findroot(lambda t: f.gap(k, t)[0], (lo, hi),
                           solver="anderson")
    return None


def main(nimp):
    t = mp.mpf(0)
    x, v = [mp.mpf(0)] * 2, [mp.mpf(0)] * 2
    last = -1
    h = mp.mpf("0.02")
    out = []
    while len(out) < nimp:
        f = Flight(t, x, v)
        a = t
        gs = [list(f.gap(k, a)) for k in range(2)]
        if last >= 0:  # on the stop just hit, leaving it
            gs[last][0] = -abs(gs[last][0])
        hit = None
        while hit is None:
            b = a + h
            gb = [f.gap(k, b) for k in range(2)]
            best = None
            for k in range(2):
                tc = first_crossing(f, k, a, b, gs[k][0], gs[k][1], gb[k][0],
                                    gb[k][1])
                if tc is not None and (best is None or tc < best[0]):
                    best = (tc, k)
            hit = best
            a = b
            gs = [list(g) for g in gb]
        tc, k = hit
        x, v = f.state(tc)
        vn = W[k][0] * v[0] + W[k][1] * v[1]
        v = [v[i] - (1 + R[k]) * vn * W[k][i] for i in range(2)]
        out.append((tc, k, vn, v))
        t, last = tc, k
    for tc, k, vn, vp in out:
        print("{%s, %d, %s, %s, %s}," % (mp.nstr(tc, 20), k, mp.nstr(vn, 20),
                                         mp.nstr(vp[0], 20), mp.nstr(vp[1], 20)))


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 24)

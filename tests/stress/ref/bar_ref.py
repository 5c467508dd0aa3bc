#!/usr/bin/python3
"""Independent reference for the impacting bar (tests/sim/test_held.c,
bench/vi_bench_bar.c): Siconos' examples/Mechanics/ImpactingBar, a free bar
of N linear elements with consistent mass, E = 210e9, S = 3.14e-4, L = 1,
rho = 7800, every node at x = 5e-5 moving at v = -0.1 onto a rigid obstacle
at node 1 (x_1 >= 0, r = 0).

Not the library's method: the bar reaches the obstacle as a rigid body at
t_c = 5e-4 exactly; the plastic impact (Newton, r = 0) takes node 1's
velocity away along M^-1 e_1; then node 1 is held and the other nodes move
as the bar clamped at node 1 (scipy.linalg.eigh of the reduced M, K, i.e.
eliminating x_1 = 0 rather than projecting in the free modes).  The
obstacle's force is row 1 of M x'' + K x, a sum of sines over the clamped
modes; the release is its first zero, bracketed on a grid of 1/40 of the
fastest period and refined by brentq.  The momentum then is that of the
free flight after release: the rebound speed is P / (rho S L).

Continuum limit (d'Alembert): the contact lasts 2 L / c, c = sqrt(E/rho),
and the bar leaves at 0.1 m/s.

Usage: bar_ref.py [N ...]   (default: the meshes the test and bench use)
"""
import sys

import numpy as np
from scipy.linalg import eigh
from scipy.optimize import brentq

E, S, L, RHO, X0, V0 = 210e9, 3.14e-4, 1.0, 7800.0, 5e-5, -0.1


def bar(ne):
    n = ne + 1
    h = L / ne
    m, k = RHO * S * h, E * S / h
    M = np.zeros((n, n))
    K = np.zeros((n, n))
    for e in range(ne):
        i, j = e, e + 1
        M[np.ix_([i, j], [i, j])] += m * np.array([[1 / 3, 1 / 6], [1 / 6, 1 / 3]])
        K[np.ix_([i, j], [i, j])] += k * np.array([[1, -1], [-1, 1]])
    return M, K


def release(ne):
    M, K = bar(ne)
    n = ne + 1
    tc = X0 / -V0
    v = np.full(n, V0)
    # plastic impact on the stop -x_1 <= 0: v -= (w.v) M^-1 w / (w.M^-1 w)
    w = np.zeros(n)
    w[0] = -1.0
    mw = np.linalg.solve(M, w)
    v = v - (w @ v) * mw / (w @ mw)
    # node 1 held: the clamped bar of nodes 2..n, from x = 0 with v[1:]
    Mr, Kr = M[1:, 1:], K[1:, 1:]
    om2, Phi = eigh(Kr, Mr)
    om = np.sqrt(om2)
    bd = Phi.T @ (Mr @ v[1:])  # modal velocities (Phi^T Mr Phi = I)
    # force on node 1: M_1r x_r'' + K_1r x_r, x_r = Phi (bd sin(om t) / om)
    c = (K[0, 1:] @ Phi - om2 * (M[0, 1:] @ Phi)) * bd / om

    def lam(t):
        return np.sin(np.outer(np.atleast_1d(t), om)) @ c

    T = 2 * L / np.sqrt(E / RHO)
    dt = 2 * np.pi / om[-1] / 40
    t0 = dt
    while t0 < 2 * T:
        ts = t0 + dt * np.arange(4096)
        f = lam(ts)
        neg = np.nonzero(f < 0)[0]
        if neg.size:
            i = neg[0]
            a = ts[i - 1] if i > 0 else t0 - dt
            tr = brentq(lambda t: lam(t)[0], a, ts[i], xtol=1e-22, rtol=1e-15,
                        maxiter=500)
            # momentum after release: the bar is free from here on
            x = Phi @ (bd * np.sin(om * tr) / om)
            xd = Phi @ (bd * np.cos(om * tr))
            vr = np.concatenate(([0.0], xd))
            P = np.ones(n) @ (M @ vr)
            return tc + tr, P / (RHO * S * L)
        t0 = ts[-1] + dt
    raise RuntimeError("no release")


def main():
    meshes = [int(a) for a in sys.argv[1:]] or [10, 20, 50, 100, 200, 500]
    c = np.sqrt(E / RHO)
    print("# continuum: release at %.17g, rebound 0.1" % (X0 / -V0 + 2 * L / c))
    for ne in meshes:
        tr, vr = release(ne)
        print("%5d  t_release = %.17g  v_rebound = %.17g" % (ne, tr, vr))


if __name__ == "__main__":
    main()

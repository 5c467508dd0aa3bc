#!/usr/bin/env python3
"""The energy ledger of a run against mpmath, interval by interval.

    ledger_check.py RUN.h5 [MORE.h5 ...]

RUN.h5 is `vibroimpact run ... -o RUN.h5` of a scene with proportional,
underdamped modes, harmonic forcing and one stop (Fig. 2, the default).
Each impact-free interval [t_a, t_b] starts from the run's own state (the
initial state, or the state after the impact at t_a: impacts/x, v_plus);
from there mode j moves exactly as q'' + d q' + lambda q = Fa cos + Fb sin
+ F0 (the modal model as written to the file, its doubles taken as exact),
in closed form at 32 digits, and FE_j = int q' F, DE_j = d int q'^2 are
integrated by mpmath.quad.  Prints, per dataset, the largest and median
relative error of the file's ledger/FE and ledger/DE.  What the reference
shares with the run is its starting states and times; the rest is the
ODE.  About a second per interval (Debian: python3-h5py, python3-mpmath).
"""
import sys

import h5py
import mpmath as mp
import numpy as np

mp.mp.dps = 32


def check(path):
    f = h5py.File(path, "r")
    Om = mp.mpf(float(f["model"].attrs["Omega"]))
    M = mp.matrix(np.array(f["model/M"]).tolist())
    P = mp.matrix(np.array(f["modal/Psi"]).tolist())
    om = np.array(f["modal/omega"])
    D = np.array(f["modal/D"])
    n = len(om)
    PT = P.T
    Fa, Fb, F0 = (PT * mp.matrix(np.array(f["model/" + k]).tolist())
                  for k in ("a", "b", "f0"))
    ta, tb = np.array(f["ledger/t_a"]), np.array(f["ledger/t_b"])
    it = np.array(f["impacts/time"])
    ix, iv = np.array(f["impacts/x"]), np.array(f["impacts/v_plus"])
    FE, DE = np.array(f["ledger/FE"]), np.array(f["ledger/DE"])
    ref = np.zeros((len(ta), n, 2))
    for i in range(len(ta)):
        if i == 0:
            x, v = np.zeros(n), np.zeros(n)  # the scene's initial state
        else:
            k = int(np.searchsorted(it, ta[i]))
            x, v = ix[k], iv[k]
        t0, t1 = mp.mpf(float(ta[i])), mp.mpf(float(tb[i]))
        q0 = PT * M * mp.matrix(list(map(float, x)))
        qd0 = PT * M * mp.matrix(list(map(float, v)))
        for j in range(n):
            lam, d = mp.mpf(float(om[j])) ** 2, mp.mpf(float(D[j, j]))
            den = (lam - Om**2) ** 2 + (d * Om) ** 2
            pA = ((lam - Om**2) * Fa[j] - d * Om * Fb[j]) / den
            pB = ((lam - Om**2) * Fb[j] + d * Om * Fa[j]) / den

            def H(t):
                return pA * mp.cos(Om * t) + pB * mp.sin(Om * t)

            def Hd(t):
                return Om * (pB * mp.cos(Om * t) - pA * mp.sin(Om * t))

            h = d / 2
            mu = mp.sqrt(lam - h * h)
            u0 = q0[j] - H(t0) - F0[j] / lam
            ud0 = qd0[j] - Hd(t0)
            b = (ud0 + h * u0) / mu

            def qd(t):
                s = t - t0
                c, sn = mp.cos(mu * s), mp.sin(mu * s)
                return Hd(t) + mp.exp(-h * s) * (
                    -h * (u0 * c + b * sn) + mu * (b * c - u0 * sn))

            def F(t):
                return Fa[j] * mp.cos(Om * t) + Fb[j] * mp.sin(Om * t) + F0[j]

            pts = mp.linspace(t0, t1, 9)
            ref[i, j, 0] = float(mp.quad(lambda t: qd(t) * F(t), pts))
            ref[i, j, 1] = float(d * mp.quad(lambda t: qd(t) ** 2, pts))
    for name, k, lib in (("FE", 0, FE), ("DE", 1, DE)):
        err = np.abs(lib - ref[:, :, k]) / np.abs(ref[:, :, k])
        print(f"{path} ledger/{name}: relative error vs mpmath max "
              f"{err.max():.3g}, median {np.median(err):.3g} "
              f"({err.size} values)")


for p in sys.argv[1:]:
    check(p)

#!/usr/bin/python3
"""Independent synthetic recordings for the identification tests
(test_identify, doc/identify.md): steady P(1,1) motions of the paper's
Fig. 2 chain and of the 4-mode cantilever (share/scenes/fig2.yaml,
cantilever4.yaml), simulated with SciPy (DOP853, event location of the
stop, Newton's impact law WB 2 applied at each contact), not with
vibroimpact's code.  The beam's modes come from mpmath roots of
cos(b) cosh(b) = -1 and the clamped-free shape functions.

Each file holds one forcing period of the settled motion, 64 samples
(t, x = w.x, v = w.x'), t = 0 at model time T0 (comment line); the tests
repeat it over P periods (the motion is periodic) and add noise.  The
jittered file holds 10 periods at non-uniform times.  Usage:
  gen_identify_data.py OUTDIR [clearance|beam4_acc|beam4_acc_rate|fig2_dof1]"""
import math
import sys

import mpmath as mp
import numpy as np
from scipy.integrate import solve_ivp


def beam(modes=4, omega1=1.0, zeta=0.05, base=0.01):
    bs = [mp.findroot(lambda b: mp.cos(b) * mp.cosh(b) + 1, g)
          for g in (1.875, 4.694, 7.855, 10.996)[:modes]]
    w, gam, om = [], [], []
    for b in bs:
        s = (mp.cosh(b) + mp.cos(b)) / (mp.sinh(b) + mp.sin(b))
        phi = lambda xi: (mp.cosh(b * xi) - mp.cos(b * xi)
                          - s * (mp.sinh(b * xi) - mp.sin(b * xi)))
        nrm = mp.sqrt(mp.quad(lambda xi: phi(xi) ** 2, [0, 1]))
        w.append(float(phi(1) / nrm))
        gam.append(float(mp.quad(phi, [0, 1]) / nrm))
        om.append(omega1 * float((b / bs[0]) ** 2))
    n = modes
    M = np.eye(n)
    K = np.diag(np.array(om) ** 2)
    C = np.diag(2 * zeta * np.array(om))
    a = -base * np.array(gam)
    return M, C, K, a, np.array(w)


def chain2():
    E = np.array([[2.0, -1.0], [-1.0, 1.0]])
    return np.eye(2), 0.1 * E, E, np.array([0.5, 0.0]), np.array([0.0, 1.0])


def simulate(M, C, K, a, w, Om, xs, r, t_end, t_rec, times, stops=None,
             accel=None):
    """Run from rest to t_end; return w.x, w.v at the given times (all
    >= t_rec) by dense output between impacts.  stops: a list of (w_k,
    xs_k, r_k) for several stops (w, xs, r then name the observation).
    accel: an array that receives w.x'' = w.M^-1 (a cos(Om t) - C v - K x)
    at the times (an accelerometer's reading)."""
    n = len(w)
    Mi = np.linalg.inv(M)
    stops = stops or [(w, xs, r)]

    def rhs(t, z):
        x, v = z[:n], z[n:]
        return np.concatenate([v, Mi @ (a * math.cos(Om * t) - C @ v - K @ x)])

    def make_gap(wk, xk):
        def gap(t, z):
            return wk @ z[:n] - xk
        gap.terminal = True
        gap.direction = 1
        return gap
    gaps = [make_gap(np.asarray(wk), xk) for wk, xk, _ in stops]
    z = np.zeros(2 * n)
    t = 0.0
    out_x = np.full(len(times), np.nan)
    out_v = np.full(len(times), np.nan)
    impacts = 0
    while t < t_end:
        sol = solve_ivp(rhs, (t, t_end), z, method='DOP853', rtol=1e-12,
                        atol=1e-14, events=gaps, dense_output=True)
        t1 = sol.t[-1]
        sel = (times >= t) & (times <= t1)
        if sel.any():
            zz = sol.sol(times[sel])
            out_x[sel] = w @ zz[:n]
            out_v[sel] = w @ zz[n:]
            if accel is not None:
                for i, tt in zip(np.nonzero(sel)[0], times[sel]):
                    accel[i] = w @ rhs(tt, zz[:, list(times[sel]).index(tt)])[n:]
        if sol.status == 1:  # an impact on stop k: WB 2
            k = [i for i, te in enumerate(sol.t_events) if len(te)][0]
            z = sol.y_events[k][0].copy()
            t = sol.t_events[k][0]
            wk, rk = np.asarray(stops[k][0]), stops[k][2]
            Miw = Mi @ wk
            vn = wk @ z[n:]
            z[n:] -= (1 + rk) * vn * Miw / (wk @ Miw)
            impacts += 1
        else:
            break
    return out_x, out_v, impacts


def write(path, T0, t, x, v, note):
    with open(path, 'w') as f:
        f.write(f"# {note}\n# T0 = {T0!r}\nt,x,v\n")
        for a, b, c in zip(t, x, v):
            f.write(f"{a!r},{b!r},{c!r}\n")


def write_acc(path, T0, t, x, v, acc, note):
    with open(path, 'w') as f:
        f.write(f"# {note}\n# T0 = {T0!r}\nt,x,v,a\n")
        for a, b, c, d in zip(t, x, v, acc):
            f.write(f"{a!r},{b!r},{c!r},{d!r}\n")


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else '.'
    rng = np.random.default_rng(7)
    only = sys.argv[2] if len(sys.argv) > 2 else None
    # share/scenes/clearance.yaml at a = (0.3, 0), Omega = 1.7: a P(1,2)
    # orbit with one impact on each of the two stops x_2 = +-0.1 (r = 0.8)
    E = np.array([[2.0, -1.0], [-1.0, 1.0]])
    M2, C2, a2 = np.eye(2), 0.05 * E, np.array([0.3, 0.0])
    e2 = np.array([0.0, 1.0])
    if only in (None, 'clearance'):
        Om = 1.7
        T = 2 * math.pi / Om
        T0 = 200 * T + 0.6123 * T
        t = np.arange(64) * T / 64
        x, v, _ = simulate(M2, C2, E, a2, e2, Om, 0.1, 0.8, T0 + T, T0, T0 + t,
                           stops=[(e2, 0.1, 0.8), (-e2, 0.1, 0.8)])
        write(f"{out}/clearance.csv", T0, t, x, v,
              "clearance: steady P(1,2), x = x_2, one period of 64 samples, "
              "a=(0.3,0) Omega=1.7 stops x_2 <= 0.1, -x_2 <= 0.1, r=0.8")
        if only:
            return
    if only == 'beam4_acc':
        # the beam's period with its tip acceleration (w.x''), for the
        # accelerometer fits
        M, C, K, a, w = beam()
        Om, xs, r = 0.85, 0.05, 0.75
        T = 2 * math.pi / Om
        T0 = 300 * T + 0.3171 * T
        t = np.arange(64) * T / 64
        acc = np.full(64, np.nan)
        x, v, _ = simulate(M, C, K, a, w, Om, xs, r, T0 + T, T0, T0 + t,
                           accel=acc)
        write_acc(f"{out}/beam4_acc.csv", T0, t, x, v, acc,
                  "beam4: steady P(1,1), one period of 64 samples with the "
                  f"acceleration a = w.x'', Omega={Om} xs={xs} r={r}")
        return
    if only == 'beam4_acc_rate':
        # the tip acceleration at a sampling rate not locked to the forcing
        # (61.3 samples per forcing period over 20 periods): no two periods
        # are sampled at the same phases (the noise estimate's folding)
        M, C, K, a, w = beam()
        Om, xs, r = 0.85, 0.05, 0.75
        T = 2 * math.pi / Om
        T0 = 300 * T + 0.3171 * T
        t = np.arange(int(20 * 61.3)) * T / 61.3
        acc = np.full(len(t), np.nan)
        x, v, _ = simulate(M, C, K, a, w, Om, xs, r, T0 + t[-1] + 1e-9, T0,
                           T0 + t, accel=acc)
        write_acc(f"{out}/beam4_acc_rate.csv", T0, t, x, v, acc,
                  "beam4: steady P(1,1), 20 periods at 61.3 samples per "
                  f"period, acceleration a = w.x'', Omega={Om} xs={xs} r={r}")
        return
    if only == 'fig2_dof1':
        # Fig. 2's chain recorded at mass 1 (x_1), not at the stop (x_2)
        M, C, K, a, w = chain2()
        Om, xs, r = 0.9, 0.1, 0.7
        T = 2 * math.pi / Om
        T0 = 200 * T + 0.3171 * T
        t = np.arange(64) * T / 64
        e1 = np.array([1.0, 0.0])
        x, v, _ = simulate(M, C, K, a, e1, Om, xs, r, T0 + T, T0, T0 + t,
                           stops=[(w, xs, r)])
        write(f"{out}/fig2_dof1.csv", T0, t, x, v,
              "fig2: steady P(1,1) recorded at x_1 (the stop is on x_2), one "
              f"period of 64 samples, Omega={Om} xs={xs} r={r}")
        return
    cases = [('beam4', beam(), 0.85, 0.05, 0.75, 300),
             ('fig2', chain2(), 0.9, 0.1, 0.7, 200)]
    for name, (M, C, K, a, w), Om, xs, r, settle in cases:
        T = 2 * math.pi / Om
        T0 = settle * T + 0.3171 * T  # an unknown phase
        t = np.arange(64) * T / 64
        x, v, _ = simulate(M, C, K, a, w, Om, xs, r, T0 + T, T0, T0 + t)
        write(f"{out}/{name}.csv", T0, t, x, v,
              f"{name}: steady P(1,1), one period of 64 samples, "
              f"Omega={Om} xs={xs} r={r}; scipy DOP853 rtol 1e-12")
        if name == 'beam4':
            tj = np.sort(rng.uniform(0, 10 * T, 640))
            tj[0] = 0.0
            x, v, _ = simulate(M, C, K, a, w, Om, xs, r, T0 + 10 * T, T0,
                               T0 + tj)
            write(f"{out}/{name}_jitter.csv", T0, tj, x, v,
                  f"{name}: 640 samples at uniform random times over 10 "
                  "periods")


if __name__ == '__main__':
    main()

#!/usr/bin/env python3
"""A cusp of a P(2,2) fold curve, located by the closed form (mpmath, 60
digits), sharing nothing with vibroimpact's code.

The scene: Fig. 2's chain (m = k = 1, a = (0.5, 0), stop on mass 2, r = 0.7)
with the dashpots c = 0.05 (`--set model.chain.c=0.05`), in the plane
(forcing.omega, stop.xs).

The P(2,2) orbit with impacts at t_0 < t_1 < t_0 + 2T is the fixed point of
an affine map (curves_check.pnm_orbit), so the stop coordinate at impact j,
phi_j(t_0, t_1; Omega) = w.x_j, does not depend on x_s: the orbit
conditions are g_j = phi_j - x_s = 0.  A fold (a multiplier +1) is
det J = 0, J = d(phi_0, phi_1)/d(t_0, t_1); a cusp adds u^T D^2 phi[v, v] = 0
(v, u the right and left null vectors of J): the fold's quadratic
coefficient vanishes.  Both solved with phi_0 = phi_1 by mp.findroot in
(Omega, t_0, t_1), derivatives by central differences of step 1e-12 at 60
digits (their error ~1e-24), then x_s = phi_0.

Cross-checks, in a second, reduced form: the forcing is harmonic, so for
the impact spacing d = t_1 - t_0 the orbit's stop coordinates are
phi_j = Re(c_j(d) e^{i Omega t_0}); phi_0 = phi_1 fixes the phase, and the
orbits at (Omega, d) have x_s = xi(d; Omega) (the one with v_N > 0).  The
folds at fixed Omega are the extrema of xi over d, the cusp is
xi' = xi'' = 0 with xi''' != 0, unfolded by Omega (d xi'/d Omega != 0):
on one side of Omega_c two fold points (x_s -+ ~ |dOmega|^{3/2} about a
common tangent of slope d xi/d Omega), on the other none.  Also: the
closed-form monodromy's multiplier +1 at the point, the others inside the
unit circle (a stable orbit), v_N > 0 at both impacts and the largest gap
over both flights below the stop (admissible).

usage: cusp_check.py [VIBROIMPACT]   (with the program: run its `curves`
through the cusp, compare the cusp it reports and put its points on the
closed-form fold).  12 CPU-s, 17 with the program.
--scan R C: the float search that found it (the extremum count of xi over
d on a grid of Omega, 0.25..4 in steps of 0.01, for r = R, c = C; where it
changes, Newton on xi' = xi'' = 0), each candidate with its smallest v_N
and largest sampled gap (curves_check.p22_gap); about 30 CPU-s."""
import json
import subprocess
import sys

import mpmath as mp

import curves_check as cc

R = '0.7'
CDAMP = '0.05'
# the float seed: the extremum count of xi changes 2 -> 0 near
# Omega = 0.5323 at d = 0.9265 T (--scan 0.7 0.05)
SEED = (0.53230065, 0.926468)


def setup(prec=60):
    mp.mp.dps = prec
    cc.C = mp.mpf(CDAMP) * cc.E
    cc._eig.clear()  # the eigenvectors at this precision
    cc._cache.clear()


def phi(Om, t0, t1):
    """w.x at both impacts of the P(2,2) orbit with impacts at t0, t1."""
    return cc.pnm_orbit(Om, mp.mpf(R), 0, [t0, t1], 2)[2]


def derivs(Om, t0, t1, h=mp.mpf('1e-12')):
    """phi, J = dphi/dt and the second derivatives D2[k][i][j] of phi_k,
    central differences on a 3 x 3 stencil."""
    P = {}
    for a in (-1, 0, 1):
        for b in (-1, 0, 1):
            P[a, b] = phi(Om, t0 + a * h, t1 + b * h)
    J = mp.matrix(2, 2)
    D2 = [[[0, 0], [0, 0]] for _ in range(2)]
    for k in range(2):
        J[k, 0] = (P[1, 0][k] - P[-1, 0][k]) / (2 * h)
        J[k, 1] = (P[0, 1][k] - P[0, -1][k]) / (2 * h)
        D2[k][0][0] = (P[1, 0][k] - 2 * P[0, 0][k] + P[-1, 0][k]) / h**2
        D2[k][1][1] = (P[0, 1][k] - 2 * P[0, 0][k] + P[0, -1][k]) / h**2
        D2[k][0][1] = D2[k][1][0] = (P[1, 1][k] - P[1, -1][k] - P[-1, 1][k] +
                                     P[-1, -1][k]) / (4 * h**2)
    return P[0, 0], J, D2


def conditions(Om, t0, t1):
    """phi_0 - phi_1, det J, u^T D2 phi[v, v] / (|u| |v|^2)."""
    p, J, D2 = derivs(Om, t0, t1)
    v = [J[0, 1], -J[0, 0]]
    u = [J[1, 0], -J[0, 0]]
    q = sum(u[k] * sum(D2[k][i][j] * v[i] * v[j] for i in range(2) for j in range(2))
            for k in range(2))
    return [p[0] - p[1], mp.det(J), q / (mp.norm(mp.matrix(u)) * mp.norm(mp.matrix(v))**2)]


def phasors(Om, d):
    """The complex amplitudes Z_j (4-vectors) of the pre-impact states of
    the orbit with spacing d: state_j = Re(Z_j e^{i Omega t_0})."""
    T = 2 * mp.pi / Om
    z = cc.pnm_orbit(Om, mp.mpf(R), 0, [mp.mpf(0), d], 2)[0]
    zq = cc.pnm_orbit(Om, mp.mpf(R), 0, [T / 4, T / 4 + d], 2)[0]  # Re(i Z) = -Im Z
    return [[mp.mpc(z[j][k], -zq[j][k]) for k in range(4)] for j in range(2)]


def reduced(Om, d):
    """(x_s, t_0, v_N0, v_N1) of the orbit at spacing d with phi_0 = phi_1
    and v_N0 > 0: e^{i Omega t_0} = +-i conj(delta)/|delta|,
    delta = c_0 - c_1."""
    Z = phasors(Om, d)
    dl = Z[0][1] - Z[1][1]
    e = 1j * mp.conj(dl) / abs(dl)
    if mp.re(Z[0][3] * e) < 0:
        e = -e
    T = 2 * mp.pi / Om
    t0 = (mp.arg(e) / Om) % T
    return mp.re(Z[0][1] * e), t0, mp.re(Z[0][3] * e), mp.re(Z[1][3] * e)


def xi(Om, d):
    return reduced(Om, d)[0]


def dxi(Om, d, k, h=mp.mpf('1e-10')):
    """The k-th derivative (k <= 3) of xi in d, central differences."""
    f = [xi(Om, d + i * h) for i in (-2, -1, 0, 1, 2)]
    return [f[2], (f[3] - f[1]) / (2 * h), (f[3] - 2 * f[2] + f[1]) / h**2,
            (f[4] - 2 * f[3] + 2 * f[1] - f[0]) / (2 * h**3)][k]


def flights(Om, xs, t0, t1, n=4000):
    """The largest sampled w.x - x_s over both flights of the orbit (the
    ends, where it is 0, left out) and the number of interior maxima, in
    floats (e^{A s} from A's eigenvectors, as curves_check.p22_gap)."""
    import numpy as np
    r = float(R)
    _, z, _ = cc.p22_float(float(Om), r, float(xs))[0](float(t0), float(t1))
    W, T, _, ev, V, Vi, X, zpf, Rf = cc.float_system(Om, r)  # cc.C: setup()'s damping
    tn = [float(t0), float(t1), float(t0) + 2 * T]
    worst, nmax = -np.inf, 0
    for j in range(2):
        z0 = Rf @ z[j] - zpf(tn[j])
        s = np.linspace(0, tn[j + 1] - tn[j], n + 2)[1:-1]
        x2 = (np.exp(np.outer(s, ev)) * (Vi @ z0)) @ V[1] + X[1] * np.exp(1j * W * (tn[j] + s))
        g = np.real(x2) - float(xs)
        worst = max(worst, g.max())
        nmax += int(np.sum((g[1:-1] > g[:-2]) & (g[1:-1] > g[2:])))
    return worst, nmax


def xi_float(W, u, r, c):
    """xi(d), d = u T, in floats (numpy, vectorised over u): (x_s, v_N1,
    t_0) of the orbit with v_N0 > 0."""
    import numpy as np
    Kf = np.array([[2.0, -1], [-1, 1]])
    Cf = c * Kf
    A = np.zeros((4, 4))
    A[0, 2] = A[1, 3] = 1
    A[2:, :2], A[2:, 2:] = -Kf, -Cf
    ev, V = np.linalg.eig(A)
    Vi = np.linalg.inv(V)
    Rf = np.diag([1, 1, 1, -r])
    T = 2 * np.pi / W
    ds = np.atleast_1d(u) * T
    X = np.linalg.solve(Kf - W**2 * np.eye(2) + 1j * W * Cf, [0.5, 0])
    Z = np.concatenate([X, 1j * W * X])
    P = lambda tau: np.real((V[None] * np.exp(np.outer(tau, ev))[:, None, :]) @ Vi)
    A0, A1 = P(ds) @ Rf, P(2 * T - ds) @ Rf
    e = np.exp(1j * W * ds)[:, None]
    b0 = Z[None] * e - (P(ds) @ Z)
    b1 = Z[None] - (P(2 * T - ds) @ Z) * e
    z0 = np.linalg.solve(np.eye(4) - A1 @ A0, (A1 @ b0[..., None])[..., 0] + b1)
    z1 = (A0 @ z0[..., None])[..., 0] + b0
    dl = z0[:, 1] - z1[:, 1]
    ph = 1j * np.conj(dl) / np.abs(dl)
    ph = np.where(np.real(z0[:, 3] * ph) < 0, -ph, ph)
    return np.real(z0[:, 1] * ph), np.real(z1[:, 3] * ph), (np.angle(ph) / W) % T


def scan(r, c, W0=0.25, W1=4.0, dW=0.01, N=3000):
    """Float search: the extrema of xi over d in (0, 2T) on a grid of
    Omega; where their count changes, Newton on xi' = xi'' = 0 in
    (Omega, d), and the candidate's admissibility (v_N > 0, the largest
    gap over the flights, curves_check.p22_gap_max)."""
    import numpy as np
    branch = lambda W, u: xi_float(W, u, r, c)
    u = (np.arange(N) + 0.5) / N * 2
    u = u[np.abs(u - 1) > 3e-3]  # d = T: the P(1,1) orbit twice
    prev, cands = None, []
    for W in np.arange(W0, W1, dW):
        xs = branch(W, u)[0]
        f1 = np.diff(xs)
        i = np.where(f1[1:] * f1[:-1] < 0)[0] + 1
        cur = u[i[(np.abs(u[i] - 1) > 6e-3) & (u[i] > 0.01) & (u[i] < 1.99)]]
        if prev is not None and len(cur) != len(prev):
            a, b = (cur, prev) if len(cur) > len(prev) else (prev, cur)
            cands += [(W - dW / 2, e) for e in a if min(abs(b - e), default=9) > 0.02]
        prev = cur
    found = []
    x = lambda W, uu: branch(W, uu)[0][0]
    for W, uu in cands:
        for it in range(40):
            h, e = 1e-4, 1e-6
            F = lambda W, uu: np.array([(x(W, uu + h) - x(W, uu - h)) / (2 * h),
                                        (x(W, uu + h) - 2 * x(W, uu) + x(W, uu - h)) / h**2])
            F0 = F(W, uu)
            Jm = np.column_stack([(F(W + e, uu) - F0) / e, (F(W, uu + e) - F0) / e])
            try:
                st = np.linalg.solve(Jm, F0)
            except np.linalg.LinAlgError:
                break
            W, uu = W - st[0], uu - st[1]
            if not (0 < uu < 2 and W > 0) or abs(st).max() < 1e-11:
                break
        if not (0.01 < uu < 1.99 and abs(uu - 1) > 6e-3 and W > 0):
            continue
        if any(abs(W - f[0]) < 1e-6 for f in found):
            continue
        xs, v1, t0 = [q[0] for q in branch(W, uu)]
        T = 2 * np.pi / W
        orbit, mu, _, _ = cc.p22_float(W, r, xs)
        vn = mu(t0, t0 + uu * T, 1)[1]
        gap = cc.p22_gap(W, r, xs, (t0, t0 + uu * T)) if vn > 0 else np.inf
        found.append((W, uu, xs, vn, gap))
        print("cusp candidate: Omega %.8f, d/T %.6f, x_s %+.6f, min v_N %+.3g, largest gap %+.3g%s"
              % (W, uu, xs, vn, gap, "  admissible" if vn > 0 and gap < 0 else ""), flush=True)
    return found


def main():
    if "--scan" in sys.argv:
        i = sys.argv.index("--scan")
        r, c = float(sys.argv[i + 1]), float(sys.argv[i + 2])
        mp.mp.dps = 24
        cc.C = mp.mpf(c) * cc.E
        scan(r, c)
        return 0
    setup()
    fails = 0
    W0, u0 = SEED
    T0 = 2 * mp.pi / W0
    _, t00, _, _ = reduced(mp.mpf(W0), u0 * T0)
    Om, t0, t1 = mp.findroot(conditions, [mp.mpf(W0), t00, t00 + u0 * T0], tol=mp.mpf('1e-36'),
                             verify=False, maxsteps=30)
    p, J, D2 = derivs(Om, t0, t1)
    xs = p[0]
    res = conditions(Om, t0, t1)
    T = 2 * Om**-1 * mp.pi
    # the reduced form's root, from the same float seed
    Om2, d2 = mp.findroot(lambda W, d: [dxi(W, d, 1), dxi(W, d, 2)],
                          [mp.mpf(W0), u0 * 2 * mp.pi / W0], tol=mp.mpf('1e-32'), verify=False,
                          maxsteps=30)
    x2, t02, v0, v1 = reduced(Om2, d2)
    agree = max(abs(Om2 - Om), abs(d2 - (t1 - t0)), abs(x2 - xs), abs(t02 - t0))
    # the multipliers (closed-form monodromy with saltation matrices)
    z, Ph, g = cc.pnm_orbit(Om, mp.mpf(R), xs, [t0, t1], 2)
    mus = sorted(cc.pnm_multipliers(Om, mp.mpf(R), [t0, t1], 2, z, Ph), key=lambda m: abs(m - 1))
    print("cusp of the P(2,2) fold curve, c = %s, r = %s, in (forcing.omega, stop.xs):" %
          (CDAMP, R))
    print("  Omega = %s" % mp.nstr(Om, 20))
    print("  x_s   = %s" % mp.nstr(xs, 20))
    print("  t_0   = %s, t_1 = %s (t_1 - t_0 = %s T)" % (mp.nstr(t0, 20), mp.nstr(t1, 20),
                                                         mp.nstr((t1 - t0) / T, 15)))
    print("  v_N   = %s, %s" % (mp.nstr(z[0][3], 12), mp.nstr(z[1][3], 12)))
    print("  multipliers: " + ", ".join(mp.nstr(m, 15) for m in mus))
    print("  residuals: g_0 %.1e, g_1 %.1e, det J %.1e, u^T D2g[v,v] / (|u||v|^2) %.1e" %
          (float(abs(g[0])), float(abs(g[1])), float(abs(res[1])), float(abs(res[2]))))
    ok = (max(abs(e) for e in g) < 1e-30 and abs(res[1]) < 1e-20 and abs(res[2]) < 1e-20
          and abs(mus[0] - 1) < 1e-15 and max(abs(m) for m in mus[1:]) < 1)
    print("%s the point solves the orbit, fold and cusp conditions; |mu - 1| = %.1e, the other "
          "multipliers of modulus <= %.4f" % ("ok  " if ok else "FAIL", float(abs(mus[0] - 1)),
                                              float(max(abs(m) for m in mus[1:]))))
    fails += not ok
    # Liouville: the saltation matrices' determinants r^2 (v_N reversed and
    # scaled by r, e^{A tau} the rest), the flows' e^{-tr(M^-1 C) 2T}
    liou = mp.mpf(R)**4 * mp.exp(-3 * mp.mpf(CDAMP) * 2 * T)
    prod = mus[0] * mus[1] * mus[2] * mus[3]
    ok = abs(prod / liou - 1) < 1e-20
    print("%s the multipliers' product %s is Liouville's r^4 e^{-tr(M^-1 C) 2T} to %.1e" % (
        "ok  " if ok else "FAIL", mp.nstr(mp.re(prod), 15), float(abs(prod / liou - 1))))
    fails += not ok
    ok = agree < 1e-15
    print("%s the reduced form's root xi' = xi'' = 0 in (Omega, d) is the same point to %.1e" %
          ("ok  " if ok else "FAIL", float(agree)))
    fails += not ok
    # nondegenerate: xi''' != 0 and Omega unfolds it
    x3 = dxi(Om2, d2, 3)
    h = mp.mpf('1e-12')
    dWx1 = (dxi(Om2 + h, d2, 1) - dxi(Om2 - h, d2, 1)) / (2 * h)
    dWx0 = (xi(Om2 + h, d2) - xi(Om2 - h, d2)) / (2 * h)
    ok = abs(x3) > 1e-3 and abs(dWx1) > 1e-3
    print("%s nondegenerate: xi''' = %s, d xi'/d Omega = %s (the branches' common tangent "
          "dx_s/dOmega = %s)" % ("ok  " if ok else "FAIL", mp.nstr(x3, 8), mp.nstr(dWx1, 8),
                                  mp.nstr(dWx0, 10)))
    fails += not ok
    # the fold curve's two branches: at Omega_c + s delta the extrema of xi
    # near d_c (two where s dWx1 / x3 < 0), none on the other side
    side = -1 if dWx1 / x3 > 0 else 1
    print("  fold points at Omega_c %s delta (x_s - x_c, (x_s - x_c) / (Omega - Omega_c), "
          "their split / delta^(3/2)):" % ("+" if side > 0 else "-"))
    ok = True
    for delta in ('1e-4', '1e-5', '1e-6'):
        dW = side * mp.mpf(delta)
        e = mp.sqrt(-2 * dWx1 * dW / x3)
        ds, xsb = [], []
        for sgn in (-1, 1):
            d = mp.findroot(lambda d: dxi(Om2 + dW, d, 1), d2 + sgn * e, tol=mp.mpf('1e-24'),
                            verify=False)
            ds.append(d)
            xsb.append(xi(Om2 + dW, d))
        split = abs(xsb[1] - xsb[0]) / mp.mpf(delta)**1.5
        print("    delta %s: d - d_c = %s, %s; x_s - x_c = %s, %s; slopes %s, %s; split %s" % (
            delta, mp.nstr(ds[0] - d2, 6), mp.nstr(ds[1] - d2, 6), mp.nstr(xsb[0] - x2, 6),
            mp.nstr(xsb[1] - x2, 6), mp.nstr((xsb[0] - x2) / dW, 8),
            mp.nstr((xsb[1] - x2) / dW, 8), mp.nstr(split, 6)))
        ok = ok and abs(ds[1] - ds[0]) > mp.mpf(delta)**0.5 and all(
            abs((xb - x2) / dW - dWx0) < 100 * mp.mpf(delta)**0.5 for xb in xsb)
        # the other side: xi' keeps its sign near d_c
        # (within 2 e of d_c: d = T, the P(1,1) orbit twice, is an extremum too)
        sg = [mp.sign(dxi(Om2 - dW, d2 + k * e / 5, 1)) for k in range(-10, 11, 4)]
        ok = ok and len(set(sg)) == 1
    print("%s two fold branches leave the cusp on one side along a common tangent (split ~ "
          "delta^(3/2)), none on the other" % ("ok  " if ok else "FAIL"))
    fails += not ok
    gap, nmax = flights(Om, xs, t0, t1)
    ok = min(v0, v1) > 0.1 and gap < 0 and nmax == 0
    print("%s admissible: v_N >= %.4f at both impacts; over both flights (4000 samples each, the "
          "ends left out) the largest gap w.x - x_s is %.5f, %d interior maxima: "
          "w.x falls after each impact (w.v = -r v_N) and rises to the next" % (
              "ok  " if ok else "FAIL", float(min(v0, v1)), gap, nmax))
    fails += not ok
    if len(sys.argv) > 1 and not sys.argv[1].startswith("--"):
        cmd = [sys.argv[1], "curves", "--set", "model.chain.c=" + CDAMP, "--set",
               "forcing.omega=0.535", "--set", "stop.xs=1.285", "--orbit", "2,2", "--kind", "fold",
               "--param", "forcing.omega", "--to", "0.52", "--param2", "stop.xs", "--from2", "1.27",
               "--to2", "1.31", "--json"]
        js = json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)
        cusps = [s for s in js["special"] if s["type"] == "cusp"]
        if cusps:
            W, x = cusps[0]["point"]
            err = max(abs(W - Om), abs(x - xs))
            ok = err < (1e-12 if cusps[0]["located"] else 1e-3)  # else: where it is seen
            print("%s vibroimpact curves reports a cusp at (%.16g, %.16g), located %s: %.1e from "
                  "the closed form" % ("ok  " if ok else "FAIL", W, x, cusps[0]["located"],
                                       float(err)))
        else:
            ok = False
            print("FAIL vibroimpact curves reports no cusp: %s" %
                  [s["type"] for s in js["special"]])
        fails += not ok
        # its points, either side of the cusp, are closed-form folds: x_s
        # an extremum of xi over d at their Omega (d > d_c before the cusp,
        # the branch from the generalized period doubling near d = T; d < d_c
        # after), every 100th point and the cusp's neighbours.  The extremum
        # in floats (numpy's closed form, xi_float): on a grid of d/T in
        # 0.8..0.999, the one nearest the point narrowed by finer grids
        # round it to 1e-10 of T, where xi is flat to 1e-17.
        pts = js["points"]
        ic = max(range(len(pts)), key=lambda i: pts[i][0])
        worst, sides = 0, set()
        import numpy as np
        for i in sorted(set(list(range(0, len(pts), 100)) + [ic - 1, ic, ic + 1, len(pts) - 1])):
            W, x = pts[i]
            u = np.linspace(0.8, 0.999, 4000)
            f = xi_float(W, u, float(R), float(CDAMP))[0]
            k = np.where(np.diff(np.sign(np.diff(f))) != 0)[0] + 1
            k = k[np.argmin(abs(f[k] - x))]
            top = f[k] > f[k - 1]  # a maximum (else a minimum) of xi
            u0, du = u[k], u[1] - u[0]
            for _ in range(5):
                u = np.linspace(u0 - du, u0 + du, 201)
                f = xi_float(W, u, float(R), float(CDAMP))[0]
                k = int(np.argmax(f) if top else np.argmin(f))
                u0, du = u[k], 2 * (u[1] - u[0])
            worst = max(worst, abs(f[k] - x))
            sides.add((i < ic, u0 * 2 * np.pi / W > d2) if i != ic else (True, True))
        ok = worst < 1e-12 and sides == {(True, True), (False, False)}
        print("%s its %d points: closed-form folds (x_s an extremum of xi) to %.1e at every 100th "
              "point and around the cusp, d > d_c before it and d < d_c after" % (
                  "ok  " if ok else "FAIL", len(pts), float(worst)))
        fails += not ok
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())

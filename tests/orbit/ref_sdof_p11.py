#!/usr/bin/env python3
"""Independent reference for test_orbits: the two P(1,1) orbits of the
single-degree-of-freedom scene share/scenes/chatter.yaml
(x'' + 0.02 x' + 0.1 x = 0.6 cos t + 0.3, stop x <= 0, r = 0.5) in 50-digit
arithmetic (python3-mpmath), from the closed-form flow, and their Floquet
multipliers as eigenvalues of the impact-to-impact map's Jacobian taken by
finite differences at 50 digits (h = 1e-20), which share nothing with the
saltation-matrix formula the library uses."""
import mpmath as mp

mp.mp.dps = 50
c, k, a, f0, Om, r, xs = (mp.mpf(s) for s in ('0.02', '0.1', '0.6', '0.3', '1', '0.5', '0'))
T = 2 * mp.pi / Om
A = mp.matrix([[0, 1], [-k, -c]])
X = a / (k - Om**2 + 1j * Om * c)
def zp(t):
    e = mp.exp(1j * Om * t)
    return mp.matrix([mp.re(X * e) + f0 / k, mp.re(1j * Om * X * e)])
Phi = mp.expm(A * T)
def flow(t0, z0, t1):
    return mp.expm(A * (t1 - t0)) * (z0 - zp(t0)) + zp(t1)
def F(ti, vN):  # post-impact (xs, -r vN) at ti; after T back at (xs, vN)
    z1 = flow(ti, mp.matrix([xs, -r * vN]), ti + T)
    return [z1[0] - xs, z1[1] - vN]
def impact_map(ti, vN):
    """next impact (time, velocity) from an impact at ti with approach vN:
    first root of x(t) = xs after ti (Newton from the period-1 guess)"""
    z0 = mp.matrix([xs, -r * vN])
    t = mp.findroot(lambda s: flow(ti, z0, s)[0] - xs, ti + T)
    return t, flow(ti, z0, t)[1]
for guess in ((mp.mpf('0.684'), mp.mpf('1.613')), (mp.mpf('2.069'), mp.mpf('2.156'))):
    ti, vN = mp.findroot(F, guess)
    h = mp.mpf('1e-20')
    J = mp.matrix(2, 2)
    for j, (dt, dv) in enumerate(((h, 0), (0, h))):
        tp, vp = impact_map(ti + dt, vN + dv)
        tm, vm = impact_map(ti - dt, vN - dv)
        J[0, j] = (tp - tm) / (2 * h)
        J[1, j] = (vp - vm) / (2 * h)
    ev = mp.eig(J)[0]
    print("t mod T =", mp.nstr(ti % T, 20), " vN =", mp.nstr(vN, 20),
          " multipliers:", [mp.nstr(e, 15) for e in ev])

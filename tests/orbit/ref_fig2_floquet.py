#!/usr/bin/env python3
"""Independent reference for test_orbits: Floquet multipliers of P(1,1)
orbits of the Wagg & Bishop (2000) Fig. 2 chain (m = k = 1, c = 0.1,
a = (0.5, 0), Omega = 0.9, r = 0.7, stop on mass 2) in 60-digit arithmetic
(python3-mpmath), sharing nothing with vibroimpact's code:
  - the orbit from the closed-form flow z(t) = e^{A(t-t0)} (z0 - z_p(t0)) + z_p(t)
    (mp.expm, phasor particular solution), Newton by mp.findroot;
  - the multipliers as eigenvalues of the Jacobian of the stroboscopic map
    (section half a period after the impact), taken by central differences
    at h = 1e-25, the impact time found anew by root finding for every
    perturbed start: no saltation matrix anywhere;
  - as a cross-check, the same eigenvalues from the saltation-matrix product
    at the same precision (they agree to ~1e-20).
Cases: the paper's x_s = 0.1, and x_s = 0.6413, just past the grazing of the
free response (amplitude 0.64119 of mass 2): v_N ~ 1.5e-4, a multiplier
~ 6e3 (the square-root singularity of the impact map).
Run: python3 tests/orbit/ref_fig2_floquet.py  (about a minute)."""
import mpmath as mp

mp.mp.dps = 60
c = mp.mpf('0.1'); r = mp.mpf('0.7'); Om = mp.mpf('0.9'); T = 2 * mp.pi / Om
E = mp.matrix([[2, -1], [-1, 1]]); K = E; C = c * E
A = mp.zeros(4, 4)
A[0, 2] = A[1, 3] = 1
for i in range(2):
    for j in range(2):
        A[2 + i, j] = -K[i, j]; A[2 + i, 2 + j] = -C[i, j]
H = K - Om**2 * mp.eye(2) + 1j * Om * C
X = mp.lu_solve(H, mp.matrix([mp.mpf('0.5'), 0]))
print("free amplitude of mass 2:", mp.nstr(abs(X[1]), 20))

def zp(t):
    e = mp.exp(1j * Om * t)
    return mp.matrix([mp.re(X[0] * e), mp.re(X[1] * e),
                      mp.re(1j * Om * X[0] * e), mp.re(1j * Om * X[1] * e)])

def flow(t0, z0, t1):
    return mp.expm(A * (t1 - t0)) * (z0 - zp(t0)) + zp(t1)

def field(t, z):
    f = A * z
    f[2] += mp.mpf('0.5') * mp.cos(Om * t)
    return f

def case(xs, seed):
    PhiT = mp.expm(A * T)
    def F(ti, x1, v1, vN):  # post-impact state at ti, back one period later
        z0 = mp.matrix([x1, xs, v1, -r * vN])
        z1 = PhiT * (z0 - zp(ti)) + zp(ti + T)
        return [z1[0] - x1, z1[1] - xs, z1[2] - v1, z1[3] - vN]
    ti, x1, v1, vN = mp.findroot(F, [mp.mpf(s) for s in seed])
    zi = mp.matrix([x1, xs, v1, vN])  # just before the impact
    ts = ti + T / 2
    zs = flow(ti, mp.matrix([x1, xs, v1, -r * vN]), ts)
    def strobe(z):
        t = mp.findroot(lambda s: flow(ts, z, s)[1] - xs, ti + T)
        zm = flow(ts, z, t)
        zm[3] = -r * zm[3]
        return flow(t, zm, ts + T)
    h = mp.mpf('1e-25')
    J = mp.matrix(4, 4)
    for j in range(4):
        e = mp.zeros(4, 1); e[j] = h
        d = (strobe(zs + e) - strobe(zs - e)) / (2 * h)
        for i in range(4):
            J[i, j] = d[i]
    ev = sorted(mp.eig(J)[0], key=lambda z: (-abs(z), mp.im(z)))
    # cross-check: saltation S = R + (f+ - R f-) g^T / g.f-, g = e_2
    R = mp.diag([1, 1, 1, -r])
    zpl = R * zi
    fm, fp = field(ti, zi), field(ti, zpl)
    S = R + (fp - R * fm) * mp.matrix([[0, 1, 0, 0]]) / vN
    ev2 = sorted(mp.eig(PhiT * S)[0], key=lambda z: (-abs(z), mp.im(z)))
    print("x_s =", xs, " t_i mod T =", mp.nstr(ti % T, 25), " v_N =", mp.nstr(vN, 25))
    print("  x1 =", mp.nstr(x1, 25), " v1 =", mp.nstr(v1, 25))
    for a in ev:
        d = min(abs(a - b) for b in ev2)
        print("  multiplier %s %s   (saltation: differs by %s)" % (
            mp.nstr(mp.re(a), 22), mp.nstr(mp.im(a), 22), mp.nstr(d, 3)))

case(mp.mpf('0.1'), ('0.6785711', '0.0962160', '0.3508950', '0.7876608'))
case(mp.mpf('0.6413'), ('3.4457435', '0.1260351', '-0.0416707', '0.000147465'))

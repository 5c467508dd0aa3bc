#!/usr/bin/env python3
"""Independent reference for test_sweep: the Fig. 2 P(1,1) orbit of Wagg &
Bishop (2000) in 40-digit arithmetic (python3-mpmath), from the closed-form
flow of the 2-mass chain, not from vibroimpact's code.

Unknowns: impact time t_i and the post-impact state (x1, v1) with x2 = x_s,
v2+ = -r v_N.  Conditions: one forcing period later the flow is back at
x = (x1, x_s) with velocity (v1, v_N) (the impact on mass 2 changes only
v2: WB 2 with M = I, w = e_2).  Prints v_N and t_i mod T."""
import mpmath as mp

mp.mp.dps = 40
m = k = mp.mpf(1); c = mp.mpf('0.1'); xs = mp.mpf('0.1'); r = mp.mpf('0.7')
a = mp.matrix([mp.mpf('0.5'), 0]); Om = mp.mpf('0.9'); T = 2 * mp.pi / Om
E = mp.matrix([[2, -1], [-1, 1]])
K = k * E; C = c * E
A = mp.zeros(4, 4)
A[0, 2] = A[1, 3] = 1
for i in range(2):
    for j in range(2):
        A[2 + i, j] = -K[i, j]; A[2 + i, 2 + j] = -C[i, j]
# particular solution x_p = Re(X e^{i Om t}), X = (K - Om^2 M + i Om C)^-1 a
H = K - Om**2 * mp.eye(2) + 1j * Om * C
X = mp.lu_solve(H, a)
def zp(t):
    e = mp.exp(1j * Om * t)
    return mp.matrix([mp.re(X[0] * e), mp.re(X[1] * e),
                      mp.re(1j * Om * X[0] * e), mp.re(1j * Om * X[1] * e)])
Phi = mp.expm(A * T)
def F(ti, x1, v1, vN):
    z0 = mp.matrix([x1, xs, v1, -r * vN])
    z1 = Phi * (z0 - zp(ti)) + zp(ti + T)
    return [z1[0] - x1, z1[1] - xs, z1[2] - v1, z1[3] - vN]
sol = mp.findroot(F, (mp.mpf('0.678571'), mp.mpf('-0.1'), mp.mpf('0.3'), mp.mpf('0.787661')))
ti, x1, v1, vN = sol
print("vN =", mp.nstr(vN, 20))
print("t_i mod T =", mp.nstr(ti % T, 20))
print("x1 =", mp.nstr(x1, 20), " v1 =", mp.nstr(v1, 20))

#!/usr/bin/env python3
"""High-precision references for the stress suite (tests/stress).

Run:  python3 tests/stress/ref/stress_ref.py   (Debian's python3-mpmath)
Every number printed here is pasted into a test_stress_*.c file next to its
derivation; the tests themselves do not need mpmath.  30 significant digits.
"""
from mpmath import mp, mpf, atan, acos, sqrt, cos, sin, pi, findroot, nsum, inf

mp.dps = 40


def show(name, v):
    print("%-34s %s" % (name, mp.nstr(v, 30)))


# ---- 1. The bouncing ball (test_stress_chatter.c) -------------------------
# x = -height, x'' = g, stop x <= 0, leaves the stop at t = 0 with speed V.
# Flight k (k = 0, 1, ...) starts with speed r^k V and lasts 2 r^k V / g, so
# impact k (1-based) is at t_k = (2V/g)(1 - r^k)/(1 - r), its approach speed
# r^(k-1) V, and the impacts accumulate at T = 2V / (g (1 - r)).
g, V, r = mpf("9.81"), mpf(5), mpf("0.8")
show("ball T_acc", 2 * V / (g * (1 - r)))
show("ball t_1", 2 * V / g)
show("ball t_30", 2 * V / g * (1 - r**30) / (1 - r))

# ---- 1b. Release of the preloaded oscillator ------------------------------
# x'' + k x = f0 + A cos(W t), stop x <= xs, stuck at x = xs from t = 0:
# contact force lambda(t) = f0 - k xs + A cos(W t) > 0 until it falls through
# zero at t_r = acos(-(f0 - k xs)/A) / W.  After release x(t_r) = xs,
# v(t_r) = 0 and the free motion (closed form below) comes back to the stop at
# the next impact t_i: the first root of x(t) - xs after t_r.
k, xs, f0, A, W = mpf(1), mpf("0.2"), mpf("0.7"), mpf(1), mpf(2)
tr = acos(-(f0 - k * xs) / A) / W
show("release t_r", tr)
w0 = sqrt(k)
P = A / (k - W**2)          # particular solution f0/k + P cos(W t)
xst = f0 / k


def xfree(t):
    # homogeneous part fitted to x(tr) = xs, v(tr) = 0
    c0 = xs - xst - P * cos(W * tr)
    s0 = (0 + P * W * sin(W * tr)) / w0
    tau = t - tr
    return xst + P * cos(W * t) + c0 * cos(w0 * tau) + s0 * sin(w0 * tau)


def vfree(t):
    c0 = xs - xst - P * cos(W * tr)
    s0 = (P * W * sin(W * tr)) / w0
    tau = t - tr
    return -P * W * sin(W * t) - c0 * w0 * sin(w0 * tau) + s0 * w0 * cos(w0 * tau)


# scan for the first sign change of x - xs after t_r (x leaves downwards)
t, dt = tr + mpf("1e-3"), mpf("1e-3")
while xfree(t + dt) - xs < 0:
    t += dt
ti = findroot(lambda s: xfree(s) - xs, (t, t + dt), solver="anderson")
show("release next impact t_i", ti)
show("release next impact v_n", vfree(ti))

# ---- 2. The ball on a spring of any stiffness ------------------------------
# x'' + K x = g, stop x <= 0, static offset g/K beyond the stop.  A flight
# leaving x = 0 with speed u: x(tau) = (g/K)(1 - cos w tau) - (u/w) sin w tau
# is zero again at tan(w tau/2) = u w / g, so tau(u) = (2/w) atan(u w / g),
# and energy (1/2 v^2 + 1/2 K x^2 - g x, equal at x = 0) makes the return
# speed u again.  Impact k at sum_{j<k} tau(r^j V); accumulation at the sum
# to infinity.
for e in range(-8, 9, 2):
    K = mpf(10) ** e
    w = sqrt(K)
    tacc = nsum(lambda j: 2 / w * atan(r**j * V * w / g), [0, inf])
    show("spring K=1e%d T_acc" % e, tacc)

# ---- 3. The grazing family (test_stress_graze.c) --------------------------
# x_p = -X cos(W t), X = 1, W = 1/2, stop at X - mu: first contact at
# W t_i = pi - acos(1 - mu/X), approach speed X W sin(acos(1 - mu/X)).
X, Wg = mpf(1), mpf(1) / 2
for e in (2, 6, 10):
    mu = mpf(10) ** (-e)
    th = acos(1 - mu / X)
    show("graze mu=1e-%d t_i" % e, (pi - th) / Wg)
    show("graze mu=1e-%d v_n" % e, X * Wg * sin(th))

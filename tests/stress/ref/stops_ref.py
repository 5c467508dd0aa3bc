#!/usr/bin/env python3
"""High-precision references for test_stress_stops.c: chattering and
sticking on several stops.

Run:  python3 tests/stress/ref/stops_ref.py   (Debian's python3-mpmath)
Every number printed here is pasted into test_stress_stops.c next to its
derivation; the test itself does not need mpmath.  30 significant digits.

The coupled case.  Two coordinates with the consistent-looking mass matrix
M = [[2, 1/2], [1/2, 1]], K = [[2, -1], [-1, 1]], C = [[0.1, -0.05],
[-0.05, 0.05]], f(t) = f0 + a cos(W t), f0 = (2, 1), a = (0.3, -0.9),
W = 0.8; stops x1 <= 0.1 (r = 0.5) and x2 <= 0.3 (r = 0.6).  From x = (0.1,
0), v = 0 at t = 0, mass 1 rests on its stop, pressed: it sticks at once.

While x1 = xs1 (x1' = x1'' = 0) the second row of M x'' + C x' + K x = f -
lambda_1 e1 - lambda_2 e2 is a linear 1-DOF oscillator

    M22 x2'' + C22 x2' + K22 x2 = f2(t) - K21 xs1,

which this script solves in closed form (its own particular and homogeneous
solutions), flight by flight: each impact on x2 = xs2 with approach speed u
leaves with -r u (with x1 held, Newton's law for the pair gives the impulse
P1 = M12 (1 + r) u > 0 on stop 1, which therefore holds), until u < 1e-25
(90 digits: the gap u tau is a difference of O(1) terms); the rest of the
tail is its leading term 2 r u / (p (1 - r)), p the push at the last
impact, good to 1e-45.  The sum is stop 2's accumulation point T2.  Along the way
the script checks that stop 1's contact force

    lambda_1 = f1(t) - K11 xs1 - K12 x2 - C12 x2' - M12 x2''

stays positive.  Held on both stops from T2 on (x = xs, v = 0), the
contact forces are lambda = f(t) - K xs (W = I, so G = M^-1 and G^-1 W^T
M^-1 = I): lambda_2 = 0.8 - 0.9 cos(0.8 t) falls through 0 at
t_r2 = (2 pi - acos(8/9)) / 0.8 and releases stop 2, while lambda_1 =
2.1 + 0.3 cos(0.8 t) keeps stop 1.
"""
from mpmath import mp, mpf, sqrt, cos, sin, exp, acos, pi, findroot

mp.dps = 90


def show(name, v):
    print("%-34s %s" % (name, mp.nstr(v, 30)))


M = [[mpf(2), mpf("0.5")], [mpf("0.5"), mpf(1)]]
K = [[mpf(2), mpf(-1)], [mpf(-1), mpf(1)]]
C = [[mpf("0.1"), mpf("-0.05")], [mpf("-0.05"), mpf("0.05")]]
f0 = [mpf(2), mpf(1)]
a = [mpf("0.3"), mpf("-0.9")]
W = mpf("0.8")
xs = [mpf("0.1"), mpf("0.3")]
r2 = mpf("0.6")

# reduced oscillator x'' + c x' + k x = F + A cos(W t)
m22 = M[1][1]
c = C[1][1] / m22
k = K[1][1] / m22
F = (f0[1] - K[1][0] * xs[0]) / m22
A = a[1] / m22
# particular solution F/k + P cos(W t) + Q sin(W t)
det = (k - W**2) ** 2 + (c * W) ** 2
P = A * (k - W**2) / det
Q = A * c * W / det
wd = sqrt(k - c**2 / 4)
sig = c / 2


def xp(t):
    return F / k + P * cos(W * t) + Q * sin(W * t)


def vp(t):
    return -P * W * sin(W * t) + Q * W * cos(W * t)


def ap(t):
    return -W**2 * (P * cos(W * t) + Q * sin(W * t))


class Flight:
    """x(t) from x(t0) = x0, x'(t0) = v0: particular + damped homogeneous."""

    def __init__(self, t0, x0, v0):
        self.t0 = t0
        self.h0 = x0 - xp(t0)
        self.h1 = (v0 - vp(t0) + sig * self.h0) / wd

    def x(self, t):
        tau = t - self.t0
        e = exp(-sig * tau)
        return xp(t) + e * (self.h0 * cos(wd * tau) + self.h1 * sin(wd * tau))

    def v(self, t):
        tau = t - self.t0
        e = exp(-sig * tau)
        hc = self.h0 * cos(wd * tau) + self.h1 * sin(wd * tau)
        hd = wd * (-self.h0 * sin(wd * tau) + self.h1 * cos(wd * tau))
        return vp(t) + e * (hd - sig * hc)

    def acc(self, t):
        return F + A * cos(W * t) - c * self.v(t) - k * self.x(t)


def lam1(fl, t):
    x2, v2, a2 = fl.x(t), fl.v(t), fl.acc(t)
    return (f0[0] + a[0] * cos(W * t) - K[0][0] * xs[0] - K[0][1] * x2
            - C[0][1] * v2 - M[0][1] * a2)


def push(t):
    """stop 2's gap acceleration at rest on its stop (x1 held)."""
    return F + A * cos(W * t) - k * xs[1]


def next_contact(fl, t0, h, tmax):
    """First t > t0 where x(t) reaches xs2 from below (scan, then root)."""
    g = lambda t: (fl.x(t) - xs[1]) / (t - t0)  # noqa: E731 (the root at t0 divided out)
    t, lmin = t0, mpf(10)
    gt = g(t0 + h / 1000)
    while t < tmax:
        tn = t + h
        gn = g(tn)
        lmin = min(lmin, lam1(fl, tn))
        if gt < 0 < gn:
            lo, hi = (t if t > t0 else t0 + h / 1000), tn
            tr = findroot(g, (lo, hi), solver="anderson")
            return tr, lmin
        t, gt = tn, gn
    raise RuntimeError("no contact before %s" % tmax)


# the first approach from rest at x2 = 0
fl = Flight(mpf(0), mpf(0), mpf(0))
t, lmin = next_contact(fl, mpf(0), mpf("0.01"), mpf(20))
u = fl.v(t)
show("coupled first impact t", t)
show("coupled first impact u", u)
impacts = [(t, u)]
while u > mpf("1e-25"):
    fl = Flight(t, xs[1], -r2 * u)
    tau_est = 2 * r2 * u / push(t)
    t, lm = next_contact(fl, t, min(tau_est / 16, mpf("0.01")), t + 20)
    lmin = min(lmin, lm)
    u = fl.v(t)
    impacts.append((t, u))
T2 = t + 2 * r2 * u / (push(t) * (1 - r2))
show("coupled impacts resolved here", len(impacts))
for j in (1, 2, 3, 4):
    show("coupled impact %d t" % (j + 1), impacts[j][0])
    show("coupled impact %d u" % (j + 1), impacts[j][1])
show("coupled stick T2", T2)
show("coupled min lambda_1 to T2", lmin)
show("coupled push at T2", push(T2))
tr2 = (2 * pi - acos(mpf(8) / 9)) / W
show("coupled release t_r2", tr2)

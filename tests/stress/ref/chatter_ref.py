#!/usr/bin/env python3
"""Independent impact sequences of two chattering models (issue 20, item 5).

Run:  python3 tests/stress/ref/chatter_ref.py   (Debian's python3-mpmath)
Writes chatter_ref_chain.csv and chatter_ref_rod.csv next to this script:
every impact up to the first accumulation point whose approach velocity
v_n is at least 1e-5 V (V the run's velocity scale as vi_sim_velocity_scale
defines it: the largest initial speed |v0_i| or approach velocity), as
index, t, v_n and a = g'' (the gap's acceleration w.x'' at the impact,
which turns a timing error into an error of v_n).  test_stress_chatref.c reads them.  Nothing of the library
is used: 30-digit mpmath throughout.

Both models have M = I, so between impacts each mode of K is a damped
oscillator under a f0 + a cos(W t) (MODEL.md sec. 1) and the flight is a
closed form.  The gap g = w.x - x_s is sampled densely (steps of at most
1/50 of the shortest period, and of 1/16 of the expected flight
2 r v_n / g'' after a slow rebound); a contact is a sign change of g, or
a local maximum of g (a sign change of g' from + to -) at which g >= 0,
so no grazing landing between samples is missed.  Roots by 110
bisections (to ~1e-33 of the step).  Impact: x' -> x' - (1 + r) v_n w /
(w.w) (WB 2 with M = I), v_n = w.x'(t-).  The sequence is followed until
v_n < 1e-8 V, well past the 1e-5 V reported.
"""
import os
from mpmath import mp, mpf, matrix, sqrt, exp, cos, sin, pi, eigsy

mp.dps = 30
RES = mpf('1e-5')  # the default impact resolution


class Linear:
    """x'' + C x' + K x = f0 + a cos(W t), M = I, C = Phi diag(2 zeta om)
    Phi^T; stop w.x <= xs with restitution r."""

    def __init__(self, K, zeta, a, f0, W, w, xs, r):
        n = len(w)
        E, Q = eigsy(matrix(K))
        self.n, self.W, self.xs, self.r = n, mpf(W), mpf(xs), mpf(r)
        self.Q = Q
        self.om = [sqrt(E[j]) for j in range(n)]
        self.sig = [zeta[j] * self.om[j] for j in range(n)]
        self.omd = [self.om[j] * sqrt(1 - zeta[j] ** 2) for j in range(n)]
        col = lambda v: matrix([mpf(x) for x in v])
        self.w = col(w)
        self.psi = Q.T * self.w               # the stop in modal coordinates
        g = Q.T * col(a)
        s = Q.T * col(f0)
        self.S = [s[j] / E[j] for j in range(n)]   # static modal load
        # the harmonic's complex amplitude g / (om^2 - W^2 + 2 i zeta om W)
        self.G = [g[j] / (E[j] - self.W ** 2 + 2j * self.sig[j] * self.W)
                  for j in range(n)]

    def part(self, j, t):
        """the particular solution of mode j and its first two derivatives"""
        e = self.G[j] * mp.expj(self.W * t)
        W = self.W
        return (self.S[j] + e.real, (1j * W * e).real, (-W * W * e).real)

    def start(self, t0, x0, v0):
        """a flight from (t0, x0, v0): the homogeneous constants per mode"""
        q = self.Q.T * matrix([mpf(x) for x in x0])
        qd = self.Q.T * matrix([mpf(x) for x in v0])
        self.t0, self.A, self.B = mpf(t0), [], []
        for j in range(self.n):
            p, pd, _ = self.part(j, self.t0)
            h, hd = q[j] - p, qd[j] - pd
            self.A.append(h)
            self.B.append((hd + self.sig[j] * h) / self.omd[j])

    def modal(self, t):
        """q, q', q'' of every mode at t on the current flight"""
        tau = t - self.t0
        out = []
        for j in range(self.n):
            s, wd, A, B = self.sig[j], self.omd[j], self.A[j], self.B[j]
            e, c, sn = exp(-s * tau), cos(wd * tau), sin(wd * tau)
            h = e * (A * c + B * sn)
            hd = e * ((B * wd - s * A) * c - (A * wd + s * B) * sn)
            hdd = -2 * s * hd - self.om[j] ** 2 * h
            p, pd, pdd = self.part(j, t)
            out.append((h + p, hd + pd, hdd + pdd))
        return out

    def gap(self, t, d=0):
        """g = w.x - xs (d = 0), g' (d = 1) or g'' (d = 2)"""
        m = self.modal(t)
        v = sum(self.psi[j] * m[j][d] for j in range(self.n))
        return v - self.xs if d == 0 else v

    def state(self, t):
        m = self.modal(t)
        q = matrix([m[j][0] for j in range(self.n)])
        qd = matrix([m[j][1] for j in range(self.n)])
        return self.Q * q, self.Q * qd


def bisect(f, a, b, fa):
    """a root of f in [a, b], f(a) of sign fa's, f(b) of the other"""
    for _ in range(110):
        c = (a + b) / 2
        if (f(c) < 0) == (fa < 0):
            a = c
        else:
            b = c
    return (a + b) / 2


def next_contact(m, t, hmax, t_end, after_impact):
    """the first t' > t with g(t') = 0 reached from below"""
    g0, g1, g2 = m.gap(t), m.gap(t, 1), m.gap(t, 2)
    h = hmax
    if after_impact and g2 > 0:  # a rebound of flight ~ -2 g' / g''
        h = min(hmax, -2 * g1 / g2 / 16)
    a, ga, da = t, (g0 if not after_impact else mpf(-1)), g1
    while a < t_end:
        b = a + h
        gb, db = m.gap(b), m.gap(b, 1)
        if gb >= 0:
            return bisect(m.gap, a, b, ga)
        if da > 0 and db < 0:  # a maximum inside: does it reach the stop?
            tm = bisect(lambda u: m.gap(u, 1), a, b, da)
            if m.gap(tm) >= 0:
                return bisect(m.gap, a, tm, ga)
        a, ga, da = b, gb, db
        h = min(hmax, h * mpf("1.5"))  # away from the stop the steps grow back
    return None


def sequence(m, x0, v0, t_end, hmax):
    """impacts (t, v_n) to the first accumulation (v_n < 1e-8 V)"""
    V = max(abs(mpf(v)) for v in v0)
    m.start(0, x0, v0)
    t, out, after = mpf(0), [], False
    while True:
        tc = next_contact(m, t, hmax, t_end, after)
        if tc is None:
            break
        x, v = m.state(tc)
        vn = (m.w.T * v)[0]
        V = max(V, vn)
        out.append((tc, vn, m.gap(tc, 2)))
        if vn < mpf('1e-8') * V:
            break
        v = v - (1 + m.r) * vn / (m.w.T * m.w)[0] * m.w
        m.start(tc, x, v)
        t, after = tc, True
    return out, V


def write(name, title, out, V):
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), name)
    above = [(t, vn, a) for t, vn, a in out if vn >= RES * V]
    below = [vn for t, vn, a in out if vn < RES * V]
    with open(path, 'w') as f:
        f.write("# %s\n" % title)
        f.write("# generated by chatter_ref.py (mpmath, %d digits): impacts "
                "with v_n >= 1e-5 V up to the first accumulation\n" % mp.dps)
        f.write("# V %s\n" % mp.nstr(V, 20))
        f.write("# first v_n below 1e-5 V: %s (%s V)\n" % (
            mp.nstr(below[0], 6), mp.nstr(below[0] / V, 6)))
        f.write("# smallest v_n above: %s V\n" % mp.nstr(above[-1][1] / V, 6))
        f.write("index,t,vn,a\n")
        for i, (t, vn, a) in enumerate(above):
            f.write("%d,%s,%s,%s\n" % (i, mp.nstr(t, 25), mp.nstr(vn, 25),
                                        mp.nstr(a, 8)))
    print("%s: %d impacts >= 1e-5 V (V = %s), %d resolved in all, last at "
          "%s" % (name, len(above), mp.nstr(V, 12), len(out),
                  mp.nstr(out[-1][0], 15)))


def chain():
    """test_stress_mdof.c's chain: unit masses, K = [2 -1; -1 1], C = 0,
    load 1 on mass 2 into the stop x_2 <= 0, r = 0.8, x0 = 0, v0 = (2, -0.3)"""
    m = Linear([[2, -1], [-1, 1]], [0, 0], [0, 0], [0, 1], 0, [0, 1], 0,
               mpf('0.8'))
    out, V = sequence(m, [0, 0], [2, mpf('-0.3')], mpf(20), mpf('0.02'))
    write("chatter_ref_chain.csv", "2-DOF chain of test_stress_mdof.c "
          "(K = [2 -1; -1 1], f0 = (0, 1), w = (0, 1), xs 0, r 0.8, "
          "v0 = (2, -0.3))", out, V)


def rod():
    """issue 20's rod as test_sim.c builds it: omega_j = (2j - 1) pi / 2,
    j = 1..20, zeta 0.02, w_j = sqrt 2 (-1)^(j+1), a = 0.1 w at W = 1.4,
    stop at 0.05, r = 0.8, from rest"""
    N = 20
    om = [(2 * j + 1) * pi / 2 for j in range(N)]
    K = [[om[i] ** 2 if i == j else 0 for j in range(N)] for i in range(N)]
    w = [(-1 if j % 2 else 1) * sqrt(2) for j in range(N)]
    m = Linear(K, [mpf('0.02')] * N, [mpf('0.1') * x for x in w], [0] * N,
               mpf('1.4'), w, mpf('0.05'), mpf('0.8'))
    hmax = 2 * pi / om[-1] / 50
    out, V = sequence(m, [0] * N, [0] * N, mpf('1.2'), hmax)
    write("chatter_ref_rod.csv", "issue 20's 20-mode rod (test_sim.c: "
          "omega (2j-1) pi/2, zeta 0.02, w_j = sqrt2 (-1)^(j+1), a = 0.1 w, "
          "W 1.4, xs 0.05, r 0.8, from rest)", out, V)


if __name__ == "__main__":
    chain()
    rod()

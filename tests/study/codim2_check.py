#!/usr/bin/env python3
"""Independent check of the codimension-two points that `vibroimpact
curves` locates, against the 24-digit closed-form P(1,1) orbit and its
saltation multipliers of curves_check.py (python3-mpmath; no code shared
with vibroimpact).  The model: the Fig. 2 chain, lightly damped (c = 0.02).

A P(1,1) orbit is a function of (Omega, t0) alone, t0 its impact phase
(the flow and the impact law are linear, so the pre-impact state is
z = (I - e^{AT} R)^-1 (I - e^{AT}) z_p(t0)); its clearance is
x_s = w.x(t0).  A codimension-two point where two multipliers meet at
-s (s = 1: 1:2 resonance, s = -1: 1:1) is a regular root of
    p(-s) = prod_i (mu_i + s) = 0,  p'(-s) = sum_i prod_{j!=i} (mu_j + s) = 0
(p the monodromy's characteristic polynomial, up to sign) in (Omega, t0),
solved here by mp.findroot from the library's point.

Checks:
  1. the P(1,1) period-doubling curve in (Omega, x_s), r = 0.8, x_s in
     [1.1, 1.4]: two 1:2 points reported and located; each within 1e-9 of
     the reference in Omega and x_s, and there the closed-form orbit has
     two multipliers within 1e-6 of -1 (at a double multiplier the
     multipliers of the point rounded to doubles split by sqrt(1e-16)) and
     the others inside the unit circle; every 10th point of the curve a
     multiplier within 1e-7 of -1;
  2. the Neimark-Sacker curve born there (from x_s = 1.15): every 10th
     point a complex pair of modulus 1 within 1e-7, the curve ending
     (`resonance`) at a located 1:2 point within 1e-9 of the reference and
     of the pd curve's;
  3. the 1:1 point that ends the NS curve of the chain at r = 0.6 in
     (Omega, x_s), the fold curve crossing that NS curve (a multiplier +1
     and a pair on the unit circle: p(1) = 0 and prod_{i<j} (mu_i mu_j - 1)
     = 0), and the 1:1 point on Fig. 2's fold curve (c = 0.1): within 1e-9
     of the reference (these lie on a fold, where the orbit itself moves as
     the square root of its parameters: the check is of the point, not of
     multipliers at the rounded point).
usage: codim2_check.py VIBROIMPACT"""
import json
import os
import subprocess
import sys

import mpmath as mp

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import curves_check as cc  # noqa: E402  (the closed form)


def run(exe, args):
    out = subprocess.run([exe, "curves"] + args + ["--json"], capture_output=True, text=True,
                         timeout=300)
    if out.returncode:
        sys.exit("FAIL: curves %s exited %d: %s" % (" ".join(args), out.returncode, out.stderr))
    return json.loads(out.stdout)


def set_damping(c):
    cc.C = mp.mpf(c) * cc.E


def orbit_near(Om, r, xs, s):
    """The P(1,1) orbit at (Omega, x_s) (v_N > 0) with a multiplier nearest
    -s: (t0, multipliers)."""
    best = None
    for t0, z in cc.p11_orbits(Om, r, xs):
        mu = cc.multipliers(Om, r, t0, z)
        d = min(abs(m + s) for m in mu)
        if best is None or d < best[0]:
            best = (d, t0, mu)
    return (best[1], best[2]) if best else (None, None)


def tests(Om, r, t0, s):
    z = cc.orbit_at(Om, r, None, t0)[0]
    mu = cc.multipliers(Om, r, t0, z)
    if s == 'fold-ns':  # a multiplier at +1 and a pair on the unit circle
        u = [m - 1 for m in mu]
        return mp.re(mp.fprod(u)), mp.re(mp.fprod(mu[i] * mu[j] - 1 for i in range(4)
                                                  for j in range(i + 1, 4)))
    u = [m + s for m in mu]
    p = mp.fprod(u)
    dp = mp.fsum(mp.fprod(u[:i] + u[i + 1:]) for i in range(len(u)))
    return mp.re(p), mp.re(dp)


def fold_phase(Om, r, xs):
    """The impact phase where w.x(t0) is extremal nearest x_s: where the two
    orbits of a fold merge (at the point rounded to doubles, there may be
    none)."""
    T = 2 * mp.pi / Om
    phi = lambda t: cc.orbit_at(Om, r, None, t)[0][1]
    t = min((T * k / 90 for k in range(90)), key=lambda t: abs(phi(t) - xs))
    return mp.findroot(lambda u: mp.diff(phi, u), t)


def reference(Om, xs, r, s):
    """The codimension-two point near (Omega, x_s): (Omega*, x_s*)."""
    t0 = orbit_near(Om, r, xs, s)[0] if s == 1 else fold_phase(Om, r, xs)
    sol = mp.findroot(lambda W, t: tests(W, r, t, s), (Om, t0))
    W, t = sol[0], sol[1]
    return W, cc.orbit_at(W, r, None, t)[0][1]


def check_point(sp, r, s, what):
    W, xs = (mp.mpf(v) for v in sp["point"])
    Wr, xr = reference(W, xs, r, s)
    err = max(abs(W - Wr), abs(xs - xr))
    ok = err < 1e-9 and sp["located"]
    print("%s %s at Omega = %.15f, x_s = %.15f: reference %s, %s (|d| %.1e)" %
          ("ok  " if ok else "FAIL", what, W, xs, mp.nstr(Wr, 16), mp.nstr(xr, 16), float(err)))
    return ok, (Wr, xr)


def main():
    exe = sys.argv[1]
    fails = 0
    set_damping('0.02')
    r = mp.mpf('0.8')
    base = ["--set", "model.chain.c=0.02", "--set", "stop.r=0.8", "--set", "forcing.omega=0.5"]
    # 1. the pd curve and its two 1:2 points
    js = run(exe, base + ["--set", "stop.xs=1.233", "--kind", "pd", "--param", "forcing.omega",
                          "--to", "0.3", "--param2", "stop.xs", "--from2", "1.1", "--to2", "1.4"])
    r12 = [e for e in js["special"] if e["type"] == "resonance_1_2"]
    ok = len(r12) == 2
    print("%s pd curve: %d points, %d resonance_1_2 points" %
          ("ok  " if ok else "FAIL", len(js["points"]), len(r12)))
    fails += not ok
    refs = []
    for sp in r12:
        good, ref = check_point(sp, r, 1, "1:2 on the pd curve")
        refs.append(ref)
        W, xs = (mp.mpf(v) for v in sp["point"])
        _, mu = orbit_near(W, r, xs, 1)
        mu = sorted(mu, key=lambda m: abs(m + 1))
        good = good and abs(mu[1] + 1) < 1e-6 and max(abs(m) for m in mu[2:]) < 1
        print("%s   closed-form multipliers there: |mu + 1| %.1e, %.1e; the others' largest "
              "modulus %.3f" % ("ok  " if good else "FAIL", float(abs(mu[0] + 1)),
                                float(abs(mu[1] + 1)), float(max(abs(m) for m in mu[2:]))))
        fails += not good
    worst = 0
    for W, xs in js["points"][::10]:
        _, mu = orbit_near(mp.mpf(W), r, mp.mpf(xs), 1)
        worst = max(worst, float(min(abs(m + 1) for m in mu)))
    ok = worst < 1e-7
    print("%s pd curve: worst |mu + 1| %.1e (every 10th point)" % ("ok  " if ok else "FAIL", worst))
    fails += not ok
    # 2. the NS curve from x_s = 1.15, ending at the upper 1:2 point
    js = run(exe, base + ["--set", "stop.xs=1.15", "--kind", "ns", "--param", "forcing.omega",
                          "--to", "0.56", "--param2", "stop.xs", "--from2", "1.0", "--to2", "1.4"])
    worst, cmax = 0, -1
    for W, xs in js["points"][::10] + [js["points"][-2]]:
        W, xs = mp.mpf(W), mp.mpf(xs)
        best = None
        for t0, z in cc.p11_orbits(W, r, xs):
            pair = [m for m in cc.multipliers(W, r, t0, z) if mp.im(m) > 1e-6]
            for m in pair:
                if best is None or abs(abs(m) - 1) < abs(abs(best) - 1):
                    best = m
        worst = max(worst, float(abs(abs(best) - 1)) if best is not None else 1.0)
        cmax = float(mp.re(best) / abs(best)) if best is not None else cmax
    end = [e for e in js["special"] if e["type"] == "resonance_1_2"]
    ok = worst < 1e-7 and js["end"].startswith("resonance") and len(end) == 1
    print("%s ns curve: %d points, worst ||mu| - 1| of the pair %.1e (every 10th point), cos "
          "theta %.6f at the point before its end (%s)" %
          ("ok  " if ok else "FAIL", len(js["points"]), worst, cmax, js["end"]))
    fails += not ok
    if end:
        good, ref = check_point(end[0], r, 1, "1:2 ending the ns curve")
        d = min(max(abs(ref[0] - q[0]), abs(ref[1] - q[1])) for q in refs) if refs else 1
        good = good and d < 1e-12
        print("%s   the same point as the pd curve's (references %.1e apart)" %
              ("ok  " if good else "FAIL", float(d)))
        fails += not good
    # 3. 1:1 points: the end of the NS curve at r = 0.6 in (Omega, x_s), and
    # on Fig. 2's fold curve
    js = run(exe, ["--set", "stop.r=0.6", "--set", "stop.xs=0.2", "--set", "model.chain.c=0.02",
                   "--kind", "ns", "--param", "forcing.omega", "--to", "3", "--param2", "stop.xs",
                   "--from2", "0", "--to2", "2"])
    r11 = [e for e in js["special"] if e["type"] == "resonance_1_1"]
    if r11:
        ok = check_point(r11[0], mp.mpf('0.6'), -1, "1:1 ending the ns curve (r = 0.6)")[0]
    else:
        ok = False
        print("FAIL ns curve at r = 0.6: no resonance_1_1 point")
    fails += not ok
    fo = [e for e in js["special"] if e["type"] == "fold"]
    if fo:
        ok = check_point(fo[0], mp.mpf('0.6'), 'fold-ns', "fold crossing that ns curve")[0]
    else:
        ok = False
        print("FAIL ns curve at r = 0.6: no fold point")
    fails += not ok
    set_damping('0.1')
    js = run(exe, ["--set", "stop.xs=0.5", "--kind", "fold", "--param", "forcing.omega", "--to",
                   "2.5", "--param2", "stop.xs", "--from2", "0", "--to2", "1.5", "--steps", "100"])
    r11 = [e for e in js["special"] if e["type"] == "resonance_1_1"]
    if r11:
        ok = check_point(r11[0], mp.mpf('0.7'), -1, "1:1 on Fig. 2's fold curve")[0]
    else:
        ok = False
        print("FAIL Fig. 2's fold curve: no resonance_1_1 point")
    fails += not ok
    sys.exit(1 if fails else 0)


if __name__ == "__main__":
    main()

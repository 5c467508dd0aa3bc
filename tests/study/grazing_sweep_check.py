#!/usr/bin/env python3
"""The grazing curve of the non-impacting orbit P(1,0) bounds the regions of
a brute-force sweep (issue 30): on Wagg & Bishop's Fig. 2 chain, on rows of
forcing frequency Omega across [0.5, 1.8] (through the resonance at 0.618),
a sweep of the clearance x_s downwards, each row started on the row's own
P(1,0) orbit (its closed form x(t) = Re X e^{i Omega t}, X = (K - Omega^2 M
+ i Omega C)^-1 a), finds P(1,0) in every cell above the curve point
`vibroimpact curves --kind grazing --orbit 1,0` reports for that Omega and
no P(1,0) in any cell below it (impacting, or not settled: the orbit is
gone).  The closed-form grazing clearance |X_2| lies in the same bracket.
Cells are 0.5 % of x_s apart, offset so that no cell lies on the curve.
Started on P(1,0), a row cannot be pulled to a coexisting impacting orbit
before the orbit itself ends, which is what a curve of existence predicts.
  usage: grazing_sweep_check.py VIBROIMPACT"""
import json
import subprocess
import sys

import numpy as np

M = np.eye(2)
K = np.array([[2.0, -1.0], [-1.0, 1.0]])
C = 0.1 * K
A = np.array([0.5, 0.0])


def run(args):
    out = subprocess.run(args, capture_output=True, text=True, timeout=600)
    if out.returncode:
        sys.exit("FAIL: %s exited %d: %s" % (" ".join(args), out.returncode, out.stderr))
    return json.loads(out.stdout)


def main():
    exe = sys.argv[1]
    curve = run([exe, "curves", "--kind", "grazing", "--orbit", "1,0", "--param", "stop.xs",
                 "--to", "5", "--param2", "forcing.omega", "--from2", "0.5", "--to2", "1.8",
                 "--json"])["points"]
    # rows at curve points (no interpolation along the curve), one of them
    # the point nearest the resonance peak
    want = list(np.linspace(0.5, 1.8, 13)) + [0.618]
    rows = sorted({min(range(len(curve)), key=lambda i: abs(curve[i][1] - w)) for w in want})
    steps, span, off = 21, 0.10, 0.0037
    bad = 0
    for i in rows:
        xc, om = curve[i]
        X = np.linalg.solve(K - om**2 * M + 1j * om * C, A)
        xg = abs(X[1])
        x0, v0 = X.real, (1j * om * X).real
        hi = xc * (1 + span / 2 + off)
        lo = xc * (1 - span / 2 + off)
        sw = run([exe, "sweep", "--set", "forcing.omega=%r" % om, "--set", "stop.xs=%r" % hi,
                  "--set", "initial.x=[%r, %r]" % tuple(x0),
                  "--set", "initial.v=[%r, %r]" % tuple(v0),
                  "--param", "stop.xs", "--from", repr(hi), "--to", repr(lo),
                  "--steps", str(steps), "--transient", "100", "--record", "10",
                  "--threads", "1", "--json", "--quiet"])
        xs, cls = sw["param"], list(zip(sw["n"], sw["m"]))
        above = [c for x, c in zip(xs, cls) if x > xc]
        below = [c for x, c in zip(xs, cls) if x < xc]
        ok = (all(c == (1, 0) for c in above) and not any(c == (1, 0) for c in below)
              and above and below)
        # the closed form in the bracket of the two cells either side
        ok = ok and max(x for x in xs if x < xc) < xg < min(x for x in xs if x > xc)
        if not ok:
            bad += 1
            print("  Omega = %.6f: curve x_s %.9g, closed form %.9g; cells %s" %
                  (om, xc, xg, ["%.6g:%s" % (x, c) for x, c in zip(xs, cls)]))
    print("%s P(1,0) grazing curve bounds the sweep's P(1,0) region on all %d rows "
          "(Omega %.3g..%.3g, cells 0.5 %% of x_s, rows started on their P(1,0) orbit)" %
          ("ok  " if not bad else "FAIL", len(rows), curve[rows[0]][1], curve[rows[-1]][1]))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())

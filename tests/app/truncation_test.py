#!/usr/bin/python3
"""`vibroimpact truncation` against closed forms and against `energy`.

    truncation_test.py APP SCENES

* Fig. 2 (2-mass chain, m = k = 1, stop on mass 2): mode 1 has
  omega_1^2 = (3 - sqrt 5) / 2 and its mass-2 entry squared
  psi_1^2 = (5 + sqrt 5) / 10, w^T M^-1 w = 1 and w^T K^-1 w = 2 (the
  chain's static flexibility at mass 2: two unit springs in series), so the
  dynamic and static fractions of k = 1 are psi_1^2 and psi_1^2 / omega_1^2
  / 2; k = 2 carries all of both.  One mode plus the static vector spans both
  modes: it is the full model, its orbit the reference's.
* The FE beam (beam_fe.yaml, L = 1, rho A = 1, EI = 1 / beta_1^4): the tip's
  static flexibility is L^3 / (3 EI) = beta_1^4 / 3, mode 1's tip value 2,
  so mode 1 carries 4 / (beta_1^4 / 3) of it (Hermite cubics: to the
  discretisation error, 1e-6 asserted); with a 4-mode reference the r_S and
  v_N are those of `energy` (the same orbit; 1e-12), r_S of 4 modes is the
  scene's r.
"""
import json
import math
import subprocess
import sys

app, scenes = sys.argv[1], sys.argv[2]
fails = 0


def check(what, got, want, tol):
    global fails
    ok = abs(got - want) <= tol
    print("%-50s %.15g  (want %.15g, tol %.1g)%s" %
          (what, got, want, tol, "" if ok else "  FAIL"))
    fails += not ok


def run(*args):
    out = subprocess.run([app, *args], check=True, capture_output=True,
                         text=True).stdout
    return json.loads(out)


s5 = math.sqrt(5)
t = run("truncation", scenes + "/fig2.yaml", "--json")
r1, r2 = t["rows"]
p1, w1 = (5 + s5) / 10, (3 - s5) / 2
check("fig2 w^T M^-1 w", t["compliance_dynamic"], 1.0, 1e-12)
check("fig2 w^T K^-1 w", t["compliance_static"], 2.0, 1e-12)
check("fig2 k=1 dynamic fraction", r1["dynamic_fraction"], p1, 1e-12)
check("fig2 k=1 static fraction", r1["static_fraction"], p1 / w1 / 2, 1e-12)
check("fig2 k=2 dynamic fraction", r2["dynamic_fraction"], 1.0, 1e-12)
check("fig2 k=2 static fraction", r2["static_fraction"], 1.0, 1e-12)
check("fig2 k=1 + static vector: all the compliance",
      r1["static_corrected"]["dynamic_fraction"], 1.0, 1e-12)
check("fig2 k=1 + static vector: the reference's v_N",
      r1["static_corrected"]["response"]["vN"], t["reference"]["vN"], 1e-9)
check("fig2 k=2 r_S = r", r2["r_S"], 0.7, 1e-9)
fails += r2["static_corrected"] is not None

b1 = 1.8751040687119611
t = run("truncation", scenes + "/beam_fe.yaml", "--modes", "1..4",
        "--reference", "4", "--json")
e = run("energy", scenes + "/beam_fe.yaml", "--json")
check("beam w^T K^-1 w = beta_1^4 / 3", t["compliance_static"], b1**4 / 3,
      1e-6 * b1**4 / 3)
check("beam k=1 static fraction = 12 / beta_1^4",
      t["rows"][0]["static_fraction"], 12 / b1**4, 1e-6)
check("beam reference v_N = energy's", t["reference"]["vN"], e["vN"], 1e-12)
for row, red in zip(t["rows"], e["reduced"]):
    check("beam r_S, %d modes = energy's" % row["k"], row["r_S"], red["r_S"],
          1e-12)
check("beam r_S, 4 modes = r", t["rows"][3]["r_S"], 0.75, 1e-9)
print("truncation_test: %d failed" % fails)
sys.exit(1 if fails else 0)

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
* -o OUT.h5 (doc/truncation-layout.md) holds what --json prints: the beam
  with a 12-mode reference and Fig. 2 (P(1,1), r_S, no static variant at
  k = 2) read back with h5py, every number equal to the JSON's (printed
  with %.17g: exactly; the errors dt, dvn_rel printed with %.3g: to 5e-3
  relative), the scene text the file's; a directory or /dev/null as the
  target: exit 1 or 2 and no file.
"""
import json
import math
import os
import subprocess
import sys
import tempfile

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

# A published pair (NLEVP sandwich beam, 168 dofs) driven at Omega = 100
# below omega_1 = 126.1 with the stop out of reach after the first impacts:
# a damped linear motion, whose only steady state is P(1,0).  Its free
# vibration makes 5 cycles in 4 periods (1.26 Omega), which read P(4,0) for
# the reference and every reduced model before the classification waited
# for the change over one period to stop shrinking.
fe = os.path.join(scenes, "..", "..", "tests", "data", "fe")
with tempfile.TemporaryDirectory() as d:
    sc = os.path.join(d, "sandwich.yaml")
    with open(sc, "w") as f:
        f.write("name: sandwich\nmodel:\n  matrices: {M: %s, K: %s}\n  modes: 6\n"
                "  zeta: 0.02\nforcing: {omega: 100, on: [100], amplitude: 1}\n"
                "stop: {dof: 100, xs: 1.5, r: 0.7}\nrun: {periods: 200}\n"
                % (os.path.join(fe, "nlevp_sandwich_beam_168_M.mtx"),
                   os.path.join(fe, "nlevp_sandwich_beam_168_K.mtx")))
    t = run("truncation", sc, "--modes", "1..4", "--json")
    got = [t["reference"]["class"]] + [r["response"]["class"] for r in t["rows"]]
    ok = got == ["P(1,0)"] * 5
    print("%-50s %s%s" % ("sandwich beam: P(1,0) throughout", got, "" if ok else "  FAIL"))
    fails += not ok


def same(what, got, want, rel=0.0):
    """got (from the file) equals want (JSON; None: NaN)."""
    global fails
    if want is None:
        ok = math.isnan(got)
    else:
        ok = abs(got - want) <= rel * abs(want)
    if not ok:
        print("%-50s %r  (want %r)  FAIL" % (what, got, want))
    fails += not ok


def same_response(what, g, i, pre, r):
    cls = r["class"]
    n, m = g[pre + "class_n"][i], g[pre + "class_m"][i]
    if cls is None:
        same(what + " class_n", n, -1)
        return
    if cls == "not periodic":
        same(what + " class_n", n, 0)
        same(what + " class_m", m, r["impacts_per_period"])
    else:
        same(what + " class", "P(%d,%d)" % (n, m) == cls, True)
    same(what + " vN", g[pre + "vN"][i], r.get("vN"))
    same(what + " phase", g[pre + "phase"][i], r.get("phase"))


def same_first(what, g, i, pre, f):
    n = len(f["t"])
    same(what + " n", g[pre + "first_n"][i], n)
    for j in range(3):
        for key in ("t", "vn"):
            same("%s %s[%d]" % (what, key, j), g[pre + "first_" + key][i][j],
                 f[key][j] if j < n else None)
        for key in ("dt", "dvn_rel"):
            if key in f:
                v = f[key][j] if j < len(f[key]) else None
                same("%s %s[%d]" % (what, key, j),
                     g[pre + "first_" + key][i][j], v, 5e-3)
    same(what + " release", g[pre + "release"][i], f["release"])


def h5_check(name, scene, *args):
    """-o of `truncation scene args` against its --json."""
    import h5py
    global fails
    j = run("truncation", scene, *args, "--json")
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "t.h5")
        subprocess.run([app, "truncation", scene, *args, "-o", out],
                       check=True, capture_output=True)
        with h5py.File(out, "r") as f:
            g = f["truncation"]
            a = g.attrs
            same(name + " scene", a["scene"].decode() == j["scene"], True)
            with open(scene, "rb") as sf:
                same(name + " scene text",
                     g["scene_text"][()] == sf.read(), True)
            for key, want in (("dofs", j["dofs"]),
                              ("modes_lo", j["modes"][0]),
                              ("modes_hi", j["modes"][1]),
                              ("restitution", j["restitution"]),
                              ("compliance_dynamic", j["compliance_dynamic"]),
                              ("compliance_static", j["compliance_static"])):
                same(name + " " + key, a[key], want)
            ref = g["reference"]
            same_response(name + " reference", ref, 0, "", j["reference"])
            same_first(name + " reference first", ref, 0, "",
                       j["first_impacts"])
            rows = g["rows"]
            same(name + " rows", len(rows["k"]), len(j["rows"]))
            for i, r in enumerate(j["rows"]):
                w = "%s k=%d" % (name, r["k"])
                for key in ("k", "omega", "dynamic_fraction",
                            "static_fraction", "r_S"):
                    same(w + " " + key, rows[key][i], r[key])
                same_response(w + " response", rows, i, "", r["response"])
                same_first(w + " first", rows, i, "", r["first_impacts"])
                same_response(w + " r_S response", rows, i, "r_S_",
                              r["response_r_S"])
                sc = r["static_corrected"]
                same(w + " static_corrected", rows["static_corrected"][i],
                     sc is not None)
                if sc is not None:
                    same(w + " sc dynamic_fraction",
                         rows["sc_dynamic_fraction"][i],
                         sc["dynamic_fraction"])
                    same_response(w + " sc response", rows, i, "sc_",
                                  sc["response"])
                    same_first(w + " sc first", rows, i, "sc_",
                               sc["first_impacts"])
    print("%-50s checked against --json" % (name + " -o"))


h5_check("beam", scenes + "/beam_fe.yaml", "--modes", "1..4",
         "--reference", "12")
h5_check("fig2", scenes + "/fig2.yaml")
# bad targets: a directory, a character device (HDF5 wants a regular
# file): refused with no file left
with tempfile.TemporaryDirectory() as d:
    for target in (d, "/dev/null"):
        p = subprocess.run([app, "truncation", scenes + "/fig2.yaml", "-o",
                            target], capture_output=True)
        ok = p.returncode in (1, 2) and b"vibroimpact" in p.stderr
        print("%-50s exit %d%s" % ("-o " + target, p.returncode,
                                   "" if ok else "  FAIL"))
        fails += not ok
    left = os.listdir(d)
    fails += bool(left)
    print("%-50s %r%s" % ("files left", left, "  FAIL" if left else ""))
print("truncation_test: %d failed" % fails)
sys.exit(1 if fails else 0)

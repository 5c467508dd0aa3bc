#!/usr/bin/python3
"""reference.json -> reference.txt, the summary test_fe_published reads: one
line per pair, `NAME n massless rigid tol count lambda_1 .. lambda_count`,
tol the relative accuracy of a double-precision solve that the pair's
conditioning allows (reference.json's rel_accuracy) joined with the
reference's own (ref_accuracy), lambda = omega^2 ascending (rigid: 0).

Usage: reference_txt.py [reference.json [reference.txt]]
"""
import json
import os
import sys

here = os.path.dirname(os.path.abspath(__file__))
src = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "reference.json")
dst = sys.argv[2] if len(sys.argv) > 2 else os.path.join(here, "reference.txt")
ref = json.load(open(src))
with open(dst, "w") as f:
    f.write("# written by reference_txt.py from reference.json: NAME n massless "
            "rigid tol count lambda...\n")
    for name, r in ref.items():
        if r.get("skip"):
            continue
        lam = r["lambda"]
        tol = max(r.get("rel_accuracy", 0.0), r.get("ref_accuracy", 0.0))
        f.write("%s %d %d %d %.3e %d %s\n" % (
            name, r["n"], r["massless"], r["rigid"], tol, len(lam),
            " ".join("%.17g" % x for x in lam)))

#!/usr/bin/python3
"""Plot a truncation study (`vibroimpact truncation SCENE --json > t.json`).

    plot_truncation.py t.json [--out DIR]

writes STEM_truncation.png (STEM: the JSON file's name without .json), four
panels against the number k of kept modes:

  1. the fraction of the stop's compliance the k modes carry: dynamic
     (sum psi_j^2 / w^T M^-1 w, the Delassus number of Newton's law) and
     static (sum psi_j^2 / omega_j^2 / w^T K^-1 w), and the dynamic fraction
     of the k modes plus the static residual vector;
  2. the error of the first impact from the scene's initial state against
     the reference, in time, for the k-mode model and with the static
     vector;
  3. the same for the approach velocity of the second impact (after one
     Newton impact: the impact law at work);
  4. impacts per forcing period of the k-mode model's motion (m / n of its
     P(n,m) class; 1 for P(1,1)) and the r_S a k-mode model needs (WB 13),
     where the reference orbit is P(1,1).

Debian's python3-matplotlib; nothing else.
"""
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def rate(resp):
    """Impacts per forcing period of a classified motion, NaN if none."""
    if not resp or not resp.get("class"):
        return math.nan
    c = resp["class"]
    if c == "P(1,1)":
        return 1.0
    if c.startswith("P("):
        n, m = c[2:-1].split(",")
        return int(m) / int(n)
    return resp.get("impacts_per_period", math.nan)


def err(first, key, j):
    vals = first.get(key, []) if first else []
    return abs(vals[j]) if len(vals) > j and vals[j] is not None else math.nan


def main(argv):
    if len(argv) < 2:
        sys.stderr.write(__doc__)
        return 2
    path = argv[1]
    out = argv[argv.index("--out") + 1] if "--out" in argv else "."
    with open(path) as f:
        d = json.load(f)
    rows = d["rows"]
    k = [r["k"] for r in rows]
    sc = [r.get("static_corrected") or {} for r in rows]
    fig, ax = plt.subplots(2, 2, figsize=(11, 8))
    a = ax[0][0]
    a.plot(k, [r["dynamic_fraction"] for r in rows], "o-", label="dynamic")
    a.plot(k, [r["static_fraction"] if r["static_fraction"] is not None
               else math.nan for r in rows], "s-", label="static")
    a.plot(k, [s.get("dynamic_fraction", math.nan) for s in sc], "^--",
           label="dynamic, + static vector")
    a.set_xlabel("modes kept k")
    a.set_yscale("log")
    a.set_ylabel("fraction of the stop's compliance")
    a.set_title("compliance carried")
    a.legend()
    for a, key, j, what in ((ax[0][1], "dt", 0, "first impact: |t - t_ref|"),
                            (ax[1][0], "dvn_rel", 1,
                             "second impact: |v_n / v_n,ref - 1|")):
        a.semilogy(k, [err(r.get("first_impacts"), key, j) for r in rows],
                   "o-", label="k modes")
        a.semilogy(k, [err(s.get("first_impacts"), key, j) for s in sc],
                   "^--", label="k modes + static vector")
        a.set_xlabel("modes kept k")
        a.set_title(what)
        a.legend()
    a = ax[1][1]
    a.plot(k, [rate(r.get("response")) for r in rows], "o-",
           label="impacts per period (scene's r)")
    a.set_xlabel("modes kept k")
    rs = [r["r_S"] if r.get("r_S") is not None else math.nan for r in rows]
    if any(not math.isnan(x) for x in rs):
        a.plot(k, rs, "s-", label="r_S (WB 13)")
    a.set_title("response; reference: %s" % (d["reference"].get("class")))
    a.legend()
    fig.suptitle("truncation study: %s (%d dofs, r = %g)" %
                 (d["scene"], d["dofs"], d["restitution"]))
    fig.tight_layout()
    stem = os.path.splitext(os.path.basename(path))[0]
    name = os.path.join(out, stem + "_truncation.png")
    fig.savefig(name, dpi=100)
    print(name)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

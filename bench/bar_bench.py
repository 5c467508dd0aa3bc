#!/usr/bin/python3
"""Siconos' impacting bar (examples/Mechanics/ImpactingBar) in the same run:
our default method on the whole process (build/dev/vi_bench_bar: model,
modes, simulation) against Siconos 4.4's Moreau-Jean time stepping (theta =
1, h = 2e-7, the example's own scheme, dense matrices, python3-siconos), on
the bar of NE elements from 0 to T = 1.5e-3; release times against the
independent clamped-bar reference tests/stress/ref/bar_ref.py.  Then the
mesh refinement towards the continuum (release 5e-4 + 2 L / c, rebound 0.1
m/s) with our method alone, up to 2000 elements.

Usage: bench/bar_bench.py [BUILD_DIR] [--ne 500] [--no-siconos]
"""
import argparse
import os
import subprocess
import sys
import time

import numpy as np

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, "..", "tests", "stress", "ref"))
import bar_ref  # noqa: E402


def ours(build, ne, method="auto"):
    t0 = time.perf_counter()
    out = subprocess.run([os.path.join(build, "vi_bench_bar"), str(ne), method],
                         check=True, capture_output=True, text=True).stdout
    wall = time.perf_counter() - t0
    f = out.split()
    return {"wall": wall, "t_rel": float(f[1]), "v": float(f[2]),
            "method": f[3], "rhs": int(f[7])}


def siconos(ne, h=2e-7, T=1.5e-3):
    import siconos.kernel as sk
    t0 = time.perf_counter()
    M, K = bar_ref.bar(ne)
    n = ne + 1
    ds = sk.LagrangianLinearTIDS(np.full(n, bar_ref.X0), np.full(n, bar_ref.V0),
                                 M, K, np.zeros((n, n)))
    H = np.zeros((1, n))
    H[0, 0] = 1.0  # y = x_1 >= 0
    inter = sk.Interaction(sk.NewtonImpactNSL(0.0), sk.LagrangianLinearTIR(H))
    nsds = sk.NonSmoothDynamicalSystem(0.0, T)
    nsds.insertDynamicalSystem(ds)
    nsds.link(inter, ds)
    s = sk.TimeStepping(nsds, sk.TimeDiscretisation(0.0, h))
    s.insertIntegrator(sk.MoreauJeanOSI(1.0))
    s.insertNonSmoothProblem(sk.LCP())
    s.initialize()
    contact, t_rel = False, None
    while s.hasNextEvent():
        s.computeOneStep()
        on = inter.lambda_(1)[0] > 0
        if on:
            contact = True
        elif contact and t_rel is None:
            t_rel = s.nextTime() - h  # the last step with a contact impulse
        s.nextStep()
    wall = time.perf_counter() - t0
    v = ds.velocity()
    P = np.ones(n) @ (M @ v)
    return {"wall": wall, "t_rel": t_rel, "v": P / (bar_ref.RHO * bar_ref.S * bar_ref.L)}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("build", nargs="?", default=os.path.join(here, "..", "build", "dev"))
    ap.add_argument("--ne", type=int, default=500)
    ap.add_argument("--no-siconos", action="store_true")
    ap.add_argument("--meshes", default="50,100,200,500,1000,2000")
    a = ap.parse_args()
    ref, vref = bar_ref.release(a.ne)
    o = ours(a.build, a.ne)
    print("bar, %d elements, 0 .. 1.5e-3 s; reference release %.17g" % (a.ne, ref))
    print("  ours (%s, whole process): %.3f s, release %.17g (error %.2g s), "
          "rebound %.12f, rhs_evals %d" % (o["method"], o["wall"], o["t_rel"],
                                           o["t_rel"] - ref, o["v"], o["rhs"]))
    if not a.no_siconos:
        try:
            sc = siconos(a.ne)
            print("  Siconos Moreau-Jean (theta 1, h 2e-7): %.3f s, release %.17g "
                  "(error %.2g s), rebound %.12f" % (sc["wall"], sc["t_rel"],
                                                     sc["t_rel"] - ref, sc["v"]))
            print("  speed ratio (Siconos / ours, same run): %.1f" % (sc["wall"] / o["wall"]))
        except ImportError as e:
            print("  Siconos unavailable:", e)
    c = np.sqrt(bar_ref.E / bar_ref.RHO)
    tc = bar_ref.X0 / -bar_ref.V0 + 2 * bar_ref.L / c
    print("continuum: release %.17g, rebound 0.1" % tc)
    print("%6s %10s %24s %10s %10s %12s %10s" % ("NE", "wall s", "release", "vs ref",
                                                  "vs cont.", "rebound", "vs 0.1"))
    for ne in [int(x) for x in a.meshes.split(",")]:
        o = ours(a.build, ne)
        r, _ = bar_ref.release(ne)
        print("%6d %10.3f %24.17g %10.2g %10.3g %12.9f %10.3g" % (
            ne, o["wall"], o["t_rel"], o["t_rel"] - r, o["t_rel"] - tc, o["v"], o["v"] - 0.1))


if __name__ == "__main__":
    main()

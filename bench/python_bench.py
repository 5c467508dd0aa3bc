#!/usr/bin/env python3
"""The Python package's cost over the library's own loops (issue 31),
ratios within one run, C and Python rounds alternating so that both see
the same machine load; the fastest round of each is compared.

1. Per call: Model.simulate of Fig. 2 (100 forcing periods, exact method,
   rtol 1e-8, atol 1e-10, the model built once, the events' arrays read)
   against the same loop in C (vi_py_bench_simulate: a new sim, method,
   tolerances, the same event collectors, the run).  Target: Python <=
   1.3 x C + 0.03 ms.
2. A 40-value sweep of forcing.omega (0.03 .. 0.05, 5 + 2 periods each,
   exact) on a 1000-mass chain (m = k = 1, C = 0.02 K, forced on mass 1,
   stop on mass 1000 at 0.1, r = 0.95; issue 19's scene, bench/
   vi_bench_sweep.c --chain) from Python (vibroimpact.sweep) against the
   same loop over vi_sweep_* in C (vi_py_bench_sweep).  Target: <= 1.2 x.

Run with the package installed (python/run-tests.sh makes a venv in the
build folder):  build/rel/python-venv/bin/python bench/python_bench.py
    [--reps 2000] [--rounds 7] [--chain 1000] [--sweep-rounds 3]"""
import argparse
import math
import time

import numpy as np

import vibroimpact as vi
from vibroimpact._vi import ffi, lib


def per_call(reps, rounds):
    m = vi.Model.chain(2, m=1, k=1, c=0.1, stops=[{"w": [0, 1], "xs": 0.1, "r": 0.7}],
                       forcing={"omega": 0.9, "a": [0.5, 0.0]})
    t_end = 100 * 2 * math.pi / 0.9
    exact = vi.METHODS.index("exact")
    c_best = py_best = math.inf
    for _ in range(rounds):
        c = lib.vi_py_bench_simulate(m._m, reps, t_end, exact, 1e-8, 1e-10)
        if c < 0:
            raise SystemExit("C loop failed: %s" % vi.strerror(int(c)))
        c_best = min(c_best, c)
        t = time.perf_counter()
        for _ in range(reps):
            r = m.simulate(t_end, method="exact", rtol=1e-8, atol=1e-10)
            ev = r.impacts
        py_best = min(py_best, (time.perf_counter() - t) / reps)
    assert ev["t"].size == 100
    target = 1.3 * c_best + 3e-5
    print("simulate, Fig. 2, 100 periods, exact (%d calls x %d rounds, fastest round):"
          % (reps, rounds))
    print("  C loop       %8.4f ms per run" % (1e3 * c_best))
    print("  Python       %8.4f ms per run  (%.2f x C, + %.4f ms)"
          % (1e3 * py_best, py_best / c_best, 1e3 * (py_best - c_best)))
    print("  target       %8.4f ms (1.3 x C + 0.03 ms): %s"
          % (1e3 * target, "met" if py_best <= target else "NOT met"))


def chain_sweep(n, rounds):
    t = time.perf_counter()
    m = vi.Model.chain(n, m=1.0, k=1.0, rayleigh=(0.0, 0.02),
                       stops=[{"dof": n - 1, "xs": 0.1, "r": 0.95}],
                       forcing={"omega": 0.04, "a": np.r_[0.05, np.zeros(n - 1)]})
    setup = time.perf_counter() - t
    vals = np.linspace(0.03, 0.05, 40)
    exact = vi.METHODS.index("exact")
    sink = ffi.new("double *")
    c_best = py_best = math.inf
    for _ in range(rounds):
        c = lib.vi_py_bench_sweep(m._m, b"forcing.omega", ffi.cast("double *",
                                  ffi.from_buffer(vals)), vals.size, 5, 2, exact, sink)
        if c < 0:
            raise SystemExit("C sweep failed: %s" % vi.strerror(int(c)))
        c_best = min(c_best, c)
        t = time.perf_counter()
        s = vi.sweep(m, "forcing.omega", vals, transient=5, record=2, method="exact")
        py_best = min(py_best, time.perf_counter() - t)
    assert not s["failed"].any()
    print("sweep, %d-mass chain, 40 values of forcing.omega, 5 + 2 periods, exact "
          "(model set-up %.2f s once; %d rounds, fastest):" % (n, setup, rounds))
    print("  C loop       %8.3f s" % c_best)
    print("  Python       %8.3f s  (%.3f x C)" % (py_best, py_best / c_best))
    print("  target       1.2 x C: %s" % ("met" if py_best <= 1.2 * c_best else "NOT met"))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--reps", type=int, default=2000)
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--chain", type=int, default=1000)
    ap.add_argument("--sweep-rounds", type=int, default=3)
    a = ap.parse_args()
    print("vibroimpact %s" % vi.library_version())
    per_call(a.reps, a.rounds)
    chain_sweep(a.chain, a.sweep_rounds)


if __name__ == "__main__":
    main()

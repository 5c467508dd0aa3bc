#!/usr/bin/python3
"""Work-precision of vibroimpact against its peers, in one run.

Scenes: the paper's Fig. 2, a 20-mass chain, the 4-mode cantilever and a
200-mass chain.  Solvers: every method of ours (bench/vi_wp, a small C
driver over the library), SciPy's solve_ivp (DOP853, LSODA) with a terminal
event on the gap and the impact law applied between calls, and Siconos
(Debian's python3-siconos 4.4): event-driven (LSODAR) and Moreau-Jean time
stepping (theta = 0.5, LCP).  The forcing reaches Siconos through a C plugin
(as Siconos' own examples do), so neither side runs Python per evaluation
except SciPy, whose right-hand side is numpy.

Error = the largest impact-time error against an independent mpmath
solution of every impact (30 digits: eigen-decomposition of the
first-order system, the harmonic particular solution, Newton on the gap),
where it is affordable (n <= 20), else against our exact method at rtol
1e-13, which mpmath checks on the other scenes.  Time = CPU time of the
integration loop only (no process start, no set-up), best of several runs,
on every side alike (the machine is shared: wall time measures the load).

Writes bench/workprec.md (tables), bench/workprec.png (log-log plot) and
bench/workprec.json (raw data).  Run through bench/run.sh, which installs
the Debian packages and builds the driver; or directly:
    /usr/bin/python3 bench/workprec.py BUILD_DIR [--quick]
"""
import datetime
import json
import math
import os
import platform
import subprocess
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BENCH = os.path.join(ROOT, "bench")

# name, scene file, forcing periods
SCENES = [
    ("fig2", "share/scenes/fig2.yaml", 100),
    ("chain20", "bench/scenes/chain20.yaml", 20),
    ("cantilever4", "share/scenes/cantilever4.yaml", 100),
    ("chain200", "bench/scenes/chain200.yaml", 5),
]
OUR_TOLS = [1e-6, 5e-7, 2e-7, 1e-7, 5e-8, 2e-8, 1e-8, 5e-9, 2e-9, 1e-9, 5e-10,
            2e-10, 1e-10, 1e-11, 1e-12]  # cheap: 1-2-5 per decade
SCIPY_TOLS = [1e-6, 1e-8, 1e-10, 1e-12]  # slow: decades only
ED_TOLS = [1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12]
MJ_STEPS_PER_PERIOD = [100, 1000]
ROUNDS = 3


def log(*a):
    print(*a, file=sys.stderr, flush=True)


# ---- ours -------------------------------------------------------------------
class Ours:
    def __init__(self, build):
        self.wp = os.path.join(build, "vi_wp")

    def model(self, scene):
        return json.loads(subprocess.check_output([self.wp, scene, "model"]))

    def run(self, scene, method, rtol, t_end, repeats=10):
        p = subprocess.run(
            [self.wp, scene, method, repr(rtol), repr(rtol * 1e-2),
             repr(t_end), str(repeats)], text=True, capture_output=True)
        if p.returncode != 0:  # a run our invariant checks stopped
            raise RuntimeError((p.stderr.strip().splitlines() or ["?"])[-1])
        lines = p.stdout.splitlines()
        head = lines[0].split()
        info = {head[i]: head[i + 1] for i in range(1, len(head) - 1)}
        imp = [tuple(map(float, l.split())) for l in lines[1:]]
        return {"wall": float(info["wall"]), "rhs": int(info["rhs"]),
                "steps": int(info["steps"]), "note": info["method"],
                "t": [x[0] for x in imp], "vn": [x[1] for x in imp]}


# ---- SciPy ------------------------------------------------------------------
def scipy_run(mdl, method, rtol, t_end, n_ref):
    from scipy.integrate import solve_ivp
    n = mdl["n"]
    M = np.array(mdl["M"])
    Minv = np.linalg.inv(M)
    MK, MC = Minv @ np.array(mdl["K"]), Minv @ np.array(mdl["C"])
    Ma, Mb, Mf = Minv @ mdl["a"], Minv @ mdl["b"], Minv @ mdl["f0"]
    w, xs, r, om = np.array(mdl["w"]), mdl["xs"], mdl["r"], mdl["omega"]
    Mw = Minv @ w
    wMw = w @ Mw

    def f(t, y):
        x, v = y[:n], y[n:]
        return np.concatenate(
            [v, Ma * math.cos(om * t) + Mb * math.sin(om * t) + Mf - MK @ x - MC @ v])

    def gap(t, y):
        return w @ y[:n] - xs
    gap.terminal = True
    gap.direction = 1

    t, y = mdl["t0"], np.concatenate([mdl["x0"], mdl["v0"]])
    imp, nfev = [], 0
    t0 = time.thread_time()
    while t < t_end and len(imp) < 10 * n_ref + 10:
        sol = solve_ivp(f, (t, t_end), y, method=method, rtol=rtol,
                        atol=rtol * 1e-2, events=gap)
        nfev += sol.nfev
        if sol.status != 1:
            break
        te, ye = sol.t_events[0][0], sol.y_events[0][0].copy()
        vn = w @ ye[n:]
        imp.append(te)
        ye[n:] -= (1 + r) * vn * Mw / wMw  # WB 2
        t, y = te, ye
    return {"wall": time.thread_time() - t0, "rhs": nfev, "t": imp}


# ---- Siconos ----------------------------------------------------------------
class Siconos:
    def __init__(self, plugin):
        import siconos.kernel as sk
        self.sk = sk
        self.plugin = plugin

    def _nsds(self, mdl, t_end):
        sk = self.sk
        n = mdl["n"]
        ds = sk.LagrangianLinearTIDS(np.array(mdl["x0"]), np.array(mdl["v0"]),
                                     np.array(mdl["M"]), np.array(mdl["K"]),
                                     np.array(mdl["C"]))
        self._z = np.concatenate([[mdl["omega"]], mdl["a"], mdl["b"], mdl["f0"]])
        ds.setzPtr(self._z)
        ds.setComputeFExtFunction(self.plugin, "vi_fext")
        w = np.array(mdl["w"])
        # y = x_s - w.x >= 0
        rel = self.sk.LagrangianLinearTIR(-w.reshape(1, n), np.array([mdl["xs"]]))
        inter = sk.Interaction(sk.NewtonImpactNSL(mdl["r"]), rel)
        nsds = sk.NonSmoothDynamicalSystem(mdl["t0"], t_end)
        nsds.insertDynamicalSystem(ds)
        nsds.link(inter, ds)
        return nsds, ds, inter, w

    def event_driven(self, mdl, tol, t_end):
        sk = self.sk
        nsds, ds, inter, w = self._nsds(mdl, t_end)
        period = 2 * math.pi / mdl["omega"]
        s = sk.EventDriven(nsds, sk.TimeDiscretisation(mdl["t0"], period))
        osi = sk.LsodarOSI()
        s.insertIntegrator(osi)
        s.insertNonSmoothProblem(sk.LCP(), sk.SICONOS_OSNSP_ED_IMPACT)
        s.insertNonSmoothProblem(sk.LCP(), sk.SICONOS_OSNSP_ED_SMOOTH_ACC)
        osi.setTol(1, tol, tol * 1e-2)
        s.initialize()
        osi.setMaxNstep(1000000)  # LSODAR's default 500 per call is too few
        imp = []
        t0 = time.thread_time()
        while s.hasNextEvent():
            s.advanceToEvent()
            vb = float(w @ ds.velocity())
            s.processEvents()
            if vb > 0 and float(w @ ds.velocity()) < 0:
                imp.append(s.startingTime())
        res = {"wall": time.thread_time() - t0, "rhs": None, "t": imp}
        if s.startingTime() < t_end * (1 - 1e-9):
            res["note"] = "stopped at t = %.4g" % s.startingTime()
        return res

    def moreau_jean(self, mdl, h, t_end):
        sk = self.sk
        nsds, ds, inter, w = self._nsds(mdl, t_end)
        s = sk.TimeStepping(nsds, sk.TimeDiscretisation(mdl["t0"], h))
        s.insertIntegrator(sk.MoreauJeanOSI(0.5))
        s.insertNonSmoothProblem(sk.LCP())
        s.initialize()
        imp = []
        vprev = float(w @ ds.velocity())
        t0 = time.thread_time()
        while s.hasNextEvent():
            s.computeOneStep()
            v = float(w @ ds.velocity())
            # an impulse in this step: the contact is somewhere inside it
            if inter.lambda_(1)[0] > 0 and vprev > 0:
                imp.append(s.nextTime() - 0.5 * h)
            vprev = v
            s.nextStep()
        return {"wall": time.thread_time() - t0, "rhs": None, "t": imp}


# ---- mpmath cross-check of the reference ------------------------------------
def mpmath_impacts(mdl, guesses, dps=30, scan=200):
    """The first impacts by an independent 30-digit solution: z' = A z + b(t)
    solved by A's eigen-decomposition plus the harmonic and static particular
    solutions, each contact the first root of the gap (a scan for earlier
    crossings, then Newton from the guess), the impact law applied exactly."""
    import mpmath as mp
    mp.mp.dps = dps
    n = mdl["n"]
    M = mp.matrix(mdl["M"])
    Minv = M ** -1
    MK, MC = Minv * mp.matrix(mdl["K"]), Minv * mp.matrix(mdl["C"])
    N = 2 * n
    A = mp.zeros(N)
    for i in range(n):
        A[i, n + i] = 1
        for j in range(n):
            A[n + i, j] = -MK[i, j]
            A[n + i, n + j] = -MC[i, j]
    lam, V = mp.eig(A)
    Vi = mp.inverse(V)
    om = mp.mpf(mdl["omega"])
    col = lambda xs: mp.matrix([mp.mpf(x) for x in xs])
    fa, fb, f0 = Minv * col(mdl["a"]), Minv * col(mdl["b"]), Minv * col(mdl["f0"])
    rc = mp.matrix(N, 1)
    r0 = mp.matrix(N, 1)
    for i in range(n):
        rc[n + i] = fa[i] - 1j * fb[i]  # a cos + b sin = Re((a - i b) e^{i om t})
        r0[n + i] = f0[i]
    Zc = mp.lu_solve(1j * om * mp.eye(N) - A, rc) if om != 0 else mp.zeros(N, 1)
    zs = -mp.lu_solve(A, r0)
    w = col(mdl["w"])
    xs, rr = mp.mpf(mdl["xs"]), mp.mpf(mdl["r"])
    Mw = Minv * w
    wMw = (w.T * Mw)[0]

    def zp(t):
        e = mp.exp(1j * om * t)
        return mp.matrix([mp.re(Zc[k] * e) + zs[k] for k in range(N)])

    wV = [sum(w[i] * V[i, k] for i in range(n)) for k in range(N)]
    wZ = sum(w[i] * Zc[i] for i in range(n))
    wzs = sum(w[i] * zs[i] for i in range(n))
    t0 = mp.mpf(mdl["t0"])
    z0 = mp.matrix([mp.mpf(x) for x in mdl["x0"]] + [mp.mpf(x) for x in mdl["v0"]])
    out = []
    for tg in guesses:
        c = Vi * (z0 - zp(t0))

        def g(t, c=c, t0=t0):
            h = sum(wV[k] * mp.exp(lam[k] * (t - t0)) * c[k] for k in range(N))
            return mp.re(h + wZ * mp.exp(1j * om * t)) + wzs - xs
        tg = mp.mpf(tg)
        # no earlier crossing on a fine grid up to just before the guess
        for k in range(1, scan):
            tk = t0 + (tg - t0) * k / scan * (1 - mp.mpf(10) ** -6)
            if g(tk) > 0:
                raise RuntimeError("mpmath: earlier contact near t = %s" % tk)
        ts = mp.findroot(g, tg, tol=mp.mpf(10) ** (-dps + 4))
        e = mp.matrix([mp.exp(lam[k] * (ts - t0)) * c[k] for k in range(N)])
        z = V * e + zp(ts)
        z = mp.matrix([mp.re(z[k]) for k in range(N)])
        vn = sum(w[i] * z[n + i] for i in range(n))
        if not vn > 0:
            raise RuntimeError("mpmath: no approach at t = %s" % ts)
        for i in range(n):
            z[n + i] -= (1 + rr) * vn * Mw[i] / wMw
        out.append(ts)
        t0, z0 = ts, z
    return out


# ---- errors and tables --------------------------------------------------------
def impact_error(t, ref):
    """Largest impact-time error; None if the impacts are not the same ones
    (count differs)."""
    if len(t) != len(ref):
        return None
    return max((abs(a - b) for a, b in zip(t, ref)), default=0.0)


def fmt_err(e):
    return "—" if e is None else "%.1e" % e


def machine():
    cpu = "unknown CPU"
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return "%s, %d cores, %s" % (cpu, os.cpu_count(), platform.platform())


def main():
    build = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "bench")
    quick = "--quick" in sys.argv
    ours = Ours(build)
    sic = None
    try:
        sic = Siconos(os.path.join(build, "vi_siconos_plugin.so"))
    except ImportError as e:
        log("siconos unavailable:", e)
    rows, checks = [], []
    scenes = SCENES[:1] if quick else SCENES
    for name, rel, periods in scenes:
        scene = os.path.join(ROOT, rel)
        mdl = ours.model(scene)
        t_end = mdl["t0"] + periods * 2 * math.pi / mdl["omega"]
        ref = ours.run(scene, "exact", 1e-13, t_end, 1)["t"]
        log("%s: %d impacts up to t = %.6g" % (name, len(ref), t_end))
        against = "exact"
        if mdl["n"] <= 20:  # mpmath's eigen-decomposition: 10 s at n = 20
            mp_t = [float(x) for x in mpmath_impacts(mdl, ref)]
            d = max(abs(a - b) for a, b in zip(mp_t, ref))
            checks.append((name, len(ref), d))
            log("  mpmath: all %d impacts agree with exact to %.2e" % (len(ref), d))
            ref, against = mp_t, "mpmath"

        def add(solver, setting, res):
            e = impact_error(res["t"], ref)
            rows.append({"scene": name, "solver": solver, "setting": setting,
                         "n": len(res["t"]), "n_ref": len(ref), "err": e,
                         "against": against,
                         "ms": 1e3 * res["wall"], "rhs": res.get("rhs"),
                         "note": res.get("note", "")})
            log("  %-22s %-10s %4d/%d  err %-8s %9.2f ms" % (
                solver, setting, len(res["t"]), len(ref), fmt_err(e),
                1e3 * res["wall"]))

        slow = set()

        def best(fn, tries):
            out = None
            for _ in range(tries):
                r = fn()
                if out is None or r["wall"] < out["wall"]:
                    out = r
                if r["wall"] > 2.0:
                    break
            return out

        def peer(solver, setting, fn, tries):
            """A peer's run; a failure is a row, and a sweep stops after a
            run longer than 20 s (the next setting would be slower still)."""
            if solver in slow:
                return
            try:
                res = best(fn, tries)
            except Exception as e:  # Siconos raises std::exception
                log("  %-22s %-10s failed: %s" % (solver, setting, e))
                rows.append({"scene": name, "solver": solver, "setting": setting,
                             "n": 0, "n_ref": len(ref), "err": None, "ms": float("nan"),
                             "against": against,
                             "rhs": None, "note": "failed: %s" % e})
                slow.add(solver)
                return
            add(solver, setting, res)
            if res["wall"] > 20.0:
                slow.add(solver)

        # ours and Siconos event-driven are fast, and the machine is shared:
        # ROUNDS interleaved rounds over all their settings, best time kept
        cfg = [("ours " + m, "rtol 1e-10", m, 1e-10) for m in ["exact", "auto"]]
        cfg += [("ours " + m, "rtol %.0e" % tol, m, tol)
                for m in ["adams", "bdf", "erk"] for tol in OUR_TOLS]
        got, failed = {}, {}
        for _ in range(ROUNDS):
            for solver, setting, m, tol in cfg:
                if (solver, setting) in failed:
                    continue
                try:
                    r = ours.run(scene, m, tol, t_end)
                except RuntimeError as e:  # shown as a failed row, not hidden
                    failed[solver, setting] = str(e)
                    continue
                if (solver, setting) not in got or r["wall"] < got[solver, setting]["wall"]:
                    got[solver, setting] = r
        for solver, setting, m, tol in cfg:
            if (solver, setting) in failed:
                e = failed[solver, setting]
                log("  %-22s %-10s failed: %s" % (solver, setting, e))
                rows.append({"scene": name, "solver": solver, "setting": setting,
                             "n": 0, "n_ref": len(ref), "err": None, "ms": float("nan"),
                             "against": against, "rhs": None, "note": "failed: %s" % e})
            else:
                add(solver, setting, got[solver, setting])
        for m in ["DOP853", "LSODA"]:
            for tol in SCIPY_TOLS:
                peer("SciPy " + m, "rtol %.0e" % tol,
                     lambda: scipy_run(mdl, m, tol, t_end, len(ref)), 3)
        if sic:
            for tol in ED_TOLS:
                peer("Siconos event-driven", "tol %.0e" % tol,
                     lambda: sic.event_driven(mdl, tol, t_end), 2 * ROUNDS)
            period = 2 * math.pi / mdl["omega"]
            for spp in MJ_STEPS_PER_PERIOD:
                h = period / spp
                peer("Siconos Moreau-Jean", "h = T/%d" % spp,
                     lambda: sic.moreau_jean(mdl, h, t_end), 2)
    write(rows, checks, build)


def write(rows, checks, build):
    with open(os.path.join(BENCH, "workprec.json"), "w") as f:
        json.dump({"rows": rows, "mpmath": checks}, f, indent=1)
    stamp = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    libs = subprocess.run(["ldd", os.path.join(build, "vi_wp")], capture_output=True,
                          text=True).stdout
    cvodes = next((l.split("=>")[1].split()[0] for l in libs.splitlines()
                   if "sundials_cvodes" in l), "?")
    L = ["# Work-precision: vibroimpact against its peers", "",
         "![work-precision](workprec.png)", "",
         "Measured %s on %s; SUNDIALS: `%s`.  Generated by `bench/run.sh`"
         " (bench/workprec.py)." % (stamp, machine(), cvodes), "",
         "Error: largest impact-time error over all impacts against the 30-digit"
         " mpmath solution (fig2, chain20, cantilever4) or our exact method at"
         " rtol 1e-13 (chain200); — where the impacts found differ in number"
         " from the reference."
         "  Time: CPU time of the integration loop only (thread CPU time on"
         " every side), best of several runs, in ms.", ""]
    L += ["The reference checked by an independent 30-digit mpmath solution (the"
          " 200-mass chain is not: mpmath's eigen-decomposition of a 400 x 400"
          " system takes too long):", "",
          "| scene | impacts checked | max \\|t_exact − t_mpmath\\| |", "|---|---|---|"]
    for name, k, d in checks:
        L.append("| %s | %d | %.1e |" % (name, k, d))
    # summary: per scene and solver the fastest run within each error bound;
    # then the speed-up over Siconos event-driven at matched error: its most
    # accurate run against each solver's fastest run at least as accurate
    bounds = [1e-6, 1e-8, 1e-10]
    L += ["", "## Fastest run within an impact-time error bound (ms, and the setting)", "",
          "| scene | solver | " + " | ".join("error ≤ %.0e" % b for b in bounds) + " |",
          "|---|---|" + "---|" * len(bounds)]
    ratios = []
    for scene in dict.fromkeys(r["scene"] for r in rows):
        rs = [r for r in rows if r["scene"] == scene and r["err"] is not None]
        for solver in dict.fromkeys(r["solver"] for r in rows if r["scene"] == scene):
            cells = []
            for b in bounds:
                ok = [r for r in rs if r["solver"] == solver and r["err"] <= b]
                if ok:
                    r = min(ok, key=lambda r: r["ms"])
                    cells.append("%.3g (%s)" % (r["ms"], r["setting"]))
                else:
                    cells.append("—")
            L.append("| %s | %s | %s |" % (scene, solver, " | ".join(cells)))
        ed = [r for r in rs if r["solver"] == "Siconos event-driven"]
        if ed:
            e = min(ed, key=lambda r: r["err"])
            line = []
            for solver in dict.fromkeys(r["solver"] for r in rs if r["solver"].startswith("ours")):
                ok = [r for r in rs if r["solver"] == solver and r["err"] <= e["err"]]
                if ok:
                    r = min(ok, key=lambda r: r["ms"])
                    line.append("%s %.3g×" % (solver[5:], e["ms"] / r["ms"]))
            ratios.append("* %s: Siconos event-driven at its best, %s: %s in %.3g ms; "
                          "ours at that error or better: %s" % (
                              scene, e["setting"], fmt_err(e["err"]), e["ms"], ", ".join(line)))
        else:
            ratios.append("* %s: Siconos event-driven found the wrong number of impacts"
                          " at every tolerance" % scene)
    L += ["", "## Speed-up over Siconos event-driven at matched error", ""] + ratios
    L += ["", "## Every run", "",
          "| scene | solver | setting | impacts | error | ms | RHS evals |",
          "|---|---|---|---|---|---:|---:|"]
    for r in rows:
        if r["note"].startswith("failed"):
            L.append("| %s | %s | %s | — | %s | | |" % (r["scene"], r["solver"],
                                                        r["setting"], r["note"]))
            continue
        L.append("| %s | %s | %s | %d/%d | %s | %.3g | %s |" % (
            r["scene"], r["solver"] + (" (%s)" % r["note"] if r["note"] and r["note"] != r["solver"].split()[-1] else ""),
            r["setting"], r["n"], r["n_ref"], fmt_err(r["err"]), r["ms"],
            "" if r["rhs"] is None else r["rhs"]))
    with open(os.path.join(BENCH, "workprec.md"), "w") as f:
        f.write("\n".join(L) + "\n")
    plot(rows, stamp)


def plot(rows, stamp):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    fig, axes = plt.subplots(2, 2, figsize=(11, 8.5))
    style = {"ours exact": "k*", "ours auto": "k+", "ours adams": "C0o-",
             "ours bdf": "C1s-", "ours erk": "C2^-", "SciPy DOP853": "C3v--",
             "SciPy LSODA": "C4D--", "Siconos event-driven": "C5P:",
             "Siconos Moreau-Jean": "C7X:"}
    for ax, scene in zip(axes.flat, scenes):
        for solver, st in style.items():
            # in the order of the sweep (tolerance or step), not sorted
            pts = [(r["err"], r["ms"]) for r in rows if r["scene"] == scene
                   and r["solver"] == solver and r["err"] is not None]
            if pts:
                ax.loglog([max(p[0], 1e-14) for p in pts], [p[1] for p in pts], st,
                          label=solver, ms=5)
        ax.set_title(scene)
        ax.set_xlabel("max impact-time error")
        ax.set_ylabel("time (ms)")
        ax.grid(True, which="major", alpha=0.3)
    for ax in list(axes.flat)[len(scenes):]:
        ax.axis("off")
    axes.flat[0].legend(fontsize=7, loc="best")
    fig.suptitle("Work-precision, %s (lower left is better; errors below 1e-14"
                 " drawn at 1e-14)" % stamp)
    fig.tight_layout()
    fig.savefig(os.path.join(BENCH, "workprec.png"), dpi=110)


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Figures from a vibroimpact HDF5 file (layout: doc/hdf5-layout.md).

    /usr/bin/python3 share/plot.py RUN.h5 [--out DIR]
                                   [--last FRACTION | --from T0 --to T1]

The window fits the data: by default the whole run for a transient (no
forcing frequency: a release, a bouncing ball that sticks) and the last
fifth of the run for a forced, settled motion; --last FRACTION or a time
window --from/--to choose it.

Writes PNGs into DIR (default: beside the file):
  NAME_phase.png        phase portraits in modal and physical coordinates
                        (Wagg & Bishop 2000, Fig. 2)
  NAME_gap.png          the impacting coordinate w.x against time (Fig. 5)
  NAME_ledger.png       per-mode energy ledger over the last part of the run
  NAME_restitution.png  r = sqrt(1 - RE/KE_i) (WB 13, Fig. 3), with the run's
                        (RE, KE_i) marked when the file has /orbits/P1_1
Impact states (/impacts) are merged into the phase portraits, so each jump
in velocity is drawn on the stop.  Axes are in the units of the scene.
Needs Debian's python3-h5py and python3-matplotlib.
"""
import argparse
import os
import sys

import h5py
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np


def text(v):
    return v.decode() if isinstance(v, bytes) else str(v)


def rows(ds, k0=0):
    """A [rows][n] dataset from row k0 as a 2-D array, also when a one-mass
    (n = 1) file stores it 1-D."""
    a = np.asarray(ds[k0:], dtype=float)
    return a.reshape(-1, 1) if a.ndim == 1 else a


def unit(ds, default=""):
    """The dataset's `units` attribute, read as units of the scene."""
    u = text(ds.attrs.get("units", default))
    return f"{u} units of the scene" if u in ("time", "length") else u


def modal_map(f, x, q):
    """T with q = T x (T = Psi^T M): from /modal when written, else fitted to
    the trajectory's own (x, q) pairs, an exact linear relation."""
    if "modal/Psi" in f:
        return f["modal/Psi"][:].reshape(x.shape[1], -1).T @ f["model/M"][:].reshape(x.shape[1], -1)
    return np.linalg.lstsq(x, q, rcond=None)[0].T


def with_impacts(f, t, x, v, q, qd):
    """The samples with every event state inside their time span merged in:
    at an impact time the state before (v_minus) then after (v_plus), so
    that the line draws the velocity jump on the stop instead of joining
    the samples across it.  A sample at an event time holds the state before
    the event, so it sorts first."""
    imp = f.get("impacts")
    if imp is None or imp["time"].shape[0] == 0:
        return t, x, v, q, qd
    ti = imp["time"][:]
    sel = (ti >= t[0]) & (ti <= t[-1])
    if not sel.any():
        return t, x, v, q, qd
    ti, xi = ti[sel], rows(imp["x"])[sel]
    vm, vp = rows(imp["v_minus"])[sel], rows(imp["v_plus"])[sel]
    T = modal_map(f, x, q)
    tt = np.concatenate([t, ti, ti])
    order = np.concatenate([np.zeros(len(t)), np.ones(len(ti)), 2 * np.ones(len(ti))])
    k = np.lexsort((order, tt))
    xx = np.concatenate([x, xi, xi])[k]
    vv = np.concatenate([v, vm, vp])[k]
    qq = np.concatenate([q, xi @ T.T, xi @ T.T])[k]
    qqd = np.concatenate([qd, vm @ T.T, vp @ T.T])[k]
    return tt[k], xx, vv, qq, qqd


def samples(tr, k0, k1=None):
    """time, x, v, q, qd of the trajectory's rows k0 .. k1, rows that are
    not finite left out (and reported)."""
    t = np.asarray(tr["time"][k0:k1], dtype=float)
    x, v, q, qd = (rows(tr[k], k0)[:None if k1 is None else k1 - k0] for k in ("x", "v", "q", "qd"))
    ok = np.isfinite(t) & np.all(np.isfinite(np.hstack([x, v, q, qd])), axis=1)
    if not ok.all():
        print(f"plot: note: {np.count_nonzero(~ok)} trajectory rows not finite, left out "
              f"(first at t = {t[~ok][0]:.6g})", file=sys.stderr)
    return t[ok], x[ok], v[ok], q[ok], qd[ok]


def window(tr, win):
    """First and end row of the trajectory inside the window win: ("last",
    fraction) or ("time", t0, t1)."""
    rows_ = tr["time"].shape[0]
    if win[0] == "last":
        return int((1 - win[1]) * rows_), rows_
    t = np.asarray(tr["time"][:], dtype=float)
    return int(np.searchsorted(t, win[1], "left")), int(np.searchsorted(t, win[2], "right"))


def describe(win):
    if win[0] == "last":
        return "the whole run" if win[1] >= 1 else f"last {win[1]:.0%} of the run"
    return f"t = {win[1]:.6g} .. {win[2]:.6g}"


def phase(f, out, win):
    tr = f.get("trajectory")
    if tr is None or tr["time"].shape[0] < 2:
        print("plot: no /trajectory (set output.samples_per_period)", file=sys.stderr)
        return
    k0, k1 = window(tr, win)
    if k1 - k0 < 2:
        print(f"plot: fewer than 2 samples in {describe(win)}", file=sys.stderr)
        return
    t, x, v, q, qd = with_impacts(f, *samples(tr, k0, k1))
    n = x.shape[1]
    m = min(n, 2)
    fig, ax = plt.subplots(2, m, figsize=(5 * m, 8), squeeze=False)
    ux, uv = unit(tr["x"], "length"), unit(tr["v"], "length/time")
    for j in range(m):
        ax[0, j].plot(q[:, j], qd[:, j], lw=0.8)
        ax[0, j].set(xlabel=f"$q_{j+1}$ (modal: length $\\sqrt{{mass}}$)",
                     ylabel=f"$\\dot q_{j+1}$ (modal: length $\\sqrt{{mass}}$ / time)", title=f"mode {j+1}")
        i = n - m + j  # physical: the last coordinates, where the stop usually is
        ax[1, j].plot(x[:, i], v[:, i], lw=0.8, color="C1")
        ax[1, j].set(xlabel=f"$x_{i+1}$ ({ux})", ylabel=f"$\\dot x_{i+1}$ ({uv})",
                     title=f"coordinate {i+1}")
    w = np.ravel(f["model/w"][:])
    xs = f["model"].attrs["x_s"]
    for j in range(m):
        i = n - m + j
        if np.count_nonzero(w) == 1 and w[i] != 0:
            ax[1, j].axvline(xs / w[i], color="k", lw=1, ls="--", label="stop")
            ax[1, j].legend(loc="best")
    fig.suptitle(f"{text(f.attrs.get('scene_name', ''))}: phase portraits ({describe(win)})")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)
    print(out)


def gap(f, out, win):
    tr = f.get("trajectory")
    if tr is None or tr["time"].shape[0] < 2:
        return
    k0, k1 = window(tr, win)
    if k1 - k0 < 2:
        return
    t, x = samples(tr, k0, k1)[:2]
    w, xs = np.ravel(f["model/w"][:]), f["model"].attrs["x_s"]
    fig, ax = plt.subplots(figsize=(10, 3.8))
    ax.plot(t, x @ w, lw=0.8, label="$w \\cdot x$")
    ax.axhline(xs, color="k", ls="--", lw=1, label="stop $x_s$")
    imp = f.get("impacts")
    if imp is not None and imp["time"].shape[0]:
        ti = imp["time"][:]
        sel = (ti >= t[0]) & (ti <= t[-1])
        ax.plot(ti[sel], rows(imp["x"])[sel] @ w, "r.", ms=4, label="impacts")
    ax.set(xlabel=f"$t$ ({unit(tr['time'], 'time')})",
           ylabel=f"$w \\cdot x$ ({unit(tr['x'], 'length')})",
           title=f"impacting coordinate ({describe(win)})")
    # beside the axes, where it cannot cover the data
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)
    print(out)


def ledger(f, out, win):
    lg = f.get("ledger")
    if lg is None or lg["FE"].shape[0] == 0:
        print("plot: no /ledger (set output.ledger)", file=sys.stderr)
        return
    L = lg["FE"].shape[0]
    if win[0] == "last":
        k0 = int((1 - win[1]) * L)
    else:  # the intervals that end inside the window
        te = np.asarray(lg["t_b"][:], dtype=float) if "t_b" in lg else None
        k0 = int(np.searchsorted(te, win[1], "left")) if te is not None else 0
        if te is not None:
            L = max(k0 + 1, int(np.searchsorted(te, win[2], "right")))
    cols = [("FE", "forcing work FE"), ("DE", "damping loss DE"), ("XE", "coupling XE"),
            ("CE", "contact work CE"), ("NE", "nonlinear force work NE"),
            ("dE", "impact jumps dE")]
    sums = {k: rows(lg[k], k0)[:L - k0].sum(axis=0) for k, _ in cols if k in lg}
    if not np.any(sums.get("NE", 0)):  # no nonlinear forces in this run
        sums.pop("NE", None)
    cols = [c for c in cols if c[0] in sums]
    n = sums["FE"].shape[0]
    idx = np.arange(n)
    wdt = 0.8 / len(cols)
    fig, ax = plt.subplots(figsize=(max(6, 1.5 * n + 3), 4))
    for s, (k, lab) in enumerate(cols):
        ax.bar(idx + (s - (len(cols) - 1) / 2) * wdt, sums[k], wdt, label=lab)
    ax.axhline(0, color="k", lw=0.5)
    ax.set_xticks(idx, [f"mode {j+1}" for j in idx])
    ax.set(ylabel="energy (units of the scene)", title=f"ledger, last {L - k0} intervals "
           f"(closure {lg['residual'][k0:L].max():.0e})")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)
    print(out)


def restitution(f, out):
    """WB 13 as in the paper's Fig. 3; with /orbits/P1_1 (vibroimpact energy
    -o) the run's own (RE, KE_i) and the r it recovers are marked."""
    orbit = f.get("orbits/P1_1") if f is not None else None
    run = None
    if orbit is not None and all(k in orbit.attrs for k in ("RE", "KE_i", "r_recovered")):
        run = tuple(float(orbit.attrs[k]) for k in ("RE", "KE_i", "r_recovered"))
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    re = np.linspace(0, 1, 400)
    ax[0].plot(re, np.sqrt(1 - re))
    ax[0].set(xlabel="$RE / KE_i$", ylabel="r",
              title="$r = \\sqrt{1 - RE/KE_i}$ (WB 13, Fig. 3)")
    top = 2.0 if run is None else max(2.0, 1.25 * max(run[0], run[1]))
    RE, KE = np.meshgrid(np.linspace(0, top, 300), np.linspace(0.01 * top, top, 300))
    R = np.where(RE <= KE, np.sqrt(np.clip(1 - RE / KE, 0, 1)), np.nan)
    cs = ax[1].contourf(RE, KE, R, levels=20)
    fig.colorbar(cs, ax=ax[1], label="r")
    ax[1].set(xlabel="RE (energy units of the scene)", ylabel="$KE_i$ (energy units of the scene)",
              title="r over (RE, $KE_i$); blank: RE > $KE_i$")
    if run is not None:
        lab = f"this run: RE = {run[0]:.4g}, $KE_i$ = {run[1]:.4g}, r = {run[2]:.4g}"
        ax[0].plot(run[0] / run[1], run[2], "o", color="C3", ms=7, label=lab)
        ax[0].legend(loc="lower left", fontsize=8)
        ax[1].plot(run[0], run[1], "o", color="C3", mec="w", ms=8, label="this run")
        ax[1].legend(loc="upper left", fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)
    print(out)
    return run


def main(argv=None):
    """The command line (argv: its arguments, default sys.argv[1:]); 0 on
    success.  Callable from Python to draw several files in one process."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file")
    ap.add_argument("--out", default=None, help="output folder")
    ap.add_argument("--last", type=float, default=None,
                    help="fraction of the run to show (default: the whole run "
                    "without forcing, else 0.2, past the transient)")
    ap.add_argument("--from", dest="t0", type=float, default=None,
                    help="window start time (with --to)")
    ap.add_argument("--to", dest="t1", type=float, default=None,
                    help="window end time")
    a = ap.parse_args(argv)
    if a.last is not None and not 0 < a.last <= 1:
        ap.error("--last must lie in (0, 1]")
    if (a.t0 is None) != (a.t1 is None):
        ap.error("--from and --to go together")
    if a.t0 is not None and (a.last is not None or not a.t0 < a.t1):
        ap.error("--from T0 --to T1 needs T0 < T1, and excludes --last")
    out = a.out or os.path.dirname(os.path.abspath(a.file))
    os.makedirs(out, exist_ok=True)
    stem = os.path.join(out, os.path.splitext(os.path.basename(a.file))[0])
    try:
        f = h5py.File(a.file, "r")
    except OSError as e:
        print(f"plot: cannot read {a.file}: {e}", file=sys.stderr)
        return 1
    with f:
        if not f.attrs.get("complete", 1):
            print("plot: note: the run was interrupted (complete = 0)", file=sys.stderr)
        if a.t0 is not None:
            win = ("time", a.t0, a.t1)
        elif a.last is not None:
            win = ("last", a.last)
        else:
            # a transient (no forcing frequency) is shown whole; a forced
            # motion past its transient, over the last fifth of the run
            forced = "model" in f and float(f["model"].attrs.get("Omega", 0)) > 0
            win = ("last", 0.2 if forced else 1.0)
        phase(f, stem + "_phase.png", win)
        gap(f, stem + "_gap.png", win)
        ledger(f, stem + "_ledger.png", win)
        restitution(f, stem + "_restitution.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())

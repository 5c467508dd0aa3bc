#!/usr/bin/python3
"""Figures from a vibroimpact HDF5 file (layout: share/doc/hdf5-layout.md).

    /usr/bin/python3 share/plot.py RUN.h5 [--out DIR] [--last FRACTION]

Writes PNGs into DIR (default: beside the file):
  NAME_phase.png        phase portraits in modal and physical coordinates
                        (Wagg & Bishop 2000, Fig. 2)
  NAME_gap.png          the impacting coordinate w.x against time (Fig. 5)
  NAME_ledger.png       per-mode energy ledger over the last part of the run
  NAME_restitution.png  r = sqrt(1 - RE/KE_i) (WB 13, Fig. 3)
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


def phase(f, out, last):
    tr = f.get("trajectory")
    if tr is None or tr["time"].shape[0] < 2:
        print("plot: no /trajectory (set output.samples_per_period)", file=sys.stderr)
        return
    k0 = int((1 - last) * tr["time"].shape[0])
    x, v, q, qd = (tr[k][k0:] for k in ("x", "v", "q", "qd"))
    n = x.shape[1]
    m = min(n, 2)
    fig, ax = plt.subplots(2, m, figsize=(5 * m, 8), squeeze=False)
    for j in range(m):
        ax[0, j].plot(q[:, j], qd[:, j], lw=0.8)
        ax[0, j].set(xlabel=f"$q_{j+1}$", ylabel=f"$\\dot q_{j+1}$", title=f"mode {j+1}")
        i = n - m + j  # physical: the last coordinates, where the stop usually is
        ax[1, j].plot(x[:, i], v[:, i], lw=0.8, color="C1")
        ax[1, j].set(xlabel=f"$x_{i+1}$", ylabel=f"$\\dot x_{i+1}$", title=f"coordinate {i+1}")
    w = f["model/w"][:]
    xs = f["model"].attrs["x_s"]
    for j in range(m):
        i = n - m + j
        if np.count_nonzero(w) == 1 and w[i] != 0:
            ax[1, j].axvline(xs / w[i], color="k", lw=1, ls="--", label="stop")
            ax[1, j].legend(loc="best")
    fig.suptitle(f"{text(f.attrs.get('scene_name', ''))}: phase portraits (last {last:.0%} of the run)")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)
    print(out)


def gap(f, out, last):
    tr = f.get("trajectory")
    if tr is None or tr["time"].shape[0] < 2:
        return
    k0 = int((1 - last) * tr["time"].shape[0])
    t, x = tr["time"][k0:], tr["x"][k0:]
    w, xs = f["model/w"][:], f["model"].attrs["x_s"]
    fig, ax = plt.subplots(figsize=(9, 3.5))
    ax.plot(t, x @ w, lw=0.8, label="$w \\cdot x$")
    ax.axhline(xs, color="k", ls="--", lw=1, label="$x_s$")
    imp = f["impacts"]
    if imp["time"].shape[0]:
        ti = imp["time"][:]
        sel = ti >= t[0]
        ax.plot(ti[sel], (imp["x"][:][sel] @ w), "r.", ms=4, label="impacts")
    ax.set(xlabel="t", ylabel="$w \\cdot x$", title="impacting coordinate")
    ax.legend(loc="lower right")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)
    print(out)


def ledger(f, out, last):
    lg = f.get("ledger")
    if lg is None or lg["FE"].shape[0] == 0:
        print("plot: no /ledger (set output.ledger)", file=sys.stderr)
        return
    L = lg["FE"].shape[0]
    k0 = int((1 - last) * L)
    sums = {k: lg[k][k0:].sum(axis=0) for k in ("FE", "DE", "XE", "CE", "dE")}
    n = sums["FE"].shape[0]
    idx = np.arange(n)
    wdt = 0.16
    fig, ax = plt.subplots(figsize=(max(6, 1.5 * n + 3), 4))
    for s, (k, lab) in enumerate((("FE", "forcing work FE"), ("DE", "damping loss DE"),
                                  ("XE", "coupling XE"), ("CE", "contact work CE"),
                                  ("dE", "impact jumps dE"))):
        ax.bar(idx + (s - 2) * wdt, sums[k], wdt, label=lab)
    ax.axhline(0, color="k", lw=0.5)
    ax.set_xticks(idx, [f"mode {j+1}" for j in idx])
    ax.set(ylabel="energy", title=f"ledger, last {L - k0} intervals "
           f"(closure {lg['residual'][k0:].max():.0e})")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)
    print(out)


def restitution(out):
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    re = np.linspace(0, 1, 400)
    ax[0].plot(re, np.sqrt(1 - re))
    ax[0].set(xlabel="RE", ylabel="r", title="$r = \\sqrt{1 - RE/KE_i}$, $KE_i = 1$ (WB Fig. 3)")
    RE, KE = np.meshgrid(np.linspace(0, 2, 300), np.linspace(0.01, 2, 300))
    R = np.where(RE <= KE, np.sqrt(np.clip(1 - RE / KE, 0, 1)), np.nan)
    cs = ax[1].contourf(RE, KE, R, levels=20)
    fig.colorbar(cs, ax=ax[1], label="r")
    ax[1].set(xlabel="RE", ylabel="$KE_i$", title="r over (RE, $KE_i$); blank: RE > $KE_i$")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)
    print(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file")
    ap.add_argument("--out", default=None, help="output folder")
    ap.add_argument("--last", type=float, default=0.2,
                    help="fraction of the run to show (default 0.2: past the transient)")
    a = ap.parse_args()
    if not 0 < a.last <= 1:
        ap.error("--last must lie in (0, 1]")
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
        phase(f, stem + "_phase.png", a.last)
        gap(f, stem + "_gap.png", a.last)
        ledger(f, stem + "_ledger.png", a.last)
    restitution(stem + "_restitution.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())

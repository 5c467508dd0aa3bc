#!/usr/bin/python3
"""Bifurcation diagrams from `vibroimpact sweep -o SWEEP.h5`
(layout: doc/sweep-layout.md).

    /usr/bin/python3 share/plot_sweep.py SWEEP.h5 [--out DIR] [--coord J]

Writes into DIR (default: beside the file):
  NAME_bifurcation.png  one-parameter sweep: impact velocity v_n of every
                        recorded impact against the parameter (up sweep in
                        black, down sweep in red, so hysteresis shows; with
                        sweep --orbits also the P(1,1) orbits found by Newton,
                        unstable ones as blue crosses), the
                        stroboscopic coordinate x_J at t0 + kT, and a strip
                        with the classification P(n, m)
  NAME_map.png          two-parameter map: the orbit period n and impacts
                        per period m over the (parameter, parameter 2) plane
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
from matplotlib.colors import ListedColormap


def text(v):
    return v.decode() if isinstance(v, bytes) else str(v)


def label(key):
    names = {"forcing.omega": r"forcing frequency $\Omega$", "stop.xs": r"clearance $x_s$",
             "stop.r": r"restitution $r$"}
    return names.get(key, key)


def lines(g):
    """(line index, direction, row) of every sweep line."""
    d, r = g["direction"][:], g["row"][:]
    return [(l, int(d[l]), int(r[l])) for l in range(len(d))]


def points(g, l, k):
    s, c = g["impact_start"][l, k], g["impact_count"][l, k]
    return g["impacts/phase"][s:s + c], g["impacts/v_n"][s:s + c]


def bifurcation(g, out, stem, coord):
    p = g["param"][:]
    key = text(g.attrs["key"])
    N = int(g.attrs["n_coordinates"])
    j = (coord if coord else N) - 1
    n, m, st = g["n"][:], g["m"][:], g["strobe"]
    fig, ax = plt.subplots(3, 1, figsize=(7.5, 8.5), sharex=True,
                           gridspec_kw={"height_ratios": [3, 3, 0.7]})
    style = {1: dict(c="k", s=0.6, label="sweep up"), -1: dict(c="tab:red", s=0.6, label="sweep down")}
    offs = {1: 0.0, -1: 0.0}
    # down sweeps first (hollow red), up sweeps on top (black dots)
    for l, d, _ in sorted(lines(g), key=lambda x: x[1]):
        xs, ys, sx, sy = [], [], [], []
        for k in range(len(p)):
            _, vn = points(g, l, k)
            xs.append(np.full(len(vn), p[k])); ys.append(vn)
            sx.append(np.full(st.shape[2], p[k])); sy.append(st[l, k, :, j])
        kw = dict(style[d]); kw["marker"] = "."; kw["linewidths"] = 0
        if d < 0:
            kw["s"] = 2.0; kw["marker"] = "o"; kw["facecolors"] = "none"
            kw["edgecolors"] = kw.pop("c"); kw["linewidths"] = 0.3
        ax[0].scatter(np.concatenate(xs) + offs[d], np.concatenate(ys), **kw)
        kw.pop("label", None)
        ax[1].scatter(np.concatenate(sx), np.concatenate(sy), **kw)
    if "p11" in g:  # every P(1,1) orbit by Newton (sweep --orbits), first line
        h = g["p11"]
        l0 = lines(g)[0][0]
        for stab, kw in ((0, dict(c="tab:blue", marker="x", s=6, linewidths=0.6,
                                  label="unstable P(1,1) (Newton)")),
                         (1, dict(c="tab:green", marker="_", s=10, linewidths=0.6,
                                  label="stable P(1,1) (Newton)"))):
            xs, ys = [], []
            for k in range(len(p)):
                s0, c = h["start"][l0, k], h["count"][l0, k]
                for q in range(s0, s0 + max(c, 0)):
                    if h["admissible"][q] and h["stable"][q] == stab:
                        xs.append(p[k]); ys.append(h["v_n"][q])
            if xs:
                ax[0].scatter(xs, ys, zorder=3, **kw)
    ax[0].set_ylabel(r"impact velocity $v_n$")
    ax[0].set_ylim(bottom=0)
    if len(lines(g)) > 1 or "p11" in g:
        ax[0].legend(loc="upper left", markerscale=6, frameon=False)
    ax[1].set_ylabel(r"$x_{%d}(t_0 + kT)$ (stroboscopic)" % (j + 1))
    # classification strips, one row per line (up on top): P(n, m) colours
    ls = sorted(lines(g), key=lambda x: -x[1])
    cls = [[f"P({a},{b})" if a > 0 else ("failed" if a < 0 else "none")
            for a, b in zip(n[l], m[l])] for l, _, _ in ls]
    kinds = sorted({c for row in cls for c in row}, key=lambda s: (s in ("none", "failed"), s))
    cmap = plt.get_cmap("tab10")
    colour = lambda c: "0.85" if c == "none" else ("k" if c == "failed" else cmap(kinds.index(c) % 10))
    step = (p[-1] - p[0]) / max(len(p) - 1, 1) if len(p) > 1 else 1.0
    for row, (l, d, _) in enumerate(ls):
        y0 = len(ls) - 1 - row
        for k, c in enumerate(cls[row]):
            ax[2].fill_between([p[k] - step / 2, p[k] + step / 2], y0, y0 + 0.9,
                               color=colour(c), lw=0)
    ax[2].set_ylim(0, len(ls))
    handles = [plt.Rectangle((0, 0), 1, 1, color=colour(c)) for c in kinds]
    ax[2].legend(handles, kinds, ncol=min(len(kinds), 7), loc="upper center",
                 bbox_to_anchor=(0.5, -0.9), frameon=False, fontsize=8)
    if len(ls) > 1:
        ax[2].set_yticks([len(ls) - 1 - r + 0.45 for r in range(len(ls))])
        ax[2].set_yticklabels(["up" if d > 0 else "down" for _, d, _ in ls], fontsize=8)
    else:
        ax[2].set_yticks([])
    ax[2].set_xlabel(label(key))
    ax[2].set_xlim(p[0] - step / 2, p[-1] + step / 2)
    fig.suptitle(f"{stem}: bifurcation diagram ({int(g.attrs['transient'])} transient + "
                 f"{int(g.attrs['record'])} recorded periods per value)", fontsize=10)
    fig.tight_layout()
    path = os.path.join(out, stem + "_bifurcation.png")
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return path


def two_param(g, out, stem):
    p, p2 = g["param"][:], g["param2"][:]
    n, m = g["n"][:], g["m"][:]
    ups = [l for l, d, _ in lines(g) if d > 0] or [l for l, _, _ in lines(g)]
    rows = g["row"][:]
    N = np.zeros((len(p2), len(p))); M = np.zeros_like(N)
    for l in ups:
        N[rows[l]] = n[l]; M[rows[l]] = m[l]
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.5))
    N = np.maximum(N, 0)  # failed values (n = -1) shown as "none"
    h = (p[-1] - p[0]) / max(len(p) - 1, 1) / 2 or 0.5
    h2 = (p2[-1] - p2[0]) / max(len(p2) - 1, 1) / 2 or 0.5
    ext = [p[0] - h, p[-1] + h, p2[0] - h2, p2[-1] + h2]  # cells centred on the values
    top = int(max(N.max(), 1))
    im = ax[0].imshow(N, origin="lower", aspect="auto", extent=ext,
                      cmap=ListedColormap(["0.85"] + [plt.get_cmap("tab10")(i % 10) for i in range(top)]),
                      vmin=-0.5, vmax=top + 0.5, interpolation="nearest")
    fig.colorbar(im, ax=ax[0], ticks=range(top + 1), label="period n (0: none)")
    im = ax[1].imshow(M, origin="lower", aspect="auto", extent=ext, cmap="viridis",
                      interpolation="nearest")
    fig.colorbar(im, ax=ax[1], label="impacts per orbit m")
    for a in ax:
        a.set_xlabel(label(text(g.attrs["key"])))
        a.set_ylabel(label(text(g.attrs["key2"])))
    fig.suptitle(f"{stem}: P(n, m) map", fontsize=10)
    fig.tight_layout()
    path = os.path.join(out, stem + "_map.png")
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return path


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("file")
    ap.add_argument("--out", default=None)
    ap.add_argument("--coord", type=int, default=0,
                    help="coordinate (1-based) of the stroboscopic panel (default: the last)")
    a = ap.parse_args()
    out = a.out or os.path.dirname(os.path.abspath(a.file))
    stem = os.path.splitext(os.path.basename(a.file))[0]
    with h5py.File(a.file, "r") as f:
        if text(f.attrs.get("kind", b"")) != "sweep" or "sweep" not in f:
            print(f"plot_sweep: {a.file} is not a sweep file (vibroimpact sweep -o)", file=sys.stderr)
            return 2
        g = f["sweep"]
        path = two_param(g, out, stem) if "param2" in g else bifurcation(g, out, stem, a.coord)
    print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/python3
"""Two-parameter bifurcation curves from `vibroimpact curves -o CURVE.h5`
(layout: doc/curves.md), drawn over the P(n, m) map of a two-parameter
sweep of the same plane (`vibroimpact sweep ... --param2 ... -o SWEEP.h5`).

    /usr/bin/python3 share/plot_curves.py CURVE.h5 [CURVE.h5 ...]
                     [--sweep SWEEP.h5] [--out FILE.png]

Each curve is a line (its kind in the legend), its codimension-two points
are marked and named; the sweep's cells (its up lines) are coloured by the
period n of the impacting motion (0: no impacts), so the curves should run
along the borders of the regions.
A curve whose (param, param2) are the sweep's (param2, param) is drawn
transposed.  Writes FILE.png (default: the first curve's name, _curves.png).
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

SP = ["grazing", "fold", "period_doubling", "cusp", "resonance_1_1", "resonance_1_2",
      "admissibility"]


def text(v):
    return v.decode() if isinstance(v, bytes) else str(v)


def label(key):
    names = {"forcing.omega": r"forcing frequency $\Omega$", "stop.xs": r"clearance $x_s$",
             "stop.r": r"restitution $r$"}
    return names.get(key, key)


def sweep_map(ax, path):
    """The sweep's period map; returns its (key, key2)."""
    with h5py.File(path, "r") as f:
        if text(f.attrs.get("kind", b"")) != "sweep" or "param2" not in f.get("sweep", {}):
            raise SystemExit(f"plot_curves: {path} is not a two-parameter sweep file")
        g = f["sweep"]
        p, p2, n, m = g["param"][:], g["param2"][:], g["n"][:], g["m"][:]
        d, rows = g["direction"][:], g["row"][:]
        N = np.zeros((len(p2), len(p)))
        for l in range(len(d)):
            if d[l] > 0:
                N[rows[l]] = np.where(m[l] > 0, np.maximum(n[l], 0), 0)
        h = (p[-1] - p[0]) / max(len(p) - 1, 1) / 2 or 0.5
        h2 = (p2[-1] - p2[0]) / max(len(p2) - 1, 1) / 2 or 0.5
        top = int(max(N.max(), 1))
        im = ax.imshow(N, origin="lower", aspect="auto",
                       extent=[p[0] - h, p[-1] + h, p2[0] - h2, p2[-1] + h2],
                       cmap=ListedColormap(["0.9"] + [plt.get_cmap("Pastel1")(i % 9)
                                                      for i in range(top)]),
                       vmin=-0.5, vmax=top + 0.5, interpolation="nearest")
        plt.colorbar(im, ax=ax, ticks=range(top + 1),
                     label="sweep: period n of the impacting motion (0: no impacts)")
        ax.set_xlim(p[0] - h, p[-1] + h)
        ax.set_ylim(p2[0] - h2, p2[-1] + h2)
        return text(g.attrs["key"]), text(g.attrs["key2"])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("curves", nargs="+")
    ap.add_argument("--sweep", default=None)
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    fig, ax = plt.subplots(figsize=(8, 5.5))
    keys = sweep_map(ax, a.sweep) if a.sweep else None
    colours = plt.get_cmap("tab10")
    for i, path in enumerate(a.curves):
        with h5py.File(path, "r") as f:
            if text(f.attrs.get("kind", b"")) != "curves" or "curve" not in f:
                print(f"plot_curves: {path} is not a curves file (vibroimpact curves -o)",
                      file=sys.stderr)
                return 2
            g = f["curve"]
            k1, k2 = text(g.attrs["param"]), text(g.attrs["param2"])
            pts, sp = g["points"][:], g["special_points"][:]
            st = g["special_type"][:]
            orbit = g.attrs["orbit"]
            kind = text(g.attrs["kind"])
        flip = keys is not None and (k2, k1) == keys
        if keys is None:
            keys = (k1, k2)
        x, y = (pts[:, 1], pts[:, 0]) if flip else (pts[:, 0], pts[:, 1])
        ax.plot(x, y, "-", color=colours(i % 10), lw=1.6,
                label=f"{kind}, P({orbit[0]},{orbit[1]})")
        for (u, v), t in zip(sp, st):
            px, py = (v, u) if flip else (u, v)
            ax.plot(px, py, "o", ms=6, mfc="none", mec="k")
            ax.annotate(SP[t] if 0 <= t < len(SP) else "?", (px, py), fontsize=7,
                        xytext=(4, 4), textcoords="offset points")
    ax.set_xlabel(label(keys[0]))
    ax.set_ylabel(label(keys[1]))
    ax.legend(loc="best", fontsize=8)
    ax.set_title("two-parameter bifurcation curves" + (" over the sweep's map" if a.sweep else ""),
                 fontsize=10)
    fig.tight_layout()
    out = a.out or os.path.splitext(os.path.abspath(a.curves[0]))[0] + "_curves.png"
    fig.savefig(out, dpi=150)
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())

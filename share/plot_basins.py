#!/usr/bin/python3
"""Basins of attraction from `vibroimpact basins -o BASINS.h5`
(layout: doc/sweep-layout.md, plus /sweep/attractor).

    /usr/bin/python3 share/plot_basins.py BASINS.h5 [--out DIR]

Writes DIR/NAME_basins.png (default DIR: beside the file): every cell of
the (param, param2) grid coloured by its attractor (same orbit, same
colour), the legend giving each attractor's P(n, m) and its share of the
cells; grey where no period was found or the cell failed.
Needs Debian's python3-h5py and python3-matplotlib.
"""
import argparse
import os

import h5py
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import ListedColormap
from matplotlib.patches import Patch


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file")
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    with h5py.File(a.file, "r") as f:
        g = f["sweep"]
        if "attractor" not in g:
            raise SystemExit("%s: no /sweep/attractor: not a basins file" % a.file)
        key, key2 = g.attrs["key"], g.attrs["key2"]
        key = key.decode() if isinstance(key, bytes) else str(key)
        key2 = key2.decode() if isinstance(key2, bytes) else str(key2)
        p, p2 = g["param"][()], g["param2"][()]
        att, n, m = g["attractor"][()], g["n"][()], g["m"][()]
    nattr = int(att.max()) + 1 if att.size else 0
    base = plt.get_cmap("tab10")
    colours = [(0.8, 0.8, 0.8, 1.0)] + [base(i % 10) for i in range(max(nattr, 1))]
    img = att + 1  # -1 (none) -> 0, grey
    fig, ax = plt.subplots(figsize=(7, 5.5))
    dx = (p[1] - p[0]) / 2 if len(p) > 1 else 0.5
    dy = (p2[1] - p2[0]) / 2 if len(p2) > 1 else 0.5
    ax.imshow(img, origin="lower", aspect="auto", interpolation="nearest",
              cmap=ListedColormap(colours[:nattr + 1]), vmin=0, vmax=max(nattr, 1),
              extent=[p[0] - dx, p[-1] + dx, p2[0] - dy, p2[-1] + dy])
    handles = []
    for k in range(nattr):
        cells = att == k
        i = np.argwhere(cells)[0]
        handles.append(Patch(color=colours[k + 1], label="%d: P(%d,%d), %.0f %%" % (
            k, n[i[0], i[1]], m[i[0], i[1]], 100.0 * cells.mean())))
    if (att < 0).any():
        handles.append(Patch(color=colours[0], label="none, %.0f %%" % (100.0 * (att < 0).mean())))
    ax.legend(handles=handles, loc="upper right", fontsize=8, framealpha=0.9)
    ax.set_xlabel(key)
    ax.set_ylabel(key2)
    ax.set_title("basins of attraction: %d attractor%s" % (nattr, "" if nattr == 1 else "s"))
    out = a.out or os.path.dirname(os.path.abspath(a.file))
    os.makedirs(out, exist_ok=True)
    name = os.path.splitext(os.path.basename(a.file))[0]
    path = os.path.join(out, name + "_basins.png")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    print(path)


if __name__ == "__main__":
    main()

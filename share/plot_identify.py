#!/usr/bin/python3
"""Plot an identification (`vibroimpact identify ... -o FIT.h5`): the
recording and the fitted model's response over one period of the fitted
orbit (samples folded by their phase), and the residuals below, against
the noise level.  Needs python3-h5py and python3-matplotlib.

usage: plot_identify.py FIT.h5 [--out DIR]   (writes DIR/STEM_identify.png)
"""
import argparse
import os

import h5py
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file")
    ap.add_argument("--out", default=".")
    a = ap.parse_args()
    with h5py.File(a.file, "r") as f:
        g = f["identify"]
        ph, x, mo, res = (np.asarray(g[k]) for k in ("phase", "x", "model", "residual"))
        val, se = np.asarray(g["value"]), np.asarray(g["stderr"])
        at = {k: g.attrs[k] for k in g.attrs}
    keys = str(at.get("keys", b"")).strip("b'").split(",")
    o = np.argsort(ph)
    fig, (ax, ar) = plt.subplots(2, 1, figsize=(7, 6), sharex=True,
                                 gridspec_kw={"height_ratios": [3, 1.4]})
    ax.plot(ph, x, ".", ms=2, color="0.55", label="recording")
    ax.plot(ph[o], mo[o], "-", lw=1.2, color="C3", label="fitted model")
    ax.set_ylabel("displacement")
    fit = ", ".join("%s = %.4g ± %.2g" % (k, v, s) for k, v, s in zip(keys, val, se))
    ax.set_title("P(%d,%d) orbit, %d samples: %s" % (at["orbit_n"], at["orbit_m"], len(x), fit),
                 fontsize=9)
    ax.legend(loc="best", fontsize=8)
    ar.plot(ph, res, ".", ms=2, color="C0")
    nz = at.get("noise", np.nan)
    ar.axhline(0, color="k", lw=0.6)
    if np.isfinite(nz):
        for s in (-2 * nz, 2 * nz):
            ar.axhline(s, color="C1", lw=0.8, ls="--")
    ar.set_ylabel("residual")
    ar.set_xlabel("phase in the orbit period (from the impact)")
    ar.set_title("residual RMS %.3g, noise %.3g (dashed: ±2 noise)" % (at["rms_residual"], nz),
                 fontsize=9)
    fig.tight_layout()
    stem = os.path.splitext(os.path.basename(a.file))[0]
    path = os.path.join(a.out, stem + "_identify.png")
    fig.savefig(path, dpi=110)
    print(path)


if __name__ == "__main__":
    main()

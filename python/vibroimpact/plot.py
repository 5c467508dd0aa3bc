"""matplotlib figures of results and studies, the Python counterparts of
share/plot.py (phase portraits, the impacting coordinate, the ledger),
share/plot_sweep.py (bifurcation diagram), share/plot_basins.py and
share/plot_identify.py, drawn from Result objects and study dicts instead
of HDF5 files.  Each returns the matplotlib Figure (nothing is shown or
saved: ``fig.savefig(...)``).  matplotlib is imported on first use."""
from typing import Any, Dict, Optional

import numpy as np

from ._core import Result


def _plt():
    import matplotlib.pyplot as plt
    return plt


def phase(res: Result, coords: Optional[list] = None, last: float = 0.5):
    """Phase portraits x_i vs v_i of the sampled motion (the last fraction
    ``last`` of the samples), impacts marked; run with samples_per_period."""
    plt = _plt()
    s, ev = res.samples, res.impacts
    if s["t"].size < 2:
        raise ValueError("no samples: simulate with samples_per_period or sample_dt")
    k0 = int((1 - last) * s["t"].size)
    n = s["x"].shape[1]
    coords = coords if coords is not None else list(range(max(0, n - 2), n))
    fig, ax = plt.subplots(1, len(coords), figsize=(5 * len(coords), 4.2), squeeze=False)
    for a, i in zip(ax[0], coords):
        a.plot(s["x"][k0:, i], s["v"][k0:, i], lw=0.8)
        if "x" in ev and ev["t"].size:
            sel = ev["t"] >= s["t"][k0]
            a.plot(ev["x"][sel, i], ev["v_minus"][sel, i], "r.", ms=4, label="impacts")
            a.legend(loc="best")
        a.set(xlabel="$x_{%d}$" % (i + 1), ylabel="$\\dot x_{%d}$" % (i + 1),
              title="coordinate %d" % (i + 1))
    fig.tight_layout()
    return fig


def gap(res: Result, w: np.ndarray, xs: float, last: float = 0.5):
    """The impacting coordinate w.x against time with the stop x_s."""
    plt = _plt()
    s, ev = res.samples, res.impacts
    k0 = int((1 - last) * s["t"].size)
    fig, ax = plt.subplots(figsize=(10, 3.8))
    ax.plot(s["t"][k0:], s["x"][k0:] @ np.asarray(w, float), lw=0.8, label="$w \\cdot x$")
    ax.axhline(xs, color="k", ls="--", lw=1, label="stop $x_s$")
    if "x" in ev and ev["t"].size:
        sel = ev["t"] >= s["t"][k0]
        ax.plot(ev["t"][sel], ev["x"][sel] @ np.asarray(w, float), "r.", ms=4, label="impacts")
    ax.set(xlabel="$t$", ylabel="$w \\cdot x$")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    fig.tight_layout()
    return fig


def ledger(res: Result, last: float = 1.0):
    """Per-mode energy ledger summed over the last fraction of intervals:
    forcing work, damping loss, coupling, contact work, impact jumps."""
    plt = _plt()
    L = res.ledger
    if not L.get("FE", np.empty(0)).size:
        raise ValueError("no ledger: simulate with ledger=True")
    k0 = int((1 - last) * L["FE"].shape[0])
    cols = [("FE", "forcing work FE"), ("DE", "damping loss DE"), ("XE", "coupling XE"),
            ("CE", "contact work CE"), ("NE", "nonlinear force work NE"),
            ("dE", "impact jumps dE")]
    sums = {k: L[k][k0:].sum(axis=0) for k, _ in cols}
    if not np.any(sums["NE"]):
        del sums["NE"]
    cols = [c for c in cols if c[0] in sums]
    n = sums["FE"].size
    idx = np.arange(n)
    wdt = 0.8 / len(cols)
    fig, ax = plt.subplots(figsize=(max(6, 1.5 * n + 3), 4))
    for s, (k, lab) in enumerate(cols):
        ax.bar(idx + (s - (len(cols) - 1) / 2) * wdt, sums[k], wdt, label=lab)
    ax.axhline(0, color="k", lw=0.5)
    ax.set_xticks(idx, ["mode %d" % (j + 1) for j in idx])
    ax.set(ylabel="energy", title="ledger (closure %.0e)" % L["residual"][k0:].max())
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def bifurcation(sw: Dict[str, Any], coord: int = -1, key: str = "parameter"):
    """A sweep's bifurcation diagram: impact velocities and stroboscopic
    states against the parameter, with the P(n, m) of each point."""
    plt = _plt()
    fig, ax = plt.subplots(3, 1, figsize=(7.5, 8.5), sharex=True,
                           gridspec_kw={"height_ratios": [3, 3, 0.7]})
    ax[0].scatter(sw["impact_value"], sw["impact_vn"], s=0.8, c="k", marker=".")
    if "orbit_vn" in sw and sw["orbit_vn"].size:
        ok = sw["orbit_admissible"]
        for stab, kw in ((False, dict(c="tab:blue", marker="x", s=6, label="unstable P(1,1)")),
                         (True, dict(c="tab:green", marker="_", s=10, label="stable P(1,1)"))):
            sel = ok & (sw["orbit_stable"] == stab)
            ax[0].scatter(sw["value"][sw["orbit_point"][sel].astype(int)], sw["orbit_vn"][sel],
                          **kw)
        ax[0].legend(loc="upper left", frameon=False)
    ax[0].set_ylabel("impact velocity $v_n$")
    P, R = sw["strobe"].shape[:2]
    n2 = sw["strobe"].shape[2] // 2
    j = coord % n2
    ax[1].scatter(np.repeat(sw["value"], R), sw["strobe"][:, :, j].ravel(), s=0.8, c="k",
                  marker=".")
    ax[1].set_ylabel("$x_{%d}(t_0 + kT)$" % (j + 1))
    labels = ["P(%d,%d)" % (a, b) if a > 0 else "none" for a, b in zip(sw["n"], sw["m"])]
    kinds = sorted(set(labels))
    cmap = plt.get_cmap("tab10")
    v = sw["value"]
    step = (v[-1] - v[0]) / max(len(v) - 1, 1) if len(v) > 1 else 1.0
    for k, lab in enumerate(labels):
        ax[2].fill_between([v[k] - step / 2, v[k] + step / 2], 0, 1,
                           color="0.85" if lab == "none" else cmap(kinds.index(lab) % 10), lw=0)
    ax[2].set_yticks([])
    handles = [plt.Rectangle((0, 0), 1, 1, color="0.85" if c == "none" else
                             cmap(kinds.index(c) % 10)) for c in kinds]
    ax[2].legend(handles, kinds, ncol=min(len(kinds), 7), loc="upper center",
                 bbox_to_anchor=(0.5, -0.5), frameon=False, fontsize=8)
    ax[2].set_xlabel(key)
    fig.tight_layout()
    return fig


def basins(b: Dict[str, Any], key: str = "parameter 1", key2: str = "parameter 2"):
    """Basins of attraction: each grid point coloured by its attractor."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(6.5, 5))
    ids = np.ma.masked_less(b["id"], 0)
    im = ax.pcolormesh(b["value"], b["value2"], ids, cmap="tab10", shading="nearest",
                       vmin=0, vmax=9)
    ax.set(xlabel=key, ylabel=key2, title="%d attractor(s)" % b["nattr"])
    fig.colorbar(im, ax=ax, label="attractor")
    fig.tight_layout()
    return fig


def identify(fit: Dict[str, Any], t: np.ndarray, x: np.ndarray):
    """A recording against the identified model's response, and the residual."""
    plt = _plt()
    fig, ax = plt.subplots(2, 1, figsize=(9, 6), sharex=True)
    ax[0].plot(t, x, ".", ms=2, label="recording")
    ax[0].plot(t, fit["response"], lw=0.8, label="fitted model")
    ax[0].legend(loc="best")
    ax[0].set_title(", ".join("%s = %.6g" % (k, p) for k, p in zip(fit["keys"], fit["p"])))
    ax[1].plot(t, np.asarray(x) - fit["response"], lw=0.6)
    ax[1].set(xlabel="t", ylabel="residual")
    fig.tight_layout()
    return fig

"""The matplotlib helpers draw from results and study dicts (Agg backend)."""
import numpy as np
import pytest

import vibroimpact as vi

mpl = pytest.importorskip("matplotlib")
mpl.use("Agg")
import vibroimpact.plot as vp  # noqa: E402


def test_figures(tmp_path):
    m = vi.Model.chain(2, m=1, k=1, c=0.1, stops=[{"w": [0, 1], "xs": 0.1, "r": 0.7}],
                       forcing={"omega": 0.9, "a": [0.5, 0.0]})
    res = m.simulate(periods=40, samples_per_period=32, ledger=True)
    sw = vi.sweep(m, "forcing.omega", np.linspace(0.85, 0.95, 3), transient=50, record=4,
                  orbits=16)
    b = vi.basins(m, "initial.x[2]", [-0.2, 0.0], "initial.v[2]", [0.0, 0.2], transient=40,
                  record=4)
    for name, fig in (("phase", vp.phase(res)), ("gap", vp.gap(res, [0, 1], 0.1)),
                      ("ledger", vp.ledger(res)),
                      ("bif", vp.bifurcation(sw, key="forcing.omega")),
                      ("basins", vp.basins(b))):
        p = tmp_path / (name + ".png")
        fig.savefig(p)
        assert p.stat().st_size > 1000

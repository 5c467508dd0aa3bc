"""Scenes from Python: the same impacts as the program, errors that name
the key, HDF5 files of the program's layout."""
import os
import subprocess

import numpy as np
import pytest

import vibroimpact as vi
from conftest import SCENES

FIG2 = os.path.join(SCENES, "fig2.yaml")


def _program_impacts(prog, tmp_path, *args):
    csv = tmp_path / "impacts.csv"
    subprocess.run([prog, "run", FIG2, "--quiet", "--impacts-csv", str(csv), *args],
                   check=True)
    return np.loadtxt(csv, delimiter=",", skiprows=1, ndmin=2)


def test_fig2_scene_equals_program(prog, tmp_path):
    """Fig. 2 from its scene: every impact time, approach velocity and
    pre-impact state equal to the program's to 1e-13 (the same library, the
    same settings: any difference would be the binding's)."""
    ref = _program_impacts(prog, tmp_path)
    res = vi.load_scene(FIG2).run()
    ev = res.impacts
    imp = ev["kind"] == 0
    assert ref.shape[0] == 100 == imp.sum()  # P(1,1): one impact per period
    np.testing.assert_allclose(ev["t"][imp], ref[:, 1], rtol=0, atol=1e-13)
    np.testing.assert_allclose(ev["vn"][imp], ref[:, 2], rtol=0, atol=1e-13)
    np.testing.assert_allclose(ev["x"][imp], ref[:, 3:5], rtol=0, atol=1e-13)
    np.testing.assert_allclose(ev["v_minus"][imp], ref[:, 5:7], rtol=0, atol=1e-13)
    # Newton's law at every impact: w.v+ = -r w.v-
    np.testing.assert_allclose(ev["v_plus"][imp][:, 1], -0.7 * ev["v_minus"][imp][:, 1],
                               rtol=1e-12, atol=1e-15)


def test_fig2_numpy_model_equals_program(prog, tmp_path):
    """Fig. 2 from numpy matrices (the chain written out by hand, m = k = 1,
    c = 0.1): the program's impacts to 1e-13 with the same method and
    tolerances."""
    ref = _program_impacts(prog, tmp_path, "--method", "exact", "--rtol", "1e-10",
                           "--atol", "1e-12")
    M = np.eye(2)
    K = np.array([[2.0, -1.0], [-1.0, 1.0]])
    C = 0.1 * K
    m = vi.Model(M=M, C=C, K=K, stops=[{"w": [0, 1], "xs": 0.1, "r": 0.7}],
                 forcing={"omega": 0.9, "a": [0.5, 0.0]})
    res = m.simulate(periods=100, method="exact", rtol=1e-10, atol=1e-12)
    ev = res.impacts
    assert ev["t"].size == ref.shape[0] == 100
    np.testing.assert_allclose(ev["t"], ref[:, 1], rtol=0, atol=1e-13)
    np.testing.assert_allclose(ev["vn"], ref[:, 2], rtol=0, atol=1e-13)
    np.testing.assert_allclose(ev["x"], ref[:, 3:5], rtol=0, atol=1e-13)


def test_fig2_period_one(prog):
    """Physics without the program: the settled P(1,1) orbit repeats every
    forcing period 2 pi / 0.9 with a fixed approach velocity."""
    res = vi.load_scene(FIG2).run(method="exact", rtol=1e-10, atol=1e-12)
    t, vn = res.impacts["t"], res.impacts["vn"]
    np.testing.assert_allclose(np.diff(t[-20:]), 2 * np.pi / 0.9, rtol=1e-9)
    assert np.ptp(vn[-20:]) < 1e-9 * abs(vn[-1])


def test_restitution_out_of_range_names_key(tmp_path):
    text = open(FIG2).read().replace("r: 0.7", "r: 2")
    p = tmp_path / "bad.yaml"
    p.write_text(text)
    with pytest.raises(vi.Error) as e:
        vi.load_scene(p)
    err = e.value
    assert err.key == "stop.r"
    assert err.file == str(p)
    assert err.line == text.splitlines().index(
        [ln for ln in text.splitlines() if ln.startswith("stop:")][0]) + 1
    assert err.status_name == "VI_ERR_RESTITUTION"
    assert "stop.r" in str(err) and "2" in str(err)


def test_settings_override_key():
    """A --set style override: Omega outside the scene changes the period
    the impacts follow."""
    res = vi.load_scene(FIG2).run(**{"forcing.omega": 0.8})
    assert res.stats["impacts"] > 0
    with pytest.raises(vi.Error) as e:
        vi.load_scene(FIG2).run(**{"stop.r": -1})
    assert e.value.key == "stop.r"


def test_to_hdf5_layout(prog, tmp_path):
    """The file written from Python has the program's groups and datasets,
    with equal contents."""
    h5py = pytest.importorskip("h5py")
    ours = tmp_path / "py.h5"
    theirs = tmp_path / "prog.h5"
    vi.load_scene(FIG2).run().to_hdf5(ours)
    subprocess.run([prog, "run", FIG2, "--quiet", "-o", str(theirs)], check=True)
    with h5py.File(ours) as a, h5py.File(theirs) as b:
        assert set(a) == set(b)
        for g in ("impacts", "trajectory", "ledger", "model", "modal"):
            assert set(a[g]) == set(b[g]), g
            for d in a[g]:
                np.testing.assert_allclose(a[g][d][()], b[g][d][()], rtol=0, atol=1e-13)
        assert a.attrs["complete"] == 1
        assert set(a["run"].attrs) == set(b["run"].attrs)

"""Models from numpy arrays: results as arrays, the ledger's energy
balance, HDF5 output, parameters by key."""
import numpy as np
import pytest

import vibroimpact as vi


def fig2(**kw):
    K = np.array([[2.0, -1.0], [-1.0, 1.0]])
    return vi.Model(M=np.eye(2), C=0.1 * K, K=K, stops=[{"w": [0, 1], "xs": 0.1, "r": 0.7}],
                    forcing={"omega": 0.9, "a": [0.5, 0.0]}, **kw)


def test_ledger_closes_and_impact_losses_match():
    """WB 10 and the ledger: every interval's energy balance closes to the
    tolerance, and the energy lost at impacts equals the events' ie, which
    equals (1 - r^2) v_n^2 / (2 w.M^-1.w) for each impact."""
    res = fig2().simulate(periods=50, method="exact", rtol=1e-10, atol=1e-12, ledger=True)
    L, ev = res.ledger, res.impacts
    bal = (L["E_b"] - L["E_a"] - L["FE"] + L["DE"] + L["XE"] - L["CE"] - L["NE"]).sum(axis=1)
    assert np.max(np.abs(bal)) < 1e-8
    assert np.max(L["residual"]) < 1e-8
    np.testing.assert_allclose(L["ie"][L["impact"] == 1], ev["ie"], rtol=1e-12)
    # w = e_2 and M = I: w.M^-1.w = 1
    np.testing.assert_allclose(ev["ie"], (1 - 0.7 ** 2) * ev["vn"] ** 2 / 2, rtol=1e-10)
    # the jumps dE sum to -ie at each impact (WB 10)
    np.testing.assert_allclose(L["dE"][L["impact"] == 1].sum(axis=1), -ev["ie"], rtol=1e-9)


def test_samples_uniform_and_below_stop():
    res = fig2().simulate(periods=10, samples_per_period=32, method="exact")
    s = res.samples
    T = 2 * np.pi / 0.9
    np.testing.assert_allclose(np.diff(s["t"]), T / 32, rtol=1e-9)
    assert s["x"].shape == (s["t"].size, 2)
    assert np.all(s["x"][:, 1] <= 0.1 + 1e-9)


def test_params_by_key():
    """A model built once, changed by key: Omega moves the orbit's period,
    r the restitution applied at every impact."""
    m = fig2()
    m.set_param("forcing.omega", 0.8)
    assert m.get_param("forcing.omega") == 0.8
    m.set_param("stop.r", 0.5)
    res = m.simulate(periods=200, method="exact", rtol=1e-10, atol=1e-12)
    ev = res.impacts
    np.testing.assert_allclose(ev["v_plus"][:, 1], -0.5 * ev["v_minus"][:, 1], rtol=1e-12,
                               atol=1e-15)
    with pytest.raises(vi.Error) as e:
        m.set_param("stop.r", 3.0)
    assert e.value.status_name == "VI_ERR_RESTITUTION"
    with pytest.raises(vi.Error) as e:
        m.set_param("no.such.key", 1.0)
    assert "no.such.key" in str(e.value)


def test_to_hdf5_of_a_model(tmp_path):
    h5py = pytest.importorskip("h5py")
    m = fig2()
    res = m.simulate(periods=20, samples_per_period=16, ledger=True, method="exact")
    p = tmp_path / "m.h5"
    res.to_hdf5(p)
    with h5py.File(p) as f:
        np.testing.assert_array_equal(f["model/K"][()], [[2, -1], [-1, 1]])
        np.testing.assert_array_equal(f["impacts/time"][()], res.impacts["t"])
        np.testing.assert_array_equal(f["impacts/kind"][()], res.impacts["kind"])
        np.testing.assert_array_equal(f["trajectory/x"][()], res.samples["x"])
        np.testing.assert_array_equal(f["ledger/FE"][()], res.ledger["FE"])
        assert f["run"].attrs["method_used"] in (b"exact", "exact")
        assert f.attrs["complete"] == 1
    m.set_param("forcing.omega", 0.8)
    with pytest.raises(vi.Error):
        res.to_hdf5(tmp_path / "stale.h5")


def test_model_errors():
    K = np.array([[2.0, -1.0], [-1.0, 1.0]])
    with pytest.raises(vi.Error) as e:
        vi.Model(M=np.eye(2), K=K, stops=[{"w": [0, 1], "xs": 0.1, "r": 1.5}])
    assert e.value.status_name == "VI_ERR_RESTITUTION"
    with pytest.raises(vi.Error) as e:
        vi.Model(M=-np.eye(2), K=K, stops=[{"w": [0, 1], "xs": 0.1, "r": 0.5}])
    assert e.value.status_name == "VI_ERR_NOT_SPD"
    with pytest.raises(vi.Error) as e:
        vi.Model(M=np.eye(2), K=np.array([[2.0, -1.0], [0.0, 1.0]]),
                 stops=[{"w": [0, 1], "xs": 0.1, "r": 0.5}])
    assert e.value.status_name == "VI_ERR_NOT_SYMMETRIC"
    with pytest.raises(vi.Error):
        vi.Model(M=np.eye(2), K=K, stops=[{"w": [0, 0], "xs": 0.1, "r": 0.5}])
    with pytest.raises(vi.Error):
        vi.Model(M=np.eye(3), K=K, stops=[{"w": [0, 1], "xs": 0.1, "r": 0.5}])
    m = fig2()
    with pytest.raises(vi.Error) as e:
        m.simulate(periods=10, x0=[0.0, 0.5])  # beyond the stop
    assert e.value.status_name == "VI_ERR_INITIAL_STATE"
    with pytest.raises(vi.Error):
        m.simulate(periods=10, rtol=-1)
    with pytest.raises(vi.Error):
        m.simulate(periods=10, method="rk4")


def test_cantilever_builder():
    """Model.cantilever: frequencies in the ratios (beta_j / beta_1)^2 of
    the roots of cos(b) cosh(b) = -1 (scipy's brentq), and the same run as
    the scene cantilever4.yaml that uses the same builder key."""
    import os
    from scipy.optimize import brentq
    from conftest import SCENES
    m = vi.Model.cantilever(4, 1.0, 0.05, xs=0.05, r=0.75, base=0.01, omega=0.85)
    beta = [brentq(lambda b: np.cos(b) * np.cosh(b) + 1, (j + 0.5) * np.pi - 1.5,
                   (j + 0.5) * np.pi + 1.0) for j in range(4)]
    np.testing.assert_allclose(m.omega, (np.array(beta) / beta[0]) ** 2, rtol=1e-10)
    np.testing.assert_allclose(m.zeta, 0.05, rtol=1e-12)
    a = m.simulate(periods=300, method="exact", rtol=1e-10, atol=1e-12).impacts
    b = vi.load_scene(os.path.join(SCENES, "cantilever4.yaml")).run().impacts
    assert a["t"].size == b["t"].size > 100
    np.testing.assert_allclose(a["t"], b["t"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(a["vn"], b["vn"], rtol=0, atol=1e-12)


def test_set_param_while_a_result_holds_the_model():
    """The library refuses to change a model a simulation holds; the Python
    Model then goes on with a changed copy, and the earlier result keeps
    the model it ran on: its end time is 10 periods of Omega = 0.9, the new
    run's 10 periods of 0.8 (T = 2 pi / Omega, to round-off)."""
    m = fig2()
    r1 = m.simulate(periods=10, method="exact")
    m.set_param("forcing.omega", 0.8)
    assert m.get_param("forcing.omega") == 0.8
    r2 = m.simulate(periods=10, method="exact")
    assert r1.t == pytest.approx(10 * 2 * np.pi / 0.9, rel=1e-14)
    assert r2.t == pytest.approx(10 * 2 * np.pi / 0.8, rel=1e-14)
    assert r1.method_used == "exact" and r1.stats["impacts"] >= 9
    with pytest.raises(vi.Error):
        m.set_param("forcing.omgea", 1.0)  # a bad key still names itself

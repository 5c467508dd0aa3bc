"""Finite-element models from scipy.sparse matrices: the library's own
reduction (vi_sparse.h), no files."""
import os
import sys

import numpy as np
import pytest

import vibroimpact as vi
from conftest import ROOT

sp = pytest.importorskip("scipy.sparse")
from scipy.linalg import eigh  # noqa: E402

E, S, RHO = 210e9, 3.14e-4, 7800.0


def bar_sparse(nodes, h):
    """Siconos' impacting bar: linear elements with consistent mass."""
    ne = nodes - 1
    m, k = RHO * S * h, E * S / h
    rows, cols, mv, kv = [], [], [], []
    for e in range(ne):
        for a, b, mm, kk in ((e, e, m / 3, k), (e + 1, e + 1, m / 3, k),
                             (e, e + 1, m / 6, -k), (e + 1, e, m / 6, -k)):
            rows.append(a)
            cols.append(b)
            mv.append(mm)
            kv.append(kk)
    M = sp.csc_matrix((mv, (rows, cols)), shape=(nodes, nodes))
    K = sp.csc_matrix((kv, (rows, cols)), shape=(nodes, nodes))
    return M, K


def bar_release_reference():
    """tests/stress/ref/bar_ref.py (clamped modes by scipy's eigh, the
    contact force's zero by brentq) for the scene's geometry: 499 elements
    of 1/500 m."""
    sys.path.insert(0, os.path.join(ROOT, "tests", "stress", "ref"))
    try:
        import bar_ref
    finally:
        sys.path.pop(0)
    bar_ref.L = 0.998
    return bar_ref.release(499)[0]


def test_impacting_bar_all_500_modes():
    """Siconos' impacting bar from scipy.sparse M, K with all 500 modes
    (the free bar's rigid mode among them): it leaves the obstacle within
    1e-11 s of the constrained-modes reference."""
    M, K = bar_sparse(500, 1.0 / 500)
    m = vi.Model.from_sparse(M, K, stops=[{"dof": 0, "direction": -1, "xs": 0.0, "r": 0.0}])
    fe = m.fe_summary()
    assert fe["modes"] == 500 and fe["rule"] == "whole" and fe["rigid"] == 1
    res = m.simulate(t_end=0.0015, x0=5e-5, v0=-0.1, rtol=1e-9, atol=1e-14)
    rel = res.impact_times("release")
    ref = bar_release_reference()
    print("release %.17g, reference %.17g, error %.2g s" % (rel[0], ref, abs(rel[0] - ref)))
    assert rel.size >= 1
    assert abs(rel[0] - ref) < 1e-11
    # it reached the obstacle as a rigid body: t_c = x0 / |v0| exactly
    assert abs(res.impacts["t"][0] - 5e-4) < 1e-15


def test_sparse_frequencies_match_eigh():
    """The lowest modes of a 200-node bar by the library's Lanczos equal
    scipy.linalg.eigh of the dense matrices to 1e-9 relative."""
    M, K = bar_sparse(200, 1.0 / 200)
    m = vi.Model.from_sparse(M, K, modes=12, zeta=0.01,
                             stops=[{"dof": 0, "direction": -1, "xs": 1e-3, "r": 0.5}])
    lam = eigh(K.toarray(), M.toarray(), eigvals_only=True)[:12]
    om = np.sqrt(np.clip(lam, 0, None))
    np.testing.assert_allclose(m.omega[1:], om[1:], rtol=1e-9)
    assert abs(m.omega[0]) < 1e-6 * om[1]
    assert m.n == 12 and m.dofs == 200
    np.testing.assert_allclose(m.zeta[1:], 0.01, rtol=1e-12)


def test_sparse_fig2_equals_dense():
    """Fig. 2's chain given as scipy.sparse (the whole 2-dof model kept):
    the same impact times as the dense model, in modal coordinates."""
    K = np.array([[2.0, -1.0], [-1.0, 1.0]])
    stops = [{"dof": 1, "xs": 0.1, "r": 0.7}]
    forcing = {"omega": 0.9, "a": [0.5, 0.0]}
    dense = vi.Model(M=np.eye(2), K=K, C=0.1 * K, stops=stops, forcing=forcing)
    fe = vi.Model.from_sparse(sp.identity(2), sp.csc_matrix(K), C=sp.csc_matrix(0.1 * K),
                              stops=stops, forcing=forcing)
    a = dense.simulate(periods=50, method="exact", rtol=1e-10, atol=1e-12).impacts
    b = fe.simulate(periods=50, method="exact", rtol=1e-10, atol=1e-12).impacts
    np.testing.assert_allclose(b["t"], a["t"], rtol=0, atol=1e-9)
    np.testing.assert_allclose(b["vn"], a["vn"], rtol=0, atol=1e-9)
    # physical states back from the modes: x = Psi q
    np.testing.assert_allclose(fe.to_physical(b["x"]), a["x"], rtol=0, atol=1e-9)


def test_sparse_errors():
    """Bad matrices are refused with the library's message, not a crash."""
    M = sp.identity(3, format="csc")
    K = sp.csc_matrix(np.array([[2.0, -1, 0], [-1, 2, -1], [0, -1, 1]]))
    with pytest.raises(vi.Error) as e:
        vi.Model.from_sparse(M, -K, stops=[{"dof": 2, "xs": 0.1, "r": 0.5}])
    assert e.value.status < 0
    with pytest.raises(vi.Error):
        vi.Model.from_sparse(M, K, stops=[{"dof": 7, "xs": 0.1, "r": 0.5}])
    with pytest.raises(vi.Error):
        vi.Model.from_sparse(M, K, stops=[{"dof": 1, "xs": 0.1, "r": 1.5}])
    with pytest.raises(vi.Error):
        vi.Model.from_sparse(sp.identity(2), K, stops=[{"dof": 1, "xs": 0.1, "r": 0.5}])

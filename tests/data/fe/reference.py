#!/usr/bin/python3
"""Independent references for the FE pairs in tests/data/fe (see SOURCES.md).

For each NAME_K.mtx / NAME_M.mtx this computes, with dense LAPACK through
scipy (nothing of vibroimpact is used):
  * massless  - dofs whose row of M is entirely zero;
  * rigid     - dim null(K), decided from K alone: eigenvectors u of the
                diagonally scaled K_s = D^-1/2 K D^-1/2 (unit diagonal) whose
                eigenvalue is below sqrt(eps) lambda_max(K_s) are candidates;
                one is a null vector when K u is at round-off entry by entry,
                max_i |K u|_i / (|K||u|)_i <= 1e4 eps (also reported: the
                count of scaled eigenvalues below n eps lambda_max(K_s));
  * cond(K)   - lambda_max/lambda_min of K itself and of K_s (the smallest
                eigenvalue through a Cholesky-based inverse, which is accurate
                to cond(K_s), not cond(K));
  * the NMODES lowest finite eigenvalues of K psi = lambda M psi from the
    reversed problem  M v = mu (K - sigma M) v,  sigma < 0 with
    K - sigma M positive definite, lambda = sigma + 1/mu: massless dofs give
    mu = 0 and drop out, rigid modes give lambda = 0 (set exactly to 0 for
    the 'rigid' lowest ones; their computed values are kept in lambda_raw);
    sigma is taken ~1e-2 of the lowest flexible eigenvalue so that the
    cancellation in sigma + 1/mu costs nothing;
  * for each mode: the residual |K psi - lambda M psi| / (|K| |psi|), the
    componentwise round-off of K psi, max_i |K psi|_i / (|K||psi|)_i (at
    eps for a rigid mode, far above eps for a flexible one, whatever cond(K)),
    and the eigenvalue's componentwise condition number
        kappa = |psi|'|K||psi| / psi'K psi + |psi|'|M||psi| / psi'M psi,
    so eps*kappa is the accuracy any method working on the stored doubles
    can promise (a relative perturbation eps of each entry of K and M moves
    lambda by at most eps*kappa*lambda);
  * a check independent of the dense solver's round-off: the Rayleigh
    quotient psi'K psi / psi'M psi summed EXACTLY (error-free products and
    math.fsum), which equals the eigenvalue of the stored matrices up to
    O(|error in psi|^2);
  * where n * bandwidth^2 <= FE_MP_BUDGET (2e7) after a reverse
    Cuthill-McKee ordering, a fully extended-precision check: subspace
    inverse iteration with a banded LDL' of K - sigma M and Rayleigh-Ritz in
    mpmath at 40 digits, started from the dense vectors.
  'lambda' is the mp result where there is one, else the exact Rayleigh
  quotient; 'ref_accuracy' is its accuracy, 'rel_accuracy' = max eps*kappa
  what a double-precision solver can be held to.
Writes reference.json next to this file; prints a table.

Usage: reference.py [NAME ...]   (default: every NAME_K.mtx[.xz] here)
Needs python3-scipy and python3-mpmath (Debian).
"""
import glob
import json
import lzma
import math
import os
import sys
import time

import mpmath
import numpy as np
import scipy.io as sio
import scipy.linalg as sl
import scipy.sparse as sp

HERE = os.path.dirname(os.path.abspath(__file__))
EPS = np.finfo(float).eps
NMODES = 10
MP_BUDGET = float(os.environ.get("FE_MP_BUDGET", "2e7"))  # n * bandwidth^2
THRESH_RULE = 1e-13  # the rule of issue 27: lambda < 1e-13 max_j K_jj/M_jj is "rigid"


def load(name, role):
    for path in (f"{name}_{role}.mtx", f"{name}_{role}.mtx.xz"):
        full = os.path.join(HERE, path)
        if os.path.exists(full):
            f = lzma.open(full, "rb") if full.endswith(".xz") else open(full, "rb")
            with f:
                A = sp.csr_matrix(sio.mmread(f))
            A.eliminate_zeros()
            return A
    return None


# --- exact dot products: Dekker/Veltkamp two-product, then math.fsum -------
_SPLIT = 134217729.0  # 2^27 + 1


def _split(a):
    c = _SPLIT * a
    hi = c - (c - a)
    return hi, a - hi


def _two_prod(a, b):
    p = a * b
    ah, al = _split(a)
    bh, bl = _split(b)
    e = ((ah * bh - p) + ah * bl + al * bh) + al * bl
    return p, e


def exact_quad(A, x):
    """x' A x for sparse A, the exact real sum rounded once (fsum)."""
    C = A.tocoo()
    p, e = _two_prod(C.data, x[C.row])
    terms = []
    for t in (p, e):
        q, f = _two_prod(t, x[C.col])
        terms.append(q)
        terms.append(f)
    return math.fsum(np.concatenate(terms).tolist())


# --- extended precision check for small pairs ------------------------------
def mp_check(K, M, vecs, sigma, iters=4):
    """Eigenvalues of the stored K, M in extended precision (mpmath, 40
    digits): subspace inverse iteration with (K - sigma M)^-1 M, started from
    the double-precision vectors, and Rayleigh-Ritz.  K - sigma M is factored
    as L D L' in band form after a reverse Cuthill-McKee ordering (it is
    positive definite, so no pivoting).  Returns the Ritz values of the last
    sweep and their largest relative change over that sweep."""
    from scipy.sparse.csgraph import reverse_cuthill_mckee
    mpmath.mp.dps = 40
    mpf = mpmath.mpf
    n, k = vecs.shape
    pat = sp.csr_matrix(abs(K) + abs(M))
    p = reverse_cuthill_mckee(pat, symmetric_mode=True)
    Kp = sp.csr_matrix(K)[p][:, p].tocoo()
    Mp = sp.csr_matrix(M)[p][:, p].tocoo()
    X = vecs[p, :]
    kent = [(int(i), int(j), mpf(float(v))) for i, j, v in zip(Kp.row, Kp.col, Kp.data)]
    ment = [(int(i), int(j), mpf(float(v))) for i, j, v in zip(Mp.row, Mp.col, Mp.data)]
    bw = int(max(np.max(np.abs(Kp.row - Kp.col)), np.max(np.abs(Mp.row - Mp.col))))
    sig = mpf(sigma)
    # band rows: A[i][i - j] for j = i - bw .. i  (offset o = i - j)
    A = [[mpf(0)] * (bw + 1) for _ in range(n)]
    for i, j, v in kent:
        if j <= i:
            A[i][i - j] += v
    for i, j, v in ment:
        if j <= i:
            A[i][i - j] -= sig * v
    # in-place band L D L'
    D = [mpf(0)] * n
    for j in range(n):
        lo = max(0, j - bw)
        Aj = A[j]
        s = Aj[0]
        for q in range(lo, j):
            l = Aj[j - q]
            s -= l * l * D[q]
        D[j] = s
        if s <= 0:
            raise ValueError("K - sigma M not positive definite in mp")
        for i in range(j + 1, min(n, j + bw + 1)):
            Ai = A[i]
            t = Ai[i - j]
            for q in range(max(0, i - bw), j):
                t -= Ai[i - q] * Aj[j - q] * D[q]
            Ai[i - j] = t / s

    def solve(b):
        y = list(b)
        for i in range(n):
            Ai = A[i]
            t = y[i]
            for q in range(max(0, i - bw), i):
                t -= Ai[i - q] * y[q]
            y[i] = t
        for i in range(n):
            y[i] = y[i] / D[i]
        for i in range(n - 1, -1, -1):
            t = y[i]
            for r in range(i + 1, min(n, i + bw + 1)):
                t -= A[r][r - i] * y[r]
            y[i] = t
        return y

    def matvec(ent, x):
        y = [mpf(0)] * n
        for i, j, v in ent:
            y[i] += v * x[j]
        return y

    def dot(x, y):
        return mpmath.fsum(a * b for a, b in zip(x, y))

    cols = [[mpf(float(v)) for v in X[:, c]] for c in range(k)]
    prev = None
    for _ in range(iters):
        Z = [solve(matvec(ment, x)) for x in cols]
        KZ = [matvec(kent, z) for z in Z]
        MZ = [matvec(ment, z) for z in Z]
        Kr = mpmath.matrix(k, k)
        Mr = mpmath.matrix(k, k)
        for a in range(k):
            for b in range(a, k):
                Kr[a, b] = Kr[b, a] = (dot(Z[a], KZ[b]) + dot(Z[b], KZ[a])) / 2
                Mr[a, b] = Mr[b, a] = (dot(Z[a], MZ[b]) + dot(Z[b], MZ[a])) / 2
        L = mpmath.cholesky(Mr)
        Li = mpmath.inverse(L)
        S = Li * Kr * Li.T
        S = (S + S.T) / 2
        theta, Y = mpmath.eigsy(S)
        order = sorted(range(k), key=lambda i: theta[i])
        theta = [theta[i] for i in order]
        W = Li.T * Y
        cols = []
        for i in order:
            cols.append([mpmath.fsum(Z[c][r] * W[c, i] for c in range(k)) for r in range(n)])
        if prev is not None:
            big = max(abs(t) for t in theta)
            change = max(abs(t - q) / abs(t) for t, q in zip(theta, prev)
                         if abs(t) > 1e-20 * big)
        prev = theta
    return theta, float(change)


def analyse(name):
    K = load(name, "K")
    M = load(name, "M")
    C = load(name, "C")
    n = K.shape[0]
    if M.shape != K.shape or (C is not None and C.shape != K.shape):
        raise ValueError(f"{name}: sizes differ")
    Kd = K.toarray()
    Md = M.toarray()
    res = {"n": n, "nnz_K": int(K.nnz), "nnz_M": int(M.nnz),
           "nnz_C": int(C.nnz) if C is not None else None}

    # symmetry and semi-definiteness of what is stored
    res["asym_K"] = float(abs(Kd - Kd.T).max() / abs(Kd).max())
    res["asym_M"] = float(abs(Md - Md.T).max() / abs(Md).max())
    massless = np.flatnonzero(np.diff(M.indptr) == 0)
    res["massless"] = int(massless.size)
    m_eig = sl.eigvalsh(Md)
    res["M_min_eig_rel"] = float(m_eig[0] / m_eig[-1])
    res["M_rank_deficiency"] = int((m_eig <= n * EPS * m_eig[-1]).sum())

    d = np.diag(Kd).copy()
    if (d <= 0).any():
        raise ValueError(f"{name}: K has a non-positive diagonal entry")
    s = 1.0 / np.sqrt(d)
    Ks = Kd * s[:, None] * s[None, :]
    ks, kv = sl.eigh(Ks)
    tol = n * EPS * ks[-1]
    # a null vector u of K has K u at round-off entry by entry:
    # |K u|_i <= c eps (|K||u|)_i; a flexible mode stays far above that
    # (>= 1e-9 on these models) however large cond(K) is
    cand = np.flatnonzero(ks <= math.sqrt(EPS) * ks[-1])
    absK = abs(K)
    cw_null = []
    for c in cand:
        u = s * kv[:, c]
        den = absK @ abs(u)
        cw_null.append(float(np.max(abs(K @ u)[den > 0] / den[den > 0])))
    rigid = int(sum(1 for x in cw_null if x <= 1e4 * EPS))
    res["rigid"] = rigid
    res["rigid_by_scaled_eigs"] = int((ks <= tol).sum())
    res["null_candidates_Ku_componentwise"] = cw_null
    res["K_scaled_eigs_low"] = [float(x) for x in ks[:max(rigid + 3, 4)]]
    res["K_scaled_null_tol"] = float(tol)
    kev = sl.eigvalsh(Kd)
    res["K_max_eig"] = float(kev[-1])
    if rigid == 0:
        Lc = sl.cholesky(Ks, lower=True)
        Li = sl.solve_triangular(Lc, np.eye(n), lower=True)
        # lambda_min(K) = 1/lambda_max(K^-1), K^-1 = S Ks^-1 S
        Kinv = (Li.T @ Li) * s[:, None] * s[None, :]
        lam_min_K = 1.0 / sl.eigvalsh(Kinv, subset_by_index=[n - 1, n - 1])[0]
        res["cond_K"] = float(kev[-1] / lam_min_K)
        res["cond_K_scaled"] = float(ks[-1] / ks[0])
        res["K_min_eig_direct"] = float(kev[0])
    else:
        res["cond_K"] = None  # singular (JSON has no infinity)
        res["cond_K_scaled"] = None
        res["cond_K_flexible_scaled"] = float(ks[-1] / ks[rigid])

    k = NMODES + rigid
    kb = min(k + 4, n - res["massless"])  # extra vectors for the mp subspace

    def reversed_eigs(sigma):
        A = Kd - sigma * Md
        mu, V = sl.eigh(Md, A, subset_by_index=[n - kb, n - 1])
        order = np.argsort(-mu)
        mu, V = mu[order], V[:, order]
        return sigma + 1.0 / mu, V

    # pass 1: a rough shift that makes K - sigma M definite (K itself when
    # it is definite); pass 2: sigma ~ -1e-2 of the lowest flexible one
    ratio = d[np.diag(Md) > 0] / np.diag(Md)[np.diag(Md) > 0]
    sigma1 = 0.0 if rigid == 0 else -1e-6 * float(np.median(ratio))
    lam1, _ = reversed_eigs(sigma1)
    sigma = -1e-2 * lam1[rigid]
    lamb, V = reversed_eigs(sigma)
    res["sigma"] = float(sigma)
    lam_dense = lamb[:k].copy()
    res["lambda_dense_raw"] = [float(x) for x in lam_dense]
    res["dense_two_shifts_agree"] = float(np.max(np.abs(lam1[rigid:k] - lam_dense[rigid:])
                                                 / lam_dense[rigid:]))

    absM = abs(M)
    Knorm2 = max(kev[-1], abs(kev[0]))
    resid, cw, kappa, lam_rq, rq_diff = [], [], [], [], []
    for j in range(k):
        psi = V[:, j] / math.sqrt(V[:, j] @ (Md @ V[:, j]))
        Kpsi = K @ psi
        r = Kpsi - lam_dense[j] * (M @ psi)
        resid.append(float(np.linalg.norm(r) / (Knorm2 * np.linalg.norm(psi))))
        den = absK @ abs(psi)
        mask = den > 0
        cw.append(float(np.max(abs(Kpsi[mask]) / den[mask])))
        qK = exact_quad(K, psi)
        qM = exact_quad(M, psi)
        lam_rq.append(qK / qM)
        if j >= rigid:
            kappa.append(float(abs(psi) @ (absK @ abs(psi)) / qK
                               + abs(psi) @ (absM @ abs(psi)) / qM))
            rq_diff.append(float(abs(qK / qM - lam_dense[j]) / lam_dense[j]))
        else:
            kappa.append(None)
            rq_diff.append(None)
    res["residual_dense"] = resid
    res["Kpsi_componentwise"] = cw
    res["kappa_componentwise"] = kappa
    res["lambda_rq_exact"] = lam_rq
    res["dense_vs_rq_exact"] = rq_diff

    # extended precision where the band of K - sigma M is narrow enough
    from scipy.sparse.csgraph import reverse_cuthill_mckee
    pat = sp.csr_matrix(abs(K) + abs(M))
    pp = reverse_cuthill_mckee(pat, symmetric_mode=True)
    Pc = pat[pp][:, pp].tocoo()
    bw = int(np.max(np.abs(Pc.row - Pc.col)))
    res["bandwidth_rcm"] = bw
    lam_ref = np.array(lam_rq)
    flex = slice(rigid, k)
    rq_rel = [(lam_rq[j] - lam_dense[j]) / lam_dense[j] for j in range(rigid, k)]
    # RQ of a vector with error e is off by O(|e|^2): (dense error)^2 * lambda/gap
    # gap to the eigenvalues outside the mode's cluster (repeated ones share
    # an invariant subspace, inside which the quotient is still exact)
    gaps = np.array([min([abs(lamb[j] - lamb[i]) / lamb[j] for i in range(rigid, kb)
                          if abs(lamb[j] - lamb[i]) > 1e-8 * lamb[j]] or [1.0])
                     for j in range(rigid, k)])
    ref_acc = float(max(2 * EPS, max(10 * r * r / g for r, g in zip(rq_rel, gaps))))
    res["ref_method"] = "exact Rayleigh quotient of the dense eigenvectors"
    if n * bw * bw <= MP_BUDGET:
        t0 = time.time()
        theta, change = mp_check(K, M, V[:, :kb], sigma)
        mp_lam = np.array([float(t) for t in theta[:k]])
        res["lambda_mp40"] = [float(x) for x in mp_lam]
        res["mp_last_sweep_change"] = change
        res["mp_vs_dense"] = float(max(abs(mp_lam[flex] - lam_dense[flex]) / mp_lam[flex]))
        res["mp_vs_rq_exact"] = float(max(abs(mp_lam[flex] - lam_ref[flex]) / mp_lam[flex]))
        res["mp_seconds"] = round(time.time() - t0, 1)
        lam_ref = mp_lam
        ref_acc = float(max(2 * EPS, change))
        res["ref_method"] = "mpmath 40 digits, banded LDL' subspace inverse iteration"
    lam_ref[:rigid] = 0.0
    res["lambda"] = [float(x) for x in lam_ref]
    res["omega"] = [float(math.sqrt(max(x, 0.0))) for x in lam_ref]
    res["freq_hz"] = [w / (2 * math.pi) for w in res["omega"]]
    res["ref_accuracy"] = ref_acc
    # what a double-precision solver can promise on these stored matrices
    per_mode = [float(max(EPS * x, 2 * EPS)) for x in kappa[rigid:]]
    res["rel_accuracy_per_mode"] = per_mode
    res["rel_accuracy"] = float(max(per_mode))
    res["dense_error"] = float(max(abs(lam_dense[flex] - lam_ref[flex]) / lam_ref[flex]))

    # the threshold rule of issue 27
    scale = THRESH_RULE * float(ratio.max())
    res["threshold_rule_scale"] = scale
    res["threshold_rule_misfires"] = int(sum(1 for x in lam_ref[flex] if x < scale))

    # repeated / clustered eigenvalues among the ones reported
    fl = lam_ref[flex]
    res["min_rel_gap"] = float(np.min(np.abs(np.diff(fl)) / fl[1:])) if fl.size > 1 else None
    return res


def main():
    names = sys.argv[1:] or sorted({os.path.basename(p).rsplit("_K.mtx", 1)[0]
                                    for p in glob.glob(os.path.join(HERE, "*_K.mtx*"))})
    out_path = os.environ.get("FE_REF_JSON", os.path.join(HERE, "reference.json"))
    for name in names:
        t0 = time.time()
        r = analyse(name)
        r["seconds"] = round(time.time() - t0, 1)
        om = ", ".join(f"{w:.6g}" for w in r["omega"][:6])
        print(f"{name}: n={r['n']} nnz(K)={r['nnz_K']} massless={r['massless']}"
              f" rigid={r['rigid']} cond(K)={r['cond_K'] or math.inf:.3g}"
              f" cond(Ks)={r['cond_K_scaled'] or math.inf:.3g} omega[:6]=[{om}]"
              f" rel_acc={r['rel_accuracy']:.2g} rule_scale={r['threshold_rule_scale']:.3g}"
              f" misfires={r['threshold_rule_misfires']} gap={r['min_rel_gap']:.2g}"
              + f" dense_err={r['dense_error']:.2g} ref_acc={r['ref_accuracy']:.2g}"
              + (f" mp_vs_rq={r['mp_vs_rq_exact']:.2g}" if "mp_vs_rq_exact" in r else "")
              + f" ({r['seconds']} s)", flush=True)
        out = {}
        if os.path.exists(out_path):  # merge: other names stay as they are
            with open(out_path) as f:
                out = json.load(f)
        out[name] = r
        with open(out_path, "w") as f:
            json.dump(out, f, indent=1, sort_keys=True)
            f.write("\n")


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Finite-element models for vibroimpact: Matrix Market files and scenes.

    fe_models.py bar  OUTDIR      Siconos' impacting bar (500 dofs)
    fe_models.py beam OUTDIR      a clamped Euler-Bernoulli beam, 100 Hermite
                                  elements, tip stop (the paper's cantilever)
    fe_models.py rod  OUTDIR [N]  a fixed-free rod of N linear elements
                                  (default 100000) and the same 20-mode model
                                  written with its closed-form modes

Each writes M.mtx, K.mtx (symmetric coordinate real, lower triangle, 17
significant digits, so a rerun gives the same bytes) and a scene whose
matrix_market paths are relative to it.  Only numpy is used (Debian's
python3-numpy); the matrices are assembled element by element here, not by a
FE library, so every number can be traced to the formulas below.
"""
import math
import os
import sys

import numpy as np


def write_mm(path, n, rows, cols, vals, comment):
    """Write the lower triangle (rows >= cols, 0-based) of a symmetric n x n
    matrix, sorted by column then row, in Matrix Market coordinate form."""
    order = np.lexsort((rows, cols))
    with open(path, "w") as f:
        f.write("%%MatrixMarket matrix coordinate real symmetric\n")
        for line in comment.strip().splitlines():
            f.write("% " + line + "\n")
        f.write("%d %d %d\n" % (n, n, len(order)))
        for k in order:
            f.write("%d %d %.17g\n" % (rows[k] + 1, cols[k] + 1, vals[k]))


def assemble(nel, ke, me, ndof_node, fixed):
    """Assemble identical elements along a line (element e joins nodes e and
    e + 1, ndof_node dofs per node); drop the `fixed` leading dofs.  Returns
    n and the lower triangles of K and M as (rows, cols, vals)."""
    nd = ke.shape[0]
    total = (nel + 1) * ndof_node
    K = {}
    M = {}
    for e in range(nel):
        dofs = [e * ndof_node + a for a in range(nd)]
        for a in range(nd):
            for b in range(nd):
                i, j = dofs[a], dofs[b]
                if i < fixed or j < fixed or i < j:
                    continue
                K[(i, j)] = K.get((i, j), 0.0) + ke[a, b]
                M[(i, j)] = M.get((i, j), 0.0) + me[a, b]
    def arrays(d):
        keys = sorted(d, key=lambda ij: (ij[1], ij[0]))
        r = np.array([k[0] - fixed for k in keys])
        c = np.array([k[1] - fixed for k in keys])
        v = np.array([d[k] for k in keys])
        keep = v != 0.0
        return r[keep], c[keep], v[keep]
    return total - fixed, arrays(K), arrays(M)


# ---- Siconos' impacting bar ------------------------------------------------
# siconos-tutorials, examples/mechanics/FEM/ImpactingBar/ImpactingBar.py (and
# ImpactingBar.cpp): a free elastic bar, nDof = 500 nodes, linear elements of
# length l = L / nDof with consistent mass (rho S l / 6) [2 1; 1 2] and
# stiffness (E S / l) [1 -1; -1 1], E = 210e9 Pa, S = 3.14e-4 m^2 (1 cm
# diameter... as written there), L = 1 m, rho = 7800 kg/m^3, no gravity;
# every node starts at q = 5e-5 m moving at v = -0.1 m/s towards a rigid
# obstacle that keeps node 1 at q >= 0 (H = e_1), Newton restitution e = 0;
# T = 0.0015 s.  Siconos sizes the element with L / nDof although 500 nodes
# make 499 elements: we keep its numbers, so the bar is 0.998 m long.
def bar(out):
    ndof, E, S, L, rho = 500, 210e9, 3.14e-4, 1.0, 7800.0
    l = L / ndof
    ke = E * S / l * np.array([[1.0, -1.0], [-1.0, 1.0]])
    me = rho * S * l / 6.0 * np.array([[2.0, 1.0], [1.0, 2.0]])
    n, Kt, Mt = assemble(ndof - 1, ke, me, 1, 0)
    src = ("Siconos' impacting bar (siconos-tutorials examples/mechanics/FEM/"
           "ImpactingBar):\n500 nodes, linear elements of l = 1/500 m, E = "
           "210e9, S = 3.14e-4, rho = 7800\nwritten by share/fe/fe_models.py "
           "bar")
    write_mm(os.path.join(out, "bar_M.mtx"), n, *Mt, "mass matrix, " + src)
    write_mm(os.path.join(out, "bar_K.mtx"), n, *Kt, "stiffness matrix, " + src)
    c = math.sqrt(E / rho)
    with open(os.path.join(out, "impacting_bar.yaml"), "w") as f:
        f.write(f"""\
# Siconos' impacting bar (siconos-tutorials, examples/mechanics/FEM/
# ImpactingBar): a free elastic steel bar of 500 nodes (linear elements of
# 1/500 m, consistent mass; E = 210e9 Pa, S = 3.14e-4 m^2, rho = 7800 kg/m^3),
# every node at 5e-5 m above a rigid obstacle and falling at 0.1 m/s; the
# obstacle keeps node 1 at x >= 0 (a stop pushing downwards: direction -1)
# with Newton restitution r = 0.  Matrices written by share/fe/fe_models.py
# bar.  The bar is free: its stiffness is singular (a rigid-body mode at
# omega = 0), reduced here to its 40 lowest modes.  The wave speed is
# {c:.1f} m/s: the bar stays on the obstacle for about 2 L / c = {2 * 0.998 / c:.3g} s
# and leaves it at about 0.1 m/s (a continuous bar would at exactly 0.1).
name: impacting-bar
model:
  matrix_market: {{M: bar_M.mtx, K: bar_K.mtx}}
  modes: 40
stop: {{dof: 1, direction: -1, xs: 0.0, r: 0.0}}
initial: {{x: 5.0e-5, v: -0.1}}
run: {{t_end: 0.0015, rtol: 1.0e-9, atol: 1.0e-14}}
""")


# ---- clamped Euler-Bernoulli beam ------------------------------------------
# Hermite cubic elements (dofs w, w' at each node) with the consistent mass:
#   k_e = EI / l^3 [12 6l -12 6l; 6l 4l^2 -6l 2l^2; -12 -6l 12 -6l;
#                   6l 2l^2 -6l 4l^2]
#   m_e = rho A l / 420 [156 22l 54 -13l; 22l 4l^2 13l -3l^2;
#                        54 13l 156 -22l; -13l -3l^2 -22l 4l^2]
# clamped at x = 0 (node 0's w and w' removed).  Scaled as the paper's
# cantilever builder (vi_build_cantilever, scene `cantilever:`): L = 1,
# rho A = 1 (modes mass-normalised for unit rho A L, tip value 2) and EI =
# (omega1 / beta_1^2)^2 so that the first frequency is omega1 = 1:
# beta_j L = 1.8751041, 4.6940911, ... solve cos(b) cosh(b) = -1.
BETA1 = 1.8751040687119611


def beam(out, nel=100):
    L, rhoA, omega1 = 1.0, 1.0, 1.0
    EI = (omega1 / BETA1**2) ** 2 * rhoA * L**4
    l = L / nel
    ke = EI / l**3 * np.array([[12, 6 * l, -12, 6 * l],
                               [6 * l, 4 * l * l, -6 * l, 2 * l * l],
                               [-12, -6 * l, 12, -6 * l],
                               [6 * l, 2 * l * l, -6 * l, 4 * l * l]])
    me = rhoA * l / 420 * np.array([[156, 22 * l, 54, -13 * l],
                                    [22 * l, 4 * l * l, 13 * l, -3 * l * l],
                                    [54, 13 * l, 156, -22 * l],
                                    [-13 * l, -3 * l * l, -22 * l, 4 * l * l]])
    n, Kt, Mt = assemble(nel, ke, me, 2, 2)
    src = (f"a clamped Euler-Bernoulli beam, {nel} Hermite elements, L = 1, "
           "rho A = 1,\nEI = 1 / beta_1^4 (omega_1 = 1); dofs w, w' of nodes "
           f"1..{nel}\nwritten by share/fe/fe_models.py beam")
    write_mm(os.path.join(out, "beam_M.mtx"), n, *Mt, "mass matrix, " + src)
    write_mm(os.path.join(out, "beam_K.mtx"), n, *Kt, "stiffness matrix, " + src)
    # base acceleration A cos(Omega t): the inertial load -A M r, r = 1 on
    # every w dof and 0 on the rotations (the rigid translation)
    Mfull = np.zeros((n, n))
    Mfull[Mt[0], Mt[1]] = Mt[2]
    Mfull[Mt[1], Mt[0]] = Mt[2]
    r = np.zeros(n)
    r[0::2] = 1.0
    A = 0.01
    # row sums correctly rounded (math.fsum): a BLAS product's summation
    # order, and so its last bit, depends on the machine's vector width
    a = np.array([-A * math.fsum(Mfull[i] * r) for i in range(n)]) + 0.0
    avec = ", ".join("%.17g" % x for x in a)
    with open(os.path.join(out, "beam_fe.yaml"), "w") as f:
        f.write(f"""\
# The paper's beam (Wagg & Bishop 2000, section 4) as a finite-element
# model: a clamped Euler-Bernoulli beam of {nel} Hermite cubic elements with
# consistent mass (share/fe/fe_models.py beam), scaled as the `cantilever:`
# builder (L = 1, rho A = 1, first frequency 1), reduced to its 4 lowest
# modes with 5 % modal damping; the stop acts on the tip's deflection
# (dof {n - 1}: w of node {nel}) with clearance 0.05 and r = 0.75; a base
# acceleration 0.01 cos(0.85 t) enters as the inertial load -0.01 M r (r = 1
# on the deflections).  The same physics as cantilever4.yaml, whose modes are
# analytic: `vibroimpact energy` on both gives the same v_N and r_S
# (tests/io/test_fe_scene.c).
name: beam-fe
model:
  matrix_market: {{M: beam_M.mtx, K: beam_K.mtx}}
  modes: 4
  zeta: 0.05
forcing:
  omega: 0.85
  a: [{avec}]
stop: {{dof: {n - 1}, xs: 0.05, r: 0.75}}
run: {{periods: 300, rtol: 1.0e-10, atol: 1.0e-12, method: exact}}
output: {{impacts: true, samples_per_period: 128, ledger: true, modes: true}}
""")


# ---- a long fixed-free rod -------------------------------------------------
# N linear elements of h = L / N (E = rho = A = L = 1), fixed at x = 0,
# consistent mass.  Its exact discrete modes are sampled sines (MODEL.md
# section 10): u_i = sin(i theta_j), theta_j = (2 j - 1) pi / (2 N), with
#   omega_j^2 = (6 / h^2) (1 - cos theta_j) / (2 + cos theta_j)
# (1 - cos written 2 sin^2(theta / 2): no cancellation for small theta).
def rod_modes(N, k):
    h = 1.0 / N
    i = np.arange(1, N + 1)
    om, tip = [], []
    for j in range(1, k + 1):
        th = (2 * j - 1) * math.pi / (2 * N)
        s2 = 2 * math.sin(th / 2) ** 2
        om.append(math.sqrt(6.0 / h**2 * s2 / (3.0 - s2)))
        u = np.sin(i * th)
        # u^T M u with M = (h / 6) tridiag(1, 4, 1), M_NN = 2 h / 6
        d = 4.0 * np.dot(u, u) - 2.0 * u[-1] ** 2
        off = 2.0 * np.dot(u[:-1], u[1:])
        norm = math.sqrt(h / 6.0 * (d + off))
        tip.append(u[-1] / norm)
    return np.array(om), np.array(tip)


def rod(out, N=100000, modes=20):
    h = 1.0 / N
    ke = 1.0 / h * np.array([[1.0, -1.0], [-1.0, 1.0]])
    me = h / 6.0 * np.array([[2.0, 1.0], [1.0, 2.0]])
    # assembled directly (N is large): node i = 1..N is dof i - 1
    d = np.arange(N)
    Kr = np.concatenate([d, d[1:]]); Kc = np.concatenate([d, d[:-1]])
    Kv = np.concatenate([np.full(N, 2.0 / h), np.full(N - 1, -1.0 / h)])
    Kv[N - 1] = 1.0 / h
    Mv = np.concatenate([np.full(N, 4.0 * h / 6.0), np.full(N - 1, h / 6.0)])
    Mv[N - 1] = 2.0 * h / 6.0
    del ke, me
    src = (f"a fixed-free rod of {N} linear elements, E = rho = A = L = 1, "
           "consistent mass\nwritten by share/fe/fe_models.py rod")
    write_mm(os.path.join(out, "rod_M.mtx"), N, Kr, Kc, Mv, "mass matrix, " + src)
    write_mm(os.path.join(out, "rod_K.mtx"), N, Kr, Kc, Kv, "stiffness matrix, " + src)
    om, tip = rod_modes(N, modes)
    # the tip pushed by F cos(Omega t) against a stop at the tip; the
    # largest-magnitude entry of each mode positive (vi_sparse.h): the
    # sampled sine's largest entry is near the tip, of the sign of u_N
    Omega, F, zeta, xs, r = 0.85 * om[0], 0.1, 0.02, 0.02, 0.8
    common = f"""\
forcing: {{omega: {Omega!r}, on: [{N}], amplitude: {F!r}}}
stop: {{dof: {N}, xs: {xs!r}, r: {r!r}}}
run: {{periods: 20, rtol: 1.0e-11, atol: 1.0e-14, method: exact}}
"""
    with open(os.path.join(out, "rod.yaml"), "w") as f:
        f.write(f"""\
# A fixed-free rod of {N} linear elements (E = rho = A = L = 1; matrices by
# share/fe/fe_models.py rod) driven at its tip against a stop at the tip,
# reduced to its {modes} lowest modes (shift-invert Lanczos); rod_modal.yaml is
# the same model written with the closed-form modes.
name: rod-fe
model:
  matrix_market: {{M: rod_M.mtx, K: rod_K.mtx}}
  modes: {modes}
  zeta: {zeta!r}
""" + common.replace(f"on: [{N}]", f"on: [{N}]"))
    k = modes
    Kd = "\n".join("    - [" + ", ".join("%.17g" % (om[a] ** 2 if a == b else 0.0)
                                         for b in range(k)) + "]" for a in range(k))
    Cd = "\n".join("    - [" + ", ".join("%.17g" % (2 * zeta * om[a] if a == b else 0.0)
                                         for b in range(k)) + "]" for a in range(k))
    w = ", ".join("%.17g" % t for t in tip)
    a = ", ".join("%.17g" % (F * t) for t in tip)
    with open(os.path.join(out, "rod_modal.yaml"), "w") as f:
        f.write(f"""\
# rod.yaml's model in modal coordinates from the closed-form discrete modes
# of the fixed-free linear-element rod (u_i = sin(i theta_j), theta_j =
# (2j - 1) pi / (2 N), mass-normalised; share/fe/fe_models.py rod): M = I,
# K = diag(omega_j^2), C = diag(2 zeta omega_j), the stop and the load on
# the tip's row of Psi.
name: rod-modal
model:
  K:
{Kd}
  C:
{Cd}
forcing: {{omega: {Omega!r}, a: [{a}]}}
stop: {{w: [{w}], xs: {xs!r}, r: {r!r}}}
run: {{periods: 20, rtol: 1.0e-11, atol: 1.0e-14, method: exact}}
""")


def main(argv):
    if len(argv) < 3 or argv[1] not in ("bar", "beam", "rod"):
        sys.stderr.write(__doc__)
        return 2
    out = argv[2]
    os.makedirs(out, exist_ok=True)
    if argv[1] == "bar":
        bar(out)
    elif argv[1] == "beam":
        beam(out)
    else:
        rod(out, int(argv[3]) if len(argv) > 3 else 100000)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

#!/usr/bin/python3
"""Convert published finite-element K/M(/C) pairs into Matrix Market files.

Reads the original files straight out of local git mirrors of the public
repositories named in SOURCES.md (at the commits recorded there) and writes
tests/data/fe/NAME_K.mtx, NAME_M.mtx and, where the model has discrete
dashpots, NAME_C.mtx: 'coordinate real symmetric', lower triangle, values as
'%.17g' so every double round-trips exactly.  Files over 200 kB are xz'd.

Usage: convert.py [MIRROR_ROOT]   (default /work/.mirror)
Needs python3-scipy (Debian); only reading / writing, no numerics that
change values except where SOURCES.md says so (sandwich beam K = Ke + G0 Kv,
real or imaginary parts of complex NLEVP data, the foundation's sign).
"""
import io
import lzma
import os
import subprocess
import sys

import numpy as np
import scipy.io as sio
import scipy.sparse as sp

HERE = os.path.dirname(os.path.abspath(__file__))
MIRRORS = sys.argv[1] if len(sys.argv) > 1 else "/work/.mirror"

SUITESPARSE = ("DrTimothyAldenDavis+SuiteSparse", "038d6635096409538260f71986a8ab4a42e0514e")
PYSS = ("ibara1454+pyss", "69b47d89f88f04876bdabd504d202a1ced7bb5e4")
NLEVP = ("ftisseur+nlevp", "1284e6738ebacd80e028d53aa94757f1d41ae983")
EXUDYN = ("jgerstmayr+EXUDYN", "e44aca1b4fe3e5f4d820ff407fb3fd30b6581c1c")
EXUDYN_DATA = "main/pythonDev/TestModels/testData/"

XZ_ABOVE = 200 * 1024


def blob(repo, path):
    """Bytes of PATH at the pinned commit of REPO's mirror."""
    name, commit = repo
    gitdir = os.path.join(MIRRORS, name, "repo")
    return subprocess.run(["git", "-C", gitdir, "show", f"{commit}:{path}"],
                          check=True, capture_output=True).stdout


def read_rsa(data):
    """Rutherford-Boeing 'rsa' (real symmetric assembled, lower triangle by
    columns).  Fixed-width fields; the widths come from the format line."""
    lines = data.decode("ascii").splitlines()
    kind, nrow, ncol, nnz = lines[2].split()[:4]
    if kind.lower() != "rsa":
        raise ValueError(f"not an rsa file: {kind}")
    nrow, ncol, nnz = int(nrow), int(ncol), int(nnz)
    fmts = lines[3].split()

    def width(fmt):  # '(16I5)' -> 5, '(4E20.12)' -> 20
        body = fmt.strip("()").upper()
        for letter in "IEDF":
            if letter in body:
                return int(body.split(letter)[1].split(".")[0])
        raise ValueError(f"unknown format {fmt}")

    def fields(start, count, w):
        out, li = [], start
        while len(out) < count:
            line = lines[li]
            out.extend(line[k:k + w] for k in range(0, len(line), w)
                       if line[k:k + w].strip())
            li += 1
        return out[:count], li

    ptr, li = fields(4, ncol + 1, width(fmts[0]))
    ind, li = fields(li, nnz, width(fmts[1]))
    val, _ = fields(li, nnz, width(fmts[2]))
    ptr = np.array([int(x) for x in ptr]) - 1
    ind = np.array([int(x) for x in ind]) - 1
    val = np.array([float(x.replace("D", "E").replace("d", "e")) for x in val])
    cols = np.repeat(np.arange(ncol), np.diff(ptr))
    low = sp.coo_matrix((val, (ind, cols)), shape=(nrow, ncol))
    return low + sp.tril(low, -1).T


def read_abaqus_coordinate(data):
    """Abaqus *MATRIX OUTPUT, FORMAT=COORDINATE: 'row col value' per line,
    1-based global dof numbers, both triangles written."""
    rows, cols, vals = [], [], []
    for lineno, line in enumerate(data.decode("ascii").splitlines(), 1):
        parts = line.replace(",", " ").split()
        if not parts:
            continue
        if len(parts) != 3:
            raise ValueError(f"line {lineno}: expected 'row col value': {line!r}")
        rows.append(int(parts[0]) - 1)
        cols.append(int(parts[1]) - 1)
        vals.append(float(parts[2]))
    n = max(max(rows), max(cols)) + 1
    A = sp.coo_matrix((vals, (rows, cols)), shape=(n, n)).tocsr()
    if A.nnz != len(vals):
        raise ValueError("duplicate entries")
    return A


def read_mtx(data):
    return sio.mmread(io.BytesIO(data))


def loadmat(data):
    return sio.loadmat(io.BytesIO(data))


def check_sym(name, A, rtol):
    A = sp.csr_matrix(A)
    scale = abs(A).max()
    asym = abs(A - A.T).max() / scale if scale > 0 else 0.0
    if asym > rtol:
        raise ValueError(f"{name}: not symmetric, max|A-A'|/max|A| = {asym:.3g}")
    return asym


def write_mtx(path, A, comments):
    """Lower triangle of A (which has been checked symmetric), 1-based,
    sorted by column then row, explicit zeros dropped."""
    L = sp.tril(sp.csc_matrix(A), format="csc")
    L.eliminate_zeros()
    L.sort_indices()
    L = L.tocoo()
    order = np.lexsort((L.row, L.col))
    out = io.StringIO()
    out.write("%%MatrixMarket matrix coordinate real symmetric\n")
    for c in comments:
        out.write(f"% {c}\n")
    out.write(f"{A.shape[0]} {A.shape[1]} {L.nnz}\n")
    for k in order:
        out.write(f"{L.row[k] + 1} {L.col[k] + 1} {L.data[k]:.17g}\n")
    text = out.getvalue().encode("ascii")
    for old in (path, path + ".xz"):
        if os.path.exists(old):
            os.remove(old)
    if len(text) > XZ_ABOVE:
        with lzma.open(path + ".xz", "wb", preset=9 | lzma.PRESET_EXTREME) as f:
            f.write(text)
        return path + ".xz"
    with open(path, "wb") as f:
        f.write(text)
    return path


def emit(name, mats, origin):
    """mats: dict 'K'/'M'/'C' -> (matrix, symmetry tolerance, note)."""
    for role, (A, tol, note) in mats.items():
        A = sp.csc_matrix(A, dtype=np.float64)
        asym = check_sym(f"{name}_{role}", A, tol)
        comments = [f"vibroimpact tests/data/fe: {name} {role}",
                    f"source: {origin}",
                    note,
                    f"symmetry of the original: max|A-A'|/max|A| = {asym:.3g};"
                    " lower triangle kept"]
        out = write_mtx(os.path.join(HERE, f"{name}_{role}.mtx"), A, comments)
        print(f"{os.path.basename(out)}: n={A.shape[0]} nnz={A.nnz}"
              f" bytes={os.path.getsize(out)}")


def hb_problem_A(data):
    return loadmat(data)["Problem"][0, 0]["A"]


def main():
    ss = f"github.com/DrTimothyAldenDavis/SuiteSparse@{SUITESPARSE[1][:12]}"
    emit("hb_bcsstk01", {
        "K": (read_rsa(blob(SUITESPARSE, "CHOLMOD/Demo/Matrix/bcsstk01.rsa")), 0,
              "HB BCSSTK01 stiffness, from CHOLMOD/Demo/Matrix/bcsstk01.rsa"),
        "M": (hb_problem_A(blob(SUITESPARSE,
                                "MATLAB_Tools/spqr_rank/SJget/mat/HB/bcsstm01.mat")), 0,
              "HB BCSSTM01 lumped mass, from MATLAB_Tools/spqr_rank/SJget/mat/HB/bcsstm01.mat"),
    }, ss)

    py = f"github.com/ibara1454/pyss@{PYSS[1][:12]}"
    emit("hb_bcsstk11", {
        "K": (read_mtx(blob(PYSS, "matrix/bcsstk11.mtx")), 0,
              "HB BCSSTK11 stiffness (ten-story frame / ore car), matrix/bcsstk11.mtx"),
        "M": (read_mtx(blob(PYSS, "matrix/bcsstm11.mtx")), 0,
              "HB BCSSTM11 lumped mass, matrix/bcsstm11.mtx"),
    }, py)

    nl = f"github.com/ftisseur/nlevp@{NLEVP[1][:12]}"
    d = loadmat(blob(NLEVP, "private/shaft.mat"))
    emit("nlevp_shaft", {
        "K": (d["K"], 0, "NLEVP shaft K, private/shaft.mat"),
        "M": (d["M"], 0, "NLEVP shaft M (lumped; rotations massless), private/shaft.mat"),
        "C": (d["C"], 0, "NLEVP shaft C (one discrete dashpot), private/shaft.mat"),
    }, nl)

    # Static stiffness of the viscoelastic sandwich: K = Ke + g(0) Kv with
    # g(0) = G0 = 3.504e5 Pa (NLEVP sandwich_beam.m); summed in double.
    g0 = 3.504e5
    for n in (168, 840, 3360):
        d = loadmat(blob(NLEVP, f"private/sandwich_beam_{n}.mat"))
        emit(f"nlevp_sandwich_beam_{n}", {
            "K": (d["Ke"] + g0 * d["Kv"], 1e-15,
                  f"NLEVP sandwich_beam K = Ke + G0*Kv, G0 = 3.504e5 (static modulus),"
                  f" private/sandwich_beam_{n}.mat"),
            "M": (d["M"], 1e-15, f"NLEVP sandwich_beam M, private/sandwich_beam_{n}.mat"),
        }, nl)

    # Concrete: K_c1 carries an imaginary part ~1e-9 of its real part; the
    # dashpots are stored as i*Cv.  Keep Re(K), Im(C).
    d = loadmat(blob(NLEVP, "private/concrete.mat"))
    emit("nlevp_concrete", {
        "K": (d["K_c1"].real, 0, "NLEVP concrete Re(K_c1), private/concrete.mat"),
        "M": (d["M_c1"], 0, "NLEVP concrete M_c1 (diagonal, 997 massless dofs)"),
        "C": (d["C_c1"].imag, 0, "NLEVP concrete Im(C_c1) (C_c1 = i*Cv, 36 dashpots)"),
    }, nl)

    # Foundation: NLEVP stores the frequency-domain equation negated,
    # K = -Ks (1 + i eta_e) (every diagonal entry negative), D = -i Cv, with
    # K + w D + w^2 M = 0: stiffness -Re(K), dashpots -Im(D) (all > 0).
    d = loadmat(blob(NLEVP, "private/foundation.mat"))
    emit("nlevp_foundation", {
        "K": (-d["K"].real, 0, "NLEVP foundation -Re(K): NLEVP's K is minus the stiffness"
                               " (all diagonal entries < 0); Im(K) is hysteretic damping"),
        "M": (d["M"], 0, "NLEVP foundation M (diagonal), private/foundation.mat"),
        "C": (-d["D"].imag, 0, "NLEVP foundation -Im(D) (D = -i*Cv, negated like K;"
                               " 211 soil dashpots)"),
    }, nl)

    ex = f"github.com/jgerstmayr/EXUDYN@{EXUDYN[1][:12]}"
    for elem in ("C3D8", "C3D4", "C3D10", "C3D20R"):
        base = f"{EXUDYN_DATA}abaqus/block{elem}"
        emit(f"abaqus_block{elem}", {
            "K": (read_abaqus_coordinate(blob(EXUDYN, base + "_STIF1.mtx")), 0,
                  f"Abaqus *MATRIX GENERATE stiffness of a free steel block, {elem} elements,"
                  f" {base}_STIF1.mtx"),
            "M": (read_abaqus_coordinate(blob(EXUDYN, base + "_MASS1.mtx")), 0,
                  f"Abaqus *MATRIX GENERATE mass, {base}_MASS1.mtx"),
        }, ex)
    base = f"{EXUDYN_DATA}rotorDisc"
    emit("abaqus_rotorDisc", {
        "K": (read_abaqus_coordinate(blob(EXUDYN, base + "TestSTIF1.mtx")), 0,
              f"Abaqus *MATRIX GENERATE stiffness of a free rotor with disc, {base}TestSTIF1.mtx"),
        "M": (read_abaqus_coordinate(blob(EXUDYN, base + "TestMASS1.mtx")), 0,
              f"Abaqus *MATRIX GENERATE lumped mass, {base}TestMASS1.mtx"),
    }, ex)
    base = f"{EXUDYN_DATA}rotorAnsys"
    emit("ansys_rotor", {
        "K": (read_mtx(blob(EXUDYN, base + "StiffnessMatrixSparse.txt")), 0,
              f"ANSYS stiffness of a free rotor (ANSYS's own dof order),"
              f" {base}StiffnessMatrixSparse.txt"),
        "M": (read_mtx(blob(EXUDYN, base + "MassMatrixSparse.txt")), 0,
              f"ANSYS lumped mass, {base}MassMatrixSparse.txt"),
    }, ex)

    d = loadmat(blob(NLEVP, "private/disk_brake100.mat"))
    emit("nlevp_disk_brake100", {
        "K": (d["K1"], 0, "NLEVP disk_brake100 K1 (symmetric stiffness; the"
                          " circulatory KR is left out)"),
        "M": (d["M"], 0, "NLEVP disk_brake100 M, private/disk_brake100.mat"),
        "C": (d["D1"], 0, "NLEVP disk_brake100 D1 (symmetric damping; DR, DG left out)"),
    }, nl)


if __name__ == "__main__":
    main()

"""Hostile input never crashes the interpreter: the program's fault cases
(tests/faults/test_faults.c: size and nesting limits, memory limits, values
out of range) and the Python-side ones (NaN, wrong shapes, bad keys, bad
outputs) each raise vibroimpact.Error (or MemoryError / ValueError from
numpy) with a message.  The battery runs in a child interpreter so that a
crash fails the test with the case that caused it instead of killing
pytest."""
import os
import subprocess
import sys
import textwrap

from conftest import SCENES

BATTERY = textwrap.dedent(r'''
    import math, os, sys, tempfile
    import numpy as np
    import scipy.sparse as sp
    import vibroimpact as vi
    SCENES = sys.argv[1]
    tmp = tempfile.mkdtemp()
    CHAIN2 = "model:\n  chain: {n: 2, m: 1, k: 1, c: 0.1}\nstop: {mass: 2, xs: 0.1, r: 0.7}\n"
    done = 0

    def expect(name, f, key=None, exc=vi.Error):
        global done
        print(name, flush=True)
        try:
            f()
        except exc as e:
            if key is not None and isinstance(e, vi.Error):
                assert key in str(e) or key == e.key, (name, key, str(e))
            done += 1
            return
        raise AssertionError("%s: no error raised" % name)

    def scene_text(text, name="hostile.yaml"):
        p = os.path.join(tmp, name)
        with open(p, "w") as f:
            f.write(text)
        return vi.load_scene(p)

    # ---- the program's fault cases ----
    expect("/dev/zero", lambda: vi.load_scene("/dev/zero"), "larger than 16777216 bytes")
    expect("small limit", lambda: vi.load_scene(os.path.join(SCENES, "fig2.yaml"),
                                                max_bytes=100), "larger than 100 bytes")
    expect("nesting", lambda: scene_text("a: " + "[" * 100000 + "]" * 100000 + "\n"),
           "nesting deeper than 32 levels")
    expect("deep flow maps",
           lambda: scene_text("a: " + "{a: " * 20000 + "1" + "}" * 20000), "nesting deeper")
    big = ("model:\n  chain: {n: 20000, m: 1, k: 1, c: 0.1}\nstop: {mass: 1, xs: 0.1, r: 0.7}\n"
           "forcing: {omega: 0.9, on: [1], amplitude: 0.5}\noutput: {ledger: true}\n")
    # an allowance of 2 GB, so that a machine with more memory refuses them too
    expect("20000-mass ledger (memory)", lambda: scene_text(big).run(max_memory=2e9),
           "model.chain.n")
    huge = ("model:\n  chain: {n: 100000, m: 1, k: 1, c: 0.1}\nstop: {mass: 1, xs: 0.1, r: 0.7}\n"
            "forcing: {omega: 0.9, on: [1], amplitude: 0.5}\nrun: {method: exact}\n")
    expect("100000-mass exact (memory)", lambda: scene_text(huge).run(max_memory=2e9))
    expect("Fig. 2 in 1 kB", lambda: vi.load_scene(os.path.join(SCENES, "fig2.yaml")).run(
        max_memory=1000), "allowed")
    # a Matrix Market header claiming 3e8 dofs: refused from the header, by
    # the loader and by an edit, before the scene's 56 n bytes (16.8 GB)
    # are allocated (they were: 17 s and 4.6 GB before the refusal)
    with open(os.path.join(tmp, "K.mtx"), "w") as f:
        f.write("%%MatrixMarket matrix coordinate real symmetric\n"
                "300000000 300000000 1\n1 1 1.0\n")
    with open(os.path.join(tmp, "M.mtx"), "w") as f:
        f.write("%%MatrixMarket matrix coordinate real symmetric\n"
                "300000000 300000000 1\n1 1 1.0\n")
    with open(os.path.join(tmp, "big.yaml"), "w") as f:
        f.write("model:\n  matrix_market: {M: M.mtx, K: K.mtx}\n  modes: 2\n"
                "forcing: {omega: 0.85}\nstop: {dof: 1, xs: 0.05, r: 0.75}\n")
    expect("3e8-dof header (load)", lambda: vi.load_scene(os.path.join(tmp, "big.yaml"),
                                                          max_memory=100e6),
           "vectors of 300000000 dofs alone would need")
    expect("1e5-mass chain in 1 MB (edit)",
           lambda: vi.load_scene(os.path.join(SCENES, "fig2.yaml"))
           .with_settings({"model.chain.n": 100000}, max_memory=1e6),
           "vectors of 100000 dofs alone would need 5.34 MB")
    ranges = [
        ("forcing: {omega: 0.9, a: [0.5, 0]}\nrun: {rtol: 10}\n", "run.rtol"),
        ("forcing: {omega: 0.9, a: [0.5, 0]}\nrun: {rtol: 1}\n", "run.rtol"),
        ("forcing: {omega: 0.9, a: [0.5, 0]}\nrun: {atol: 1e10}\n", "run.atol"),
        ("forcing: {omega: 1e-300, a: [0.5, 0]}\n", "forcing.omega"),
        ("forcing: {omega: 1e300, a: [0.5, 0]}\n", "forcing.omega"),
        ("forcing: {omega: -0.9, a: [0.5, 0]}\n", "forcing.omega"),
        ("forcing: {omega: 0.9, a: [1e300, 0]}\n", "forcing.a[1]"),
        ("forcing: {omega: 0.9, a: [0.5, 0]}\nrun: {periods: 1e-300}\n", "run.periods"),
        ("forcing: {omega: 0.9, a: [0.5, 0]}\nrun: {periods: 1e300}\n", "run.periods"),
        ("forcing: {omega: 0.9, a: [0.5, 0]}\ninitial: {v: [1e30, 0]}\n", "initial.v"),
        ("forcing: {omega: 0.9, a: [0.5, 0]}\ninitial: {x: [-1e300, 0]}\n", "initial.x[1]"),
        ("forcing: {omega: !!str 0.9, a: [0.5, 0]}\n", "forcing.omega"),
        ("forcing: {omega: '0.9', a: [0.5, 0]}\n", "forcing.omega"),
        ("forcing: {omega: 0.9, a: [0.5, 0]}\nname: [1, 2]\n", "name"),
        ("forcing: {omega: 0.9, a: [0.5, 0]}\n---\nname: second\n", "second YAML document"),
        ("forcing: {omega: 0.9, a: [0.5, 0]}\noutput: {ledger: 'true'}\n", "output.ledger"),
        ("forcing: {omega: 0.9, a: [0.5, 0]}\nrun: {periods: 3, atol: 1e80}\n", "run.atol"),
    ]
    for text, key in ranges:
        expect("range " + key, lambda: scene_text(CHAIN2 + text).run(), key)
    models = [
        ("model:\n  chain: {n: 2, m: [1, 1e-30], k: 1, c: 0.1}\n", "model.chain.m"),
        ("model:\n  chain: {n: 2, m: 1, k: [1e30, 1], c: 0.1}\n", "model.chain.k"),
        ("model:\n  chain: {n: 2, m: 1, k: 1, c: 1e300}\n", "model.chain.c"),
        ("model:\n  chain: {n: 2, m: 1, k: 1, c: 1e20}\n", "damping ratio"),
    ]
    for text, key in models:
        expect("model " + key, lambda: scene_text(
            text + "stop: {mass: 2, xs: 0.1, r: 0.7}\nforcing: {omega: 0.9, a: [0.5, 0]}\n").run(),
            key)
    expect("no such file", lambda: vi.load_scene(os.path.join(tmp, "none.yaml")))
    expect("a directory", lambda: vi.load_scene(tmp))
    expect("binary junk", lambda: scene_text("\x00\x01\xff\xfe" * 100))
    expect("empty", lambda: scene_text(""))
    expect("syntax", lambda: scene_text("model: {chain: [\n"))
    expect("unknown key", lambda: scene_text(CHAIN2 + "bogus: 1\n"), "bogus")
    expect("bad --set key", lambda: vi.load_scene(os.path.join(SCENES, "fig2.yaml")).run(
        **{"forcing.a[9]": 1}))
    expect("bad --set value", lambda: vi.load_scene(os.path.join(SCENES, "fig2.yaml")).run(
        **{"stop.r": "[1, {"}))
    fig2 = vi.load_scene(os.path.join(SCENES, "fig2.yaml")).run(periods=2)
    for target in ("/proc/vi_out.h5", tmp, "/dev/null", os.path.join(tmp, "no", "dir.h5")):
        expect("output " + target, lambda: fig2.to_hdf5(target))
    # ---- Python-side input ----
    K = np.array([[2.0, -1.0], [-1.0, 1.0]])
    S = [{"w": [0, 1], "xs": 0.1, "r": 0.7}]
    F = {"omega": 0.9, "a": [0.5, 0]}
    expect("NaN in K", lambda: vi.Model(K=[[np.nan, 0], [0, 1]], stops=S))
    expect("inf in M", lambda: vi.Model(M=np.diag([np.inf, 1]), K=K, stops=S))
    expect("K not square", lambda: vi.Model(K=np.ones((2, 3)), stops=S))
    expect("K empty", lambda: vi.Model(K=np.zeros((0, 0)), stops=S))
    expect("K 3-d", lambda: vi.Model(K=np.ones((2, 2, 2)), stops=S))
    expect("strings", lambda: vi.Model(K=[["a", "b"], ["c", "d"]], stops=S),
           exc=(vi.Error, ValueError))
    expect("w wrong length", lambda: vi.Model(K=K, stops=[{"w": [1, 2, 3], "xs": 0, "r": 0.5}]))
    expect("stop key typo", lambda: vi.Model(K=K, stops=[{"w": [0, 1], "x_s": 0, "r": 0.5}]))
    expect("no stops", lambda: vi.Model(K=K))
    expect("forcing NaN", lambda: vi.Model(K=K, stops=S, forcing={"omega": np.nan, "a": [1, 0]}))
    expect("forcing omega 0", lambda: vi.Model(K=K, stops=S, forcing={"omega": 0, "a": [1, 0]}))
    expect("chain n = 0", lambda: vi.Model.chain(0, stops=S))
    expect("chain n < 0", lambda: vi.Model.chain(-5, stops=S))
    expect("chain huge dense", lambda: vi.Model.chain(10 ** 9, stops=S), "band=True")
    expect("negative mass", lambda: vi.Model.chain(2, m=-1, stops=S, forcing=F))
    m = vi.Model.chain(2, m=1, k=1, c=0.1, stops=S, forcing=F)
    expect("t_end NaN", lambda: m.simulate(float("nan")))
    expect("t_end inf", lambda: m.simulate(float("inf")))
    expect("t_end before t0", lambda: m.simulate(-1.0))
    expect("rtol 0", lambda: m.simulate(10, rtol=0))
    expect("atol NaN", lambda: m.simulate(10, atol=float("nan")))
    expect("x0 NaN", lambda: m.simulate(10, x0=[np.nan, 0]))
    expect("x0 wrong length", lambda: m.simulate(10, x0=[0, 0, 0]))
    expect("v0 huge", lambda: m.simulate(10, v0=[1e300, 0]))
    expect("sample dt tiny", lambda: m.simulate(10, sample_dt=1e-300))
    expect("method", lambda: m.simulate(10, method="euler"))
    expect("method number", lambda: m.simulate(10, method=99))
    expect("impact resolution", lambda: m.simulate(10, impact_resolution=2.0))
    expect("spring index", lambda: m.simulate(10, springs=[{"type": "cubic", "i": 9, "k3": 1}]))
    expect("param unknown", lambda: m.set_param("bogus", 1.0), "bogus")
    expect("param index", lambda: m.set_param("forcing.a[99]", 1.0))
    expect("param NaN", lambda: m.set_param("stop.xs", float("nan")))
    expect("param r", lambda: m.set_param("stop.r", -0.1))
    expect("sweep key", lambda: vi.sweep(m, "bogus", [1.0, 2.0]))
    expect("sweep NaN", lambda: vi.sweep(m, "forcing.omega", [np.nan]))
    expect("sweep record", lambda: vi.sweep(m, "forcing.omega", [0.9], record=1))
    expect("basins key", lambda: vi.basins(m, "initial.x[7]", [0], "initial.v[1]", [0]))
    expect("orbits n", lambda: vi.orbits(m, 0, 1))
    expect("continuation key", lambda: vi.continuation(m, "bogus", 1.0, 3))
    expect("identify short", lambda: vi.identify(m, np.arange(5.0), np.zeros(5),
                                                 {"stop.r": (0.1, 0.9)}))
    expect("identify NaN", lambda: vi.identify(m, np.arange(100.0), np.full(100, np.nan),
                                               {"stop.r": (0.1, 0.9)}))
    expect("identify key", lambda: vi.identify(m, np.arange(100.0), np.zeros(100),
                                               {"bogus": (0.1, 0.9)}))
    expect("truncation of a physical model", lambda: vi.truncation(
        vi.Model(M=np.diag([1.0, 2.0]), K=K, stops=S)))
    Ms, Ks = sp.identity(3, format="csc"), sp.csc_matrix(np.diag([1.0, 2.0, 3.0]))
    Sf = [{"dof": 0, "xs": 0.1, "r": 0.5}]
    expect("sparse NaN", lambda: vi.Model.from_sparse(
        sp.csc_matrix(np.diag([1, np.nan, 1])), Ks, stops=Sf))
    expect("sparse sizes", lambda: vi.Model.from_sparse(sp.identity(2), Ks, stops=Sf))
    expect("sparse not symmetric", lambda: vi.Model.from_sparse(
        Ms, sp.csc_matrix(np.triu(np.ones((3, 3))) + np.eye(3)), stops=Sf))
    expect("sparse too many modes", lambda: vi.Model.from_sparse(Ms, Ks, modes=9, stops=Sf))
    expect("sparse dof", lambda: vi.Model.from_sparse(
        Ms, Ks, stops=[{"dof": -1, "xs": 0, "r": 0.5}]))
    expect("sparse direction", lambda: vi.Model.from_sparse(
        Ms, Ks, stops=[{"dof": 0, "direction": 2, "xs": 0, "r": 0.5}]))
    expect("sparse zeta", lambda: vi.Model.from_sparse(Ms, Ks, zeta=[-1.0], stops=Sf))
    print("ALL %d CASES RAISED" % done)
''')


def test_hostile_inputs_raise_errors():
    p = subprocess.run([sys.executable, "-c", BATTERY, SCENES], capture_output=True, text=True,
                       timeout=600, cwd=os.path.dirname(__file__))
    tail = "\n".join(p.stdout.splitlines()[-5:])
    assert p.returncode == 0, "the interpreter ended with %d after:\n%s\n%s" % (
        p.returncode, tail, p.stderr[-3000:])
    assert "ALL" in p.stdout and "CASES RAISED" in p.stdout
    print(p.stdout.splitlines()[-1])


def test_address_space_limit_is_the_budget():
    """Under `ulimit -v` (RLIMIT_AS, 2 GiB) a dense 3500-mass chain (2.9 GB)
    is refused before allocating, the budget being what the limit leaves
    (vi_scene_memory_available), not the machine's free memory, which may
    well hold it.  In a child interpreter: the limit is the process's."""
    code = textwrap.dedent('''
        import resource
        resource.setrlimit(resource.RLIMIT_AS, (2 << 30, 2 << 30))
        import vibroimpact as vi
        left = vi._lib.vi_scene_memory_available()
        assert 0 < left < 2 << 30, left
        try:
            vi.Model.chain(3500, m=1, k=1, c=0.1, stops=[{"mass": 1, "xs": 0.1, "r": 0.7}],
                           forcing={"omega": 0.9})
        except vi.Error as e:
            assert "are available" in str(e), str(e)
            print("REFUSED", e)
    ''')
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert p.returncode == 0 and "REFUSED" in p.stdout, (p.returncode, p.stdout, p.stderr[-2000:])

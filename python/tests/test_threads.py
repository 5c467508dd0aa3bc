"""Behaviour a Python user expects: the GIL released during runs, Ctrl-C
cancelling a run through the library's cancel hook."""
import subprocess
import sys
import textwrap
import threading
import time

import numpy as np

import vibroimpact as vi


def _long_model():
    # a 30-mass chain on Adams: about a second of integration per 2000 periods
    return vi.Model.chain(30, m=1.0, k=1.0, c=0.05,
                          stops=[{"dof": 29, "xs": 0.05, "r": 0.8}],
                          forcing={"omega": 0.7, "a": np.r_[1.0, np.zeros(29)]})


def test_gil_released_during_run():
    """While a run is in a worker thread the main thread keeps running
    Python: the longest pause between its iterations is a small part of
    the run (with the GIL held it would be the whole run)."""
    m = _long_model()
    done = threading.Event()
    box = {}

    def work():
        t = time.perf_counter()
        box["res"] = m.simulate(t_end=12000.0, method="adams")
        box["wall"] = time.perf_counter() - t
        done.set()

    th = threading.Thread(target=work)
    stamps = []
    th.start()
    while not done.is_set():
        stamps.append(time.perf_counter())
        time.sleep(0.001)
    th.join()
    gap = np.max(np.diff(stamps)) if len(stamps) > 1 else box["wall"]
    print("run %.3f s, longest pause of the main thread %.4f s" % (box["wall"], gap))
    assert box["wall"] > 0.1, "the run must be long enough to tell"
    assert gap < 0.25 * box["wall"]
    assert box["res"].stats["impacts"] > 0


def test_threads_share_a_model():
    """Two threads simulate one model at once: each result equals the
    serial one (a set-up model is shared read-only)."""
    m = vi.Model.chain(2, m=1, k=1, c=0.1, stops=[{"w": [0, 1], "xs": 0.1, "r": 0.7}],
                       forcing={"omega": 0.9, "a": [0.5, 0]})
    ref = m.simulate(periods=200, method="exact").impacts["t"]
    out = [None] * 4

    def work(i):
        out[i] = m.simulate(periods=200, method="exact").impacts["t"]

    ths = [threading.Thread(target=work, args=(i,)) for i in range(4)]
    for th in ths:
        th.start()
    for th in ths:
        th.join()
    for o in out:
        np.testing.assert_array_equal(o, ref)


SCRIPT = textwrap.dedent("""
    import os, signal, sys, threading, time
    import numpy as np
    import vibroimpact as vi
    m = vi.Model.chain(30, m=1.0, k=1.0, c=0.05,
                       stops=[{"dof": 29, "xs": 0.05, "r": 0.8}],
                       forcing={"omega": 0.7, "a": np.r_[1.0, np.zeros(29)]})
    threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
    t = time.perf_counter()
    try:
        m.simulate(t_end=1e7, method="adams")
        print("finished")
    except KeyboardInterrupt:
        print("interrupted after %.2f s" % (time.perf_counter() - t))
    # a study: the sweep's cancel hook
    threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
    t = time.perf_counter()
    try:
        vi.sweep(m, "forcing.omega", [0.7, 0.8], transient=10**7, method="adams")
        print("finished")
    except KeyboardInterrupt:
        print("sweep interrupted after %.2f s" % (time.perf_counter() - t))
    # the interpreter's own handler is back: a later Ctrl-C is Python's
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    try:
        os.kill(os.getpid(), signal.SIGINT)
        time.sleep(1)
        print("no KeyboardInterrupt")
    except KeyboardInterrupt:
        print("second interrupt")
    """)


def test_ctrl_c_raises_keyboard_interrupt():
    """SIGINT during a run (which would take hours) cancels it through the
    library's cancel hook and raises KeyboardInterrupt within moments."""
    p = subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True,
                       text=True, timeout=120)
    print(p.stdout, p.stderr)
    assert p.returncode == 0
    lines = p.stdout.split("\n")
    assert lines[0].startswith("interrupted after")
    assert float(lines[0].split()[2]) < 10
    assert lines[1].startswith("sweep interrupted after")
    assert float(lines[1].split()[3]) < 10
    assert lines[2] == "second interrupt"

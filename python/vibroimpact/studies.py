"""The library's studies as Python functions returning numpy arrays and
plain dicts of them: bifurcation sweeps, basins of attraction, the census
of periodic orbits, continuation, the energy balance of WB 11-13, modal
truncation and identification from recorded data.

Each is a thin loop over the library's own study API (vi_study.h,
vi_census.h, vi_cont.h, vi_orbit.h, vi_builders.h, vi_identify.h) on a
model built once: parameters change by key (vi_param.h), never by
rebuilding.  The GIL is released inside every library call and Ctrl-C
cancels through the studies' cancel hooks (KeyboardInterrupt)."""
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from ._core import Model, _dvec, _method, _nothing, _on_model, _own, _ptr
from ._errors import Error, _s
from ._vi import ffi, lib

_CANCELLED = lib.VI_CANCELLED


class _Cancel:
    """Ctrl-C for a study: the SIGINT hook armed while it runs; the
    library's cancel callback compares the count with its start."""

    fn = ffi.addressof(lib, "vi_py_cancel_since")

    def __enter__(self):
        lib.vi_py_sigint_arm()
        self.start = ffi.new("unsigned *", lib.vi_py_sigint_count())
        return self

    def __exit__(self, *exc):
        lib.vi_py_sigint_disarm()
        return False

    def check(self, st: int) -> None:
        if st == _CANCELLED and lib.vi_py_sigint_count() != self.start[0]:
            _nothing()
            raise KeyboardInterrupt


def _raise(st: int, msg) -> None:
    if st < 0:
        raise Error(_s(msg) or _s(lib.vi_strerror(st)), st)


def _ivec(p, n) -> np.ndarray:
    return np.frombuffer(ffi.buffer(p, n * 4), dtype=np.intc).astype(np.int32) if n else \
        np.empty(0, np.int32)


def _dcopy(p, n) -> np.ndarray:
    return np.frombuffer(ffi.buffer(p, n * 8), dtype=np.float64).copy() if n else np.empty(0)


# ---- sweeps and basins -----------------------------------------------------
def _new_sweep(model: Model, transient, record, method, rtol, atol, tol, nmax, x0, v0, t0):
    sp = ffi.new("vi_sweep **")
    _on_model(model, lambda: lib.vi_sweep_create(model._m, sp))
    sw = _own(sp[0], lib.vi_sweep_destroy, "vi_sweep")

    def call(st):
        _raise(st, lib.vi_sweep_errmsg(sw))

    call(lib.vi_sweep_set_periods(sw, int(transient), int(record)))
    call(lib.vi_sweep_set_classify(sw, float(tol), int(nmax)))
    call(lib.vi_sweep_set_run(sw, _method(method), float(rtol), float(atol)))
    if x0 is not None or v0 is not None or t0:
        xa, va = _dvec(x0, model.n, "x0"), _dvec(v0, model.n, "v0")
        call(lib.vi_sweep_set_initial(sw, float(t0), _ptr(xa), _ptr(va)))
    return sw, call


def _point(sw, n):
    """The last point's P(n, m), impacts and stroboscopic states."""
    pn, pm = ffi.new("int *"), ffi.new("int *")
    lib.vi_sweep_period(sw, pn, pm)
    cnt = ffi.new("vi_int64 *")
    t, ph, vn = ffi.new("double **"), ffi.new("double **"), ffi.new("double **")
    lib.vi_sweep_impacts(sw, cnt, t, ph, vn)
    k = int(cnt[0])
    ld, rec = ffi.new("int *"), ffi.new("int *")
    s = lib.vi_sweep_strobe(sw, ld, rec)
    strobe = np.full((rec[0], 2 * n), np.nan) if s == ffi.NULL else \
        np.frombuffer(ffi.buffer(s, ld[0] * rec[0] * 8), dtype=np.float64).reshape(
            rec[0], ld[0])[:, :2 * n].copy()
    return pn[0], pm[0], _dcopy(t[0], k), _dcopy(ph[0], k), _dcopy(vn[0], k), strobe


def sweep(model: Model, key: str, values: Sequence[float], *, transient: int = 100,
          record: int = 10, warm: bool = True, method: Union[str, int] = "auto",
          rtol: float = 1e-8, atol: float = 1e-10, tol: float = 1e-6, nmax: int = 32,
          orbits: int = 0, lyapunov: bool = False, x0=None, v0=None,
          t0: float = 0.0) -> Dict[str, np.ndarray]:
    """A bifurcation diagram: the model at each value of the parameter
    ``key`` (vi_param.h, e.g. "forcing.omega", "stop.r", "stop.xs"),
    simulated for ``transient`` forcing periods and ``record`` more, warm
    started from the previous point (hysteresis shows) unless warm=False.

    Returns a dict: ``value`` [P]; ``n``, ``m`` [P] the motion P(n, m)
    (n = 0: no period up to nmax); ``failed`` [P] bool; ``strobe`` [P,
    record, 2n] the stroboscopic states (x then v); ``lyapunov`` [P] (NaN
    unless asked); the impacts of every point flattened: ``impact_point``
    (index into value), ``impact_value``, ``impact_t``, ``impact_phase``
    (t mod T), ``impact_vn``; with orbits=nphase > 0 the P(1,1) census at
    each point: ``orbit_point``, ``orbit_vn``, ``orbit_phase``,
    ``orbit_stable``, ``orbit_admissible``.  A failed point is marked, not
    raised; Ctrl-C raises KeyboardInterrupt."""
    vals = np.asarray(values, dtype=np.float64).reshape(-1)
    sw, call = _new_sweep(model, transient, record, method, rtol, atol, tol, nmax, x0, v0, t0)
    call(lib.vi_sweep_set_warm(sw, 1 if warm else 0))
    if orbits:
        call(lib.vi_sweep_set_orbits(sw, int(orbits)))
    if lyapunov:
        call(lib.vi_sweep_set_lyapunov(sw, 1))
    n = model.n
    P = vals.size
    out: Dict[str, Any] = {"value": vals, "n": np.zeros(P, np.int32), "m": np.zeros(P, np.int32),
                           "failed": np.zeros(P, bool),
                           "strobe": np.full((P, int(record), 2 * n), np.nan),
                           "lyapunov": np.full(P, np.nan)}
    imp: List[List[np.ndarray]] = [[], [], [], [], []]
    orb: List[List[np.ndarray]] = [[], [], [], [], []]
    kb = key.encode()
    with _Cancel() as cancel:
        call(lib.vi_sweep_set_cancel(sw, cancel.fn, cancel.start, ffi.NULL))
        for i, val in enumerate(vals):
            call(lib.vi_sweep_set_param(sw, kb, float(val)))
            st = lib.vi_sweep_iterate(sw)
            cancel.check(st)
            if st == lib.VI_ERR_FREQUENCY:  # no period to sweep with
                call(st)
            out["failed"][i] = bool(lib.vi_sweep_failed(sw)) or st < 0
            pn, pm, t, ph, vn, strobe = _point(sw, n)
            out["n"][i], out["m"][i] = pn, pm
            out["strobe"][i, :strobe.shape[0]] = strobe
            out["lyapunov"][i] = lib.vi_sweep_lyapunov(sw)
            for lst, a in zip(imp, (np.full(t.size, i), np.full(t.size, val), t, ph, vn)):
                lst.append(a)
            if orbits:
                c = ffi.new("int *")
                ov, op = ffi.new("double **"), ffi.new("double **")
                os_, oa = ffi.new("int **"), ffi.new("int **")
                lib.vi_sweep_orbits(sw, c, ov, op, os_, oa)
                k = max(c[0], 0)
                for lst, a in zip(orb, (np.full(k, i), _dcopy(ov[0], k), _dcopy(op[0], k),
                                        _ivec(os_[0], k).astype(bool),
                                        _ivec(oa[0], k).astype(bool))):
                    lst.append(a)
    for name, lst in zip(("impact_point", "impact_value", "impact_t", "impact_phase",
                          "impact_vn"), imp):
        out[name] = np.concatenate(lst) if lst else np.empty(0)
    out["impact_point"] = out["impact_point"].astype(np.int64)
    if orbits:
        for name, lst in zip(("orbit_point", "orbit_vn", "orbit_phase", "orbit_stable",
                              "orbit_admissible"), orb):
            out[name] = np.concatenate(lst) if lst else np.empty(0)
    return out


def basins(model: Model, key: str, values: Sequence[float], key2: str,
           values2: Sequence[float], *, transient: int = 100, record: int = 10,
           method: Union[str, int] = "auto", rtol: float = 1e-8, atol: float = 1e-10,
           tol: float = 1e-6, nmax: int = 32, x0=None, v0=None,
           t0: float = 0.0, threads: int = 1) -> Dict[str, np.ndarray]:
    """Basins of attraction (or a two-parameter map): every point of the
    grid values x values2 started cold from the initial state (keys
    initial.x[i], initial.v[i], initial.t0 move it; model keys change the
    model), its motion classified and the periodic ones grouped into
    attractors (vi_sweep_attractors).  ``threads`` > 1 computes the points
    on that many threads (the GIL is released in the library), each with
    its own study of the model: the same result as one thread, since every
    point starts cold.

    Returns ``value`` [P], ``value2`` [Q], ``n``, ``m`` [Q, P] (row j =
    values2[j]), ``id`` [Q, P] the attractor of each point (-1: none) and
    ``nattr``, ``vn`` [Q, P] the last recorded impact's approach velocity
    (NaN without impacts)."""
    v1 = np.asarray(values, dtype=np.float64).reshape(-1)
    v2 = np.asarray(values2, dtype=np.float64).reshape(-1)
    if not v1.size or not v2.size:
        raise Error("basins needs at least one value of each key (got %d x %d)"
                    % (v1.size, v2.size), lib.VI_ERR_ARG)
    n = model.n
    P, Q = v1.size, v2.size
    per = np.zeros(P * Q, np.intc)
    pm = np.zeros(P * Q, np.int32)
    vnl = np.full(P * Q, np.nan)
    strobe = np.full((P * Q, int(record), 2 * n), np.nan)
    k1, k2 = key.encode(), key2.encode()

    def work(points, cancel):
        sw, call = _new_sweep(model, transient, record, method, rtol, atol, tol, nmax,
                              x0, v0, t0)
        call(lib.vi_sweep_set_warm(sw, 0))
        call(lib.vi_sweep_set_cancel(sw, cancel.fn, cancel.start, ffi.NULL))
        for p in points:
            j, i = divmod(p, P)
            call(lib.vi_sweep_set_param(sw, k1, float(v1[i])))
            call(lib.vi_sweep_set_param(sw, k2, float(v2[j])))
            st = lib.vi_sweep_iterate(sw)
            cancel.check(st)
            pn, pmm, t, ph, vn, s = _point(sw, n)
            per[p], pm[p] = (pn, pmm) if st >= 0 else (0, 0)
            vnl[p] = vn[-1] if vn.size else np.nan
            strobe[p, :s.shape[0]] = s

    threads = max(1, min(int(threads), P * Q))
    with _Cancel() as cancel:
        if threads == 1:
            work(range(P * Q), cancel)
        else:
            from concurrent.futures import ThreadPoolExecutor
            # interleaved blocks even out the uneven cost across the grid
            blocks = [range(k, P * Q, threads) for k in range(threads)]
            with ThreadPoolExecutor(threads) as ex:
                for f in [ex.submit(work, b, cancel) for b in blocks]:
                    f.result()
    ids = np.zeros(P * Q, np.intc)
    nattr = ffi.new("int *")
    sc = np.ascontiguousarray(strobe.reshape(P * Q, -1))
    st = lib.vi_sweep_attractors(P * Q, n, int(record), ffi.cast("int *", ffi.from_buffer(per)),
                                 _ptr(sc), 2 * n, float(tol) * 10,
                                 ffi.cast("int *", ffi.from_buffer(ids)), nattr)
    _raise(st, ffi.NULL)
    return {"value": v1, "value2": v2, "n": per.reshape(Q, P).astype(np.int32),
            "m": pm.reshape(Q, P), "id": ids.reshape(Q, P).astype(np.int32),
            "nattr": int(nattr[0]), "vn": vnl.reshape(Q, P)}


# ---- periodic orbits ---------------------------------------------------------
def orbits(model: Model, n: int = 1, m: int = 1, *, phases: int = 720, x0=None, v0=None,
           t0: float = 0.0) -> Dict[str, np.ndarray]:
    """Every P(n, m) orbit the census finds (vi_census.h; what
    ``vibroimpact orbits`` prints), unstable and inadmissible ones
    included.  Returns, for K orbits: ``t`` [K, m] impact times in
    [0, nT), ``x``, ``v`` [K, m, N] pre-impact states, ``stop`` [K, m],
    ``vn`` [K, m], ``multipliers`` [K, 2N] complex Floquet multipliers,
    ``stable``, ``admissible`` [K] bool, ``gmax`` [K] the largest gap
    between impacts."""
    if not (1 <= int(n) <= 64 and 1 <= int(m) <= 64):  # the census's limits
        raise Error("orbits: n = %d and m = %d must lie in 1..64" % (n, m), lib.VI_ERR_ARG)
    cp = ffi.new("vi_census **")
    _on_model(model, lambda: lib.vi_census_create(model._m, int(n), int(m), cp))
    c = _own(cp[0], lib.vi_census_destroy, "vi_census")
    N = model.n

    def call(st):
        _raise(st, lib.vi_census_errmsg(c))

    call(lib.vi_census_set_phases(c, int(phases)))
    if x0 is not None or v0 is not None or t0:
        xa, va = _dvec(x0, N, "x0"), _dvec(v0, N, "v0")
        call(lib.vi_census_set_initial(c, float(t0), _ptr(xa), _ptr(va)))
    with _Cancel() as cancel:
        call(lib.vi_census_set_cancel(c, cancel.fn, cancel.start, ffi.NULL))
        st = lib.vi_census_run(c)
        cancel.check(st)
        call(st)
    K, m = lib.vi_census_count(c), int(m)
    out = {"t": np.zeros((K, m)), "x": np.zeros((K, m, N)), "v": np.zeros((K, m, N)),
           "stop": np.zeros((K, m), np.int32), "vn": np.zeros((K, m)),
           "multipliers": np.zeros((K, 2 * N), complex), "stable": np.zeros(K, bool),
           "admissible": np.zeros(K, bool), "gmax": np.zeros(K)}
    for i in range(K):
        t, vn = np.zeros(m), np.zeros(m)
        x, v = np.zeros((m, N)), np.zeros((m, N))  # column-major [N x m] = C [m, N]
        stop = np.zeros(m, np.intc)
        call(lib.vi_census_orbit(c, i, _ptr(t), _ptr(x), _ptr(v), N,
                                 ffi.cast("int *", ffi.from_buffer(stop)), _ptr(vn)))
        re, im = np.zeros(2 * N), np.zeros(2 * N)
        s, a, g = ffi.new("int *"), ffi.new("int *"), ffi.new("double *")
        call(lib.vi_census_stability(c, i, _ptr(re), _ptr(im), s, a, g))
        out["t"][i], out["vn"][i], out["x"][i], out["v"][i] = t, vn, x, v
        out["stop"][i] = stop
        out["multipliers"][i] = re + 1j * im
        out["stable"][i], out["admissible"][i], out["gmax"][i] = bool(s[0]), bool(a[0]), g[0]
    return out


CONT_EVENTS = ("period_doubling", "fold_or_pitchfork", "neimark_sacker", "grazing",
               "grazing_impact", "fold", "lost", "closed")
CONT_STATES = ("running", "end", "ends", "closes", "corrector", "stalled")


def continuation(model: Model, key: str, to: float, steps: int, *, n: int = 1,
                 method: str = "arclength", orbit: Optional[Mapping[str, Any]] = None,
                 max_points: Optional[int] = None) -> Dict[str, Any]:
    """Follow a P(n, 1) orbit in the parameter ``key`` from its value in
    the model to ``to`` in ``steps`` steps (vi_cont.h; "arclength" goes
    round folds, "natural" stops at one), detecting period doubling,
    folds, Neimark-Sacker and grazing.  The starting orbit is ``orbit``
    ({"t": impact time, "x": .., "v": .. before it}) or the first stable
    admissible P(n, 1) orbit of the census.

    Returns ``param``, ``vn``, ``t``, ``rho`` (largest |multiplier|),
    ``admissible`` per branch point; ``x``, ``v`` [points, N] the orbits;
    ``events``: a dict of arrays ``type`` (names in CONT_EVENTS),
    ``param``, ``vn``, ``mu`` (complex critical multiplier), ``admissible``;
    and ``state``, why it ended (CONT_STATES)."""
    N = model.n
    if orbit is None:
        found = orbits(model, n, 1)
        ok = np.nonzero(found["stable"] & found["admissible"])[0]
        if not ok.size:
            raise Error("no stable admissible P(%d,1) orbit to start from: give orbit=" % n,
                        lib.VI_ERR_NOT_CONVERGED)
        i = ok[0]
        orbit = {"t": found["t"][i, 0], "x": found["x"][i, 0], "v": found["v"][i, 0]}
    meth = {"natural": 0, "arclength": 1}[method]
    cp = ffi.new("vi_cont **")
    _on_model(model, lambda: lib.vi_cont_create(model._m, key.encode(), int(n), meth, cp))
    c = _own(cp[0], lib.vi_cont_destroy, "vi_cont")

    def call(st):
        _raise(st, lib.vi_cont_errmsg(c))

    call(lib.vi_cont_set_range(c, float(to), int(steps)))
    xa, va = _dvec(orbit["x"], N, "orbit x"), _dvec(orbit["v"], N, "orbit v")
    call(lib.vi_cont_set_orbit(c, float(orbit["t"]), _ptr(xa), _ptr(va)))
    pts: Dict[str, List[Any]] = {k: [] for k in ("param", "vn", "t", "rho", "admissible", "x",
                                                 "v")}
    evs: Dict[str, List[Any]] = {k: [] for k in ("type", "param", "vn", "mu", "admissible")}
    limit = max_points if max_points is not None else 4 * int(steps) + 10
    d = [ffi.new("double *") for _ in range(5)]
    ad = ffi.new("int *")
    with _Cancel() as cancel:
        call(lib.vi_cont_set_cancel(c, cancel.fn, cancel.start, ffi.NULL))
        for _ in range(limit):
            st = lib.vi_cont_iterate(c)
            cancel.check(st)
            call(st)
            for e in range(lib.vi_cont_num_events(c)):
                ty = ffi.new("int *")
                lib.vi_cont_event(c, e, ty, d[0], d[1], d[2], d[3], ad)
                evs["type"].append(CONT_EVENTS[ty[0]] if 0 <= ty[0] < len(CONT_EVENTS)
                                   else str(ty[0]))
                evs["param"].append(d[0][0])
                evs["vn"].append(d[1][0])
                evs["mu"].append(complex(d[2][0], d[3][0]))
                evs["admissible"].append(bool(ad[0]))
            if st == 0:
                lib.vi_cont_point(c, d[0], d[1], d[2], d[3], ad)
                x, v = np.zeros(N), np.zeros(N)
                lib.vi_cont_orbit(c, ffi.NULL, _ptr(x), _ptr(v))
                for k, val in zip(("param", "vn", "t", "rho", "admissible", "x", "v"),
                                  (d[0][0], d[1][0], d[2][0], d[3][0], bool(ad[0]), x, v)):
                    pts[k].append(val)
            if lib.vi_cont_done(c) or st != 0:
                break
    out: Dict[str, Any] = {k: np.array(v) for k, v in pts.items()}
    if not len(pts["x"]):
        out["x"] = out["v"] = np.zeros((0, N))
    out["events"] = {k: np.array(v) for k, v in evs.items()}
    st = lib.vi_cont_done(c)
    out["state"] = CONT_STATES[st] if 0 <= st < len(CONT_STATES) else str(st)
    return out


CURVE_KINDS = ("grazing", "fold", "pd", "ns")
CURVE_SPECIALS = ("grazing", "fold", "period_doubling", "cusp", "resonance_1_1",
                  "resonance_1_2", "admissibility")
CURVE_ENDS = ("running", "end of range", "not admissible beyond", "closed",
              "corrector failed", "point limit", "resonance (beyond, a neutral saddle)")


def _curve_seed(model: Model, n: int, m: int) -> Mapping[str, np.ndarray]:
    """The admissible P(n, m) orbit of the census with the smallest largest
    multiplier (as ``vibroimpact curves`` takes the scene's), its impacts
    from the earliest."""
    found = orbits(model, n, m)
    ok = np.nonzero(found["admissible"])[0]
    if not ok.size:
        raise Error("no admissible P(%d,%d) orbit to start from: give orbit=" % (n, m),
                    lib.VI_ERR_NOT_CONVERGED)
    i = ok[np.argmin(np.abs(found["multipliers"][ok]).max(axis=1))]
    order = np.argsort(found["t"][i])
    return {"t": found["t"][i][order], "x": found["x"][i][order], "v": found["v"][i][order]}


def curve(model: Model, kind: str, key: str, to: float, key2: str, from2: float, to2: float, *,
          orbit: Tuple[int, int] = (1, 1), steps: int = 200,
          start: Optional[Mapping[str, Any]] = None) -> Dict[str, Any]:
    """A curve of codimension-one points in two parameters (vi_cont_curve.h;
    what ``vibroimpact curves`` computes, doc/curves.md): follow the
    P(n, m) orbit ``orbit`` ((1, 0): the non-impacting one) in ``key`` from
    its value in the model towards ``to`` until the first point of
    ``kind`` (grazing, fold, pd or ns), solved exactly, then follow that
    point in (key, key2) over key2 from ``from2`` to ``to2``, its largest
    step 1/steps of that range.  The starting orbit is ``start`` ({"t":
    [m] impact times ascending within nT, "x", "v": [m, N] states before
    them}, e.g. a row of :func:`orbits`) or the census's admissible one
    with the smallest largest multiplier.

    Returns ``kind``, ``param``, ``param2``, ``orbit``, ``located`` (the
    first point, [key, key2]), ``points`` [K, 2] in order along the curve,
    ``special``: a list of {"type" (CURVE_SPECIALS), "point", "located"},
    and ``start`` and ``end`` (CURVE_ENDS: why the first and the last
    point end the curve), as the command's JSON."""
    if kind not in CURVE_KINDS:
        raise ValueError("kind must be one of %s, not %r" % (", ".join(CURVE_KINDS), kind))
    if int(steps) < 1:
        raise Error("steps must be >= 1, not %d" % steps, lib.VI_ERR_ARG)
    n, m = int(orbit[0]), int(orbit[1])
    N = model.n
    for k in (key, key2):  # an unknown key named (the handle says only "invalid argument")
        model.get_param(k)
    if key == key2:  # refused by the library with no message of its own
        raise Error("key and key2 are both %s: a curve needs two different parameters" % key,
                    lib.VI_ERR_ARG)
    if m and start is None:
        start = _curve_seed(model, n, m)
    cp = ffi.new("vi_cont_curve **")
    _on_model(model, lambda: lib.vi_cont_curve_create(
        model._m, CURVE_KINDS.index(kind), n, m, key.encode(), key2.encode(), cp))
    c = _own(cp[0], lib.vi_cont_curve_destroy, "vi_cont_curve")

    def call(st):
        _raise(st, lib.vi_cont_curve_errmsg(c))

    if m:
        t = np.ascontiguousarray(np.asarray(start["t"], float).reshape(m))
        # [m, N] in C order is the column-major [N x m] the library takes
        x = np.ascontiguousarray(np.asarray(start["x"], float).reshape(m, N))
        v = np.ascontiguousarray(np.asarray(start["v"], float).reshape(m, N))
        call(lib.vi_cont_curve_set_impacts(c, _ptr(t), _ptr(x), _ptr(v), N))
    p, p2 = ffi.new("double *"), ffi.new("double *")
    call(lib.vi_cont_curve_locate(c, float(to), int(steps), p))
    call(lib.vi_cont_curve_point(c, p, p2, ffi.NULL, ffi.NULL, ffi.NULL, ffi.NULL))
    located = [p[0], p2[0]]
    call(lib.vi_cont_curve_set_range(c, float(from2), float(to2), int(steps)))
    points: List[List[float]] = []
    special: List[Dict[str, Any]] = []
    ty, loc = ffi.new("int *"), ffi.new("int *")
    while not lib.vi_cont_curve_done(c):
        st = lib.vi_cont_curve_iterate(c)
        if st < 0:
            call(st)
        if st:
            break
        lib.vi_cont_curve_point(c, p, p2, ffi.NULL, ffi.NULL, ffi.NULL, ffi.NULL)
        points.append([p[0], p2[0]])
        for i in range(lib.vi_cont_curve_num_special(c)):
            lib.vi_cont_curve_special(c, i, ty, p, p2, loc)
            special.append({"type": CURVE_SPECIALS[ty[0]] if 0 <= ty[0] < len(CURVE_SPECIALS)
                            else str(ty[0]), "point": [p[0], p2[0]], "located": bool(loc[0])})
    end, start = lib.vi_cont_curve_done(c), lib.vi_cont_curve_start(c)
    return {"kind": kind, "param": key, "param2": key2, "orbit": [n, m], "located": located,
            "points": np.array(points).reshape(-1, 2), "special": special,
            "start": CURVE_ENDS[start] if 0 <= start < len(CURVE_ENDS) else str(start),
            "end": CURVE_ENDS[end] if 0 <= end < len(CURVE_ENDS) else str(end)}


# ---- energy ------------------------------------------------------------------
def energy(model: Model, *, x0=None, v0=None, method: Union[str, int, None] = None,
           rtol: Optional[float] = None, atol: Optional[float] = None,
           transient: float = 3000, tol: float = 1e-6) -> Dict[str, Any]:
    """The paper's energy balance (WB 11-13; ``vibroimpact energy``): the
    motion after the transient classified P(n, m); for a P(1,1) orbit,
    refined by Newton shooting, its balance over one period: ``period``,
    ``phase``, ``vN``, ``KE_i``, ``RE``, ``IE``, ``r_recovered`` (WB 12),
    ``closure`` |RE - IE| / KE_i, per mode ``FE``, ``DE``, ``XE``,
    ``r_eff``; ``multipliers`` (complex, 2N), ``t_impact``, ``x_impact``,
    ``v_impact``, ``min_gap``, and ``r_S`` [min(N, 4)], the restitution a
    model of the first 1, 2, .. modes needs (NaN where none exists).
    Other motions give ``n``, ``m`` only."""
    op = ffi.new("vi_orbit **")
    _on_model(model, lambda: lib.vi_orbit_create(model._m, op))
    o = _own(op[0], lib.vi_orbit_destroy, "vi_orbit")
    N = model.n

    def call(st):
        _raise(st, lib.vi_orbit_errmsg(o))

    if method is not None:
        call(lib.vi_orbit_set_method(o, _method(method)))
    if rtol is not None or atol is not None:
        call(lib.vi_orbit_set_tolerances(o, float(rtol or 1e-10), float(atol or 1e-12)))
    if x0 is not None or v0 is not None:
        call(lib.vi_orbit_set_initial(o, _ptr(_dvec(x0, N, "x0")), _ptr(_dvec(v0, N, "v0"))))
    call(lib.vi_orbit_set_transient(o, float(transient), float(tol)))
    call(lib.vi_orbit_find(o))
    pn, pm = ffi.new("int *"), ffi.new("int *")
    call(lib.vi_orbit_classify(o, pn, pm))
    out: Dict[str, Any] = {"n": pn[0], "m": pm[0]}
    if (pn[0], pm[0]) != (1, 1):
        return out
    d = [ffi.new("double *") for _ in range(8)]
    call(lib.vi_orbit_balance(o, *d))
    for k, p in zip(("period", "phase", "vN", "KE_i", "RE", "IE", "r_recovered", "closure"), d):
        out[k] = p[0]
    FE, DE, XE, re = (np.zeros(N) for _ in range(4))
    call(lib.vi_orbit_modal_balance(o, _ptr(FE), _ptr(DE), _ptr(XE), _ptr(re)))
    out.update(FE=FE, DE=DE, XE=XE, r_eff=re)
    mr, mi = np.zeros(2 * N), np.zeros(2 * N)
    call(lib.vi_orbit_multipliers(o, _ptr(mr), _ptr(mi)))
    out["multipliers"] = mr + 1j * mi
    t, x, v = ffi.new("double *"), np.zeros(N), np.zeros(N)
    call(lib.vi_orbit_impact_state(o, t, _ptr(x), _ptr(v)))
    out.update(t_impact=t[0], x_impact=x, v_impact=v)
    g = ffi.new("double *")
    call(lib.vi_orbit_min_gap(o, g))
    out["min_gap"] = g[0]
    rs = np.full(min(N, 4), np.nan)
    for k in range(1, rs.size + 1):
        modes = np.arange(k, dtype=np.intc)
        r = ffi.new("double *")
        if lib.vi_orbit_reduced_restitution(o, ffi.cast("int *", ffi.from_buffer(modes)), k,
                                            r) == 0:
            rs[k - 1] = r[0]
    out["r_S"] = rs
    return out


# ---- truncation ---------------------------------------------------------------
def truncation(model: Model, kmax: Optional[int] = None, stop: int = 0) -> Dict[str, np.ndarray]:
    """How much of the stop's compliance the first k modes carry, k = 1..kmax
    (``vibroimpact truncation``'s first table; a model in modal
    coordinates: Model.from_sparse): ``k``, ``dynamic`` = sum psi_i^2 (of
    w^T M^-1 w, Newton's law's Delassus number), ``static`` = sum
    psi_i^2 / omega_i^2 (of w^T K^-1 w; inf once a rigid mode carries the
    stop), and ``dynamic_fraction``, ``static_fraction`` of the model's
    whole compliance (its N modes).  truncated_model() gives the reduced
    model itself."""
    N = model.n
    kmax = N if kmax is None else int(kmax)
    dyn, sta = np.zeros(N), np.zeros(N)
    _on_model(model, lambda: lib.vi_model_modal_compliance(model._m, int(stop), N, _ptr(dyn),
                                                           _ptr(sta)))
    with np.errstate(invalid="ignore", divide="ignore"):
        return {"k": np.arange(1, kmax + 1), "dynamic": dyn[:kmax], "static": sta[:kmax],
                "dynamic_fraction": dyn[:kmax] / dyn[-1], "static_fraction": sta[:kmax] / sta[-1]}


def truncated_model(model: Model, k: int, *, static_vector: bool = False,
                    r: Optional[float] = None) -> Model:
    """The model cut to its first k modal coordinates (and, with
    static_vector, the static residual vector at the stop), restitution r
    (default the model's): vi_model_create_truncated."""
    if r is None:
        r = model.get_param("stop.r")
    if not 1 <= int(k) <= model.n - (1 if static_vector else 0):
        raise Error("k = %d modes: the model has %d coordinates (k + 1 with static_vector)"
                    % (k, model.n), lib.VI_ERR_ARG)
    mp = ffi.new("vi_model **")
    _on_model(model, lambda: lib.vi_model_create_truncated(
        model._m, int(k), 1 if static_vector else 0, float(r), ffi.NULL, ffi.NULL, ffi.NULL, mp))
    return Model(_handle=_own(mp[0], lib.vi_model_destroy, "vi_model"))


# The columns of a truncation study's row (vi_truncation.h), name and width.
_TRUNCATION_COLUMNS = (
    ("k", 1), ("omega", 1), ("dynamic_fraction", 1), ("static_fraction", 1),
    ("class_n", 1), ("class_m", 1), ("vN", 1), ("phase", 1),
    ("first_n", 1), ("first_t", 3), ("first_vn", 3), ("first_dt", 3), ("first_dvn_rel", 3),
    ("release", 1), ("r_S", 1), ("r_S_class_n", 1), ("r_S_class_m", 1), ("r_S_vN", 1),
    ("r_S_phase", 1), ("static_corrected", 1), ("sc_dynamic_fraction", 1), ("sc_class_n", 1),
    ("sc_class_m", 1), ("sc_vN", 1), ("sc_phase", 1), ("sc_first_n", 1), ("sc_first_t", 3),
    ("sc_first_vn", 3), ("sc_first_dt", 3), ("sc_first_dvn_rel", 3), ("sc_release", 1))
_TRUNCATION_SUMMARY = ("dofs", "modes_lo", "modes_hi", "reference_modes", "restitution",
                       "compliance_dynamic", "compliance_static", "complete")


def _truncation_columns(rows: np.ndarray) -> Dict[str, np.ndarray]:
    out, c = {}, 0
    for name, w in _TRUNCATION_COLUMNS:
        out[name] = rows[:, c] if w == 1 else rows[:, c:c + w]
        c += w
    return out


def truncation_study(model: Model, modes: Optional[Tuple[int, int]] = None, *,
                     initial: Optional[Mapping[str, Any]] = None) -> Dict[str, Any]:
    """The truncation study of ``vibroimpact truncation`` (vi_truncation.h):
    for each kept-mode count k in ``modes`` (lo, hi; default every mode),
    the stop compliance the first k modes carry, the k-mode model's
    response with the model's r, the r_S that carries the reference's
    energy balance (WB 12-13) and that model's response, the same with a
    static vector at the stop, and with ``initial`` ({"t0", "t_end", "x",
    "v"}, x and v optional) the first impacts against the reference's.
    The reference is ``model`` with all its modes.

    Returns ``rows``: a dict of arrays over k (names as the C row's
    columns: ``k``, ``omega``, ``dynamic_fraction``, ``r_S``,
    ``first_t`` [k, 3], ...); ``reference``: the reference's row as a dict;
    ``summary``: dofs, modes_lo, modes_hi, reference_modes, restitution,
    compliance_dynamic, compliance_static, complete."""
    tp = ffi.new("vi_truncation **")
    _on_model(model, lambda: lib.vi_truncation_create(model._m, tp))
    tr = _own(tp[0], lib.vi_truncation_destroy, "vi_truncation")

    def call(st):
        _raise(st, lib.vi_truncation_errmsg(tr))

    if modes is not None:
        call(lib.vi_truncation_set_modes(tr, int(modes[0]), int(modes[1])))
    if initial is not None:
        N = model.n
        x = _dvec(initial.get("x"), N, "initial x")
        v = _dvec(initial.get("v"), N, "initial v")
        call(lib.vi_truncation_set_initial(tr, float(initial.get("t0", 0.0)),
                                           float(initial["t_end"]),
                                           _ptr(x) if x is not None else ffi.NULL,
                                           _ptr(v) if v is not None else ffi.NULL))
    with _Cancel() as cancel:
        call(lib.vi_truncation_set_cancel(tr, cancel.fn, cancel.start, ffi.NULL))
        while not lib.vi_truncation_done(tr):
            st = lib.vi_truncation_iterate(tr)
            cancel.check(st)
            call(st)
    ncol = lib.VI_TRUNCATION_COLUMNS
    nr = ffi.new("int *")
    call(lib.vi_truncation_table(tr, ffi.NULL, 1, nr))
    rows = np.zeros((ncol, max(1, nr[0])))  # column-major [ld x ncol]
    call(lib.vi_truncation_table(tr, _ptr(rows), max(1, nr[0]), nr))
    ref = np.zeros(ncol)
    call(lib.vi_truncation_row(tr, 0, _ptr(ref)))
    info = np.zeros(lib.VI_TRUNCATION_INFO)
    call(lib.vi_truncation_summary(tr, _ptr(info)))
    table = rows.T[:nr[0]]
    refd = {k: v[0] for k, v in _truncation_columns(ref[None, :]).items()}
    return {"rows": _truncation_columns(table), "reference": refd,
            "summary": dict(zip(_TRUNCATION_SUMMARY, info.tolist()))}


# ---- identification --------------------------------------------------------------
def identify(model: Model, t: np.ndarray, x: np.ndarray, fit: Mapping[str, Tuple[float, float]],
             *, v: Optional[np.ndarray] = None, observation=None, noise: Optional[float] = None,
             global_search: bool = True, stable_only: bool = True) -> Dict[str, Any]:
    """Parameters from a recorded periodic response (vi_identify.h, the
    paper's section 4): least squares on the model's orbit against the
    recording (t, x = c.x; v = c.x' optional), c the observation vector
    (default the stop's w), fitting the keys of ``fit`` ({"stop.r": (lo,
    hi), ...}, NaN for an open side) from starts spread over their ranges.

    Returns ``keys``, ``p``, ``se``, ``lo95``, ``hi95`` (Jacobian
    intervals), ``profile_lo95``, ``profile_hi95``, ``solutions`` [S, P]
    every fit the noise admits (best first) and ``unique``; ``converged``,
    ``iterations``, ``rms``, ``noise``, ``n``, ``m`` (the orbit's P(n, m)),
    ``t0`` the fitted time shift, ``response`` the fitted model's c.x at
    the recording's times and ``outliers``: the samples of x beyond 6 noise
    levels from it (``count``; the worst 8, farthest first, as 0-based
    ``samples`` and their distances ``z`` in noise levels;
    ``rms_ratio_without`` the others' residual RMS over the noise)."""
    keys = list(fit)
    P = len(keys)
    ip = ffi.new("vi_identify **")
    _on_model(model, lambda: lib.vi_identify_create(model._m, P, ip))
    h = _own(ip[0], lib.vi_identify_destroy, "vi_identify")

    def call(st):
        _raise(st, lib.vi_identify_errmsg(h))

    for j, k in enumerate(keys):
        lo, hi = fit[k]
        call(lib.vi_identify_set_param_key(h, j, k.encode(), float(lo), float(hi)))
    if observation is not None:
        c = _dvec(observation, model.n, "observation")
        call(lib.vi_identify_set_observation(h, _ptr(c)))
    if noise is not None:
        call(lib.vi_identify_set_noise(h, float(noise)))
    call(lib.vi_identify_set_global(h, 1 if global_search else 0))
    call(lib.vi_identify_set_stable_only(h, 1 if stable_only else 0))
    ta = np.ascontiguousarray(t, dtype=np.float64)
    xa = np.ascontiguousarray(x, dtype=np.float64)
    va = None if v is None else np.ascontiguousarray(v, dtype=np.float64)
    if xa.size != ta.size or (va is not None and va.size != ta.size):
        raise Error("t, x (and v) must have one length", lib.VI_ERR_DIM)
    call(lib.vi_identify_set_data(h, ta.size, _ptr(ta), _ptr(xa), _ptr(va)))
    with _Cancel() as cancel:
        call(lib.vi_identify_set_cancel(h, cancel.fn, cancel.start, ffi.NULL))
        st = lib.vi_identify_run(h)
        cancel.check(st)
        call(st)
    uq = ffi.new("int *")
    S = lib.vi_identify_nsolutions(h, uq)
    sols = np.zeros((S, P))
    out: Dict[str, Any] = {"keys": keys}
    for s in range(S):
        p, se, lo, hi = (np.zeros(P) for _ in range(4))
        call(lib.vi_identify_solution(h, s, _ptr(p), _ptr(se), _ptr(lo), _ptr(hi), ffi.NULL))
        sols[s] = p
        if s == 0:
            out.update(p=p, se=se, lo95=lo, hi95=hi)
            plo, phi = np.zeros(P), np.zeros(P)
            call(lib.vi_identify_solution_profile(h, 0, _ptr(plo), _ptr(phi), ffi.NULL))
            out.update(profile_lo95=plo, profile_hi95=phi)
    out["solutions"], out["unique"] = sols, bool(uq[0])
    cv, it, pn, pm = (ffi.new("int *") for _ in range(4))
    rms, nz, rc = (ffi.new("double *") for _ in range(3))
    call(lib.vi_identify_summary(h, cv, it, rms, nz, rc, pn, pm))
    out.update(converged=bool(cv[0]), iterations=it[0], rms=rms[0], noise=nz[0], n=pn[0],
               m=pm[0])
    sn, sm = ffi.new("int *"), ffi.new("int *")
    d = [ffi.new("double *") for _ in range(4)]
    call(lib.vi_identify_solution_summary(h, 0, sn, sm, *d))
    out["t0"] = d[3][0]
    resp = np.zeros(ta.size)
    call(lib.vi_identify_response(h, ta.size, _ptr(ta), _ptr(resp), ffi.NULL))
    # samples beyond 6 noise levels (once in 5e8 for Gaussian noise), the
    # worst 8 farthest first, as the program reports them
    cap, oc, rest = 8, ffi.new("int *"), ffi.new("double *")
    oi, oz = ffi.new("int[]", cap), np.zeros(cap)
    call(lib.vi_identify_outliers(h, 6.0, cap, oi, _ptr(oz), oc, rest))
    k = min(cap, oc[0])
    out["outliers"] = {"count": oc[0], "samples": [oi[i] for i in range(k)],
                       "z": oz[:k].copy(), "rms_ratio_without": rest[0]}
    out["response"] = resp
    return out

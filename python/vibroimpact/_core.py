"""Models, scenes, simulations and their results."""
import math
import os
import threading
from typing import Any, Callable, Dict, Iterable, List, Mapping, Optional, Sequence, Union

import numpy as np

from ._errors import Error, _s, check, diag_error
from ._vi import ffi, lib

ArrayLike = Union[float, Sequence[float], np.ndarray]

METHODS = ("adams", "bdf", "exact", "auto", "erk")
_KINDS = {"impact": 0, "stick": 1, "release": 2}


# ---- handles owned by Python objects ------------------------------------
def _own(ptr, destroy, kind):
    """A cdata pointer freed by its vi_*_destroy when Python drops it."""
    def free(p):
        destroy(ffi.new(kind + " **", p))
    return ffi.gc(ptr, free)


def _dvec(x, n: int, what: str, allow_none: bool = True):
    """A contiguous float64 vector of length n (a scalar is broadcast)."""
    if x is None:
        if allow_none:
            return None
        raise Error("%s is required" % what, lib.VI_ERR_ARG)
    a = np.asarray(x, dtype=np.float64)
    if a.ndim == 0:
        a = np.full(n, float(a))
    a = np.ascontiguousarray(a.reshape(-1))
    if a.size != n:
        raise Error("%s has %d entries, the model %d" % (what, a.size, n), lib.VI_ERR_DIM)
    return a


def _dmat(A, n: int, what: str):
    """A Fortran-ordered (column-major) n x n float64 matrix."""
    a = np.asarray(A, dtype=np.float64)
    if a.ndim != 2 or a.shape != (n, n):
        raise Error("%s must be %d x %d, not %s" % (what, n, n, a.shape), lib.VI_ERR_DIM)
    return np.asfortranarray(a)


def _ptr(a):
    """double * of a numpy array (NULL for None); the array must stay alive."""
    if a is None:
        return ffi.NULL
    if not a.flags.c_contiguous:  # column-major: its transpose is the same memory
        a = a.T
    return ffi.cast("double *", ffi.from_buffer(a))


def _method(method) -> int:
    if isinstance(method, (int, np.integer)):
        if 0 <= int(method) < len(METHODS):
            return int(method)
        raise Error("unknown method %r (one of %s)" % (method, ", ".join(METHODS)), lib.VI_ERR_ARG)
    m = lib.vi_method_from_name(str(method).encode())
    if m < 0:
        raise Error("unknown method %r (one of %s)" % (method, ", ".join(METHODS)), lib.VI_ERR_ARG)
    return m


_METHOD_IDS = {name: i for i, name in enumerate(METHODS)}


def _nothing():
    """A Python call: the interpreter runs pending signal handlers here."""
    return None


# ---- results -------------------------------------------------------------
_LED = ("t_a", "t_b", "ie", "residual", "impact", "E_a", "E_b", "K_a", "K_b",
        "FE", "DE", "XE", "CE", "NE", "dE")
_INT = ("kind", "stop", "impact")


class Result:
    """The outcome of one run: events, samples, ledger, statistics.

    Attributes
    ----------
    impacts : dict of numpy arrays
        One row per event: ``t``, ``vn`` (approach velocity), ``ie`` (energy
        lost), ``kind`` (0 impact, 1 stick, 2 release, as in HDF5), ``stop``
        (0-based) and, unless the run was made with ``states=False``, the
        states ``x``, ``v_minus``, ``v_plus`` ``[events, n]``.
    samples : dict
        ``t``, ``x``, ``v`` of the uniform samples (empty without sampling).
    ledger : dict
        The energy ledger per impact-free interval (empty unless asked).
    stats : dict
        Every statistic of the library by its name (``steps``, ``impacts``...).
    status : str
        ``"ok"``, ``"stopped"`` or ``"cancelled"``.
    method_used, method_note : str
        The method that ran and why.
    t, x, v :
        The final time and state.
    """

    def __init__(self, model, sim, run, status, fe=None, scene=None,
                 rtol=None, atol=None, method=None, generation=0):
        self._model = model
        self._sim = sim
        self._run = run
        self._scene = scene
        self._rtol, self._atol, self._method = rtol, atol, method
        self._generation = generation
        self._cache: Dict[int, Dict[str, np.ndarray]] = {}
        self.status = {0: "ok", 1: "stopped", 2: "cancelled"}.get(status, str(status))
        self.n = model.n

    def _table(self, g: int) -> Dict[str, np.ndarray]:
        """Table g (0 events, 1 samples, 2 ledger) as named column views of
        one array copied from the run's buffer."""
        out = self._cache.get(g)
        if out is not None:
            return out
        rows, width = ffi.new("vi_int64 *"), ffi.new("int *")
        p = lib.vi_py_table(self._run, g, rows, width)
        A = np.empty((rows[0], width[0]))
        if rows[0]:
            ffi.memmove(ffi.from_buffer(A), p, A.nbytes)
        n = self.n
        out = {}
        if g == 1:
            out.update(t=A[:, 0], x=A[:, 1:1 + n], v=A[:, 1 + n:1 + 2 * n])
        elif g == 0:
            ks = A[:, 3:4].view(np.int32)  # kind and stop: two int32 in one column
            out.update(t=A[:, 0], vn=A[:, 1], ie=A[:, 2], kind=ks[:, 0], stop=ks[:, 1])
            if width[0] > 4:  # states=True
                out.update(x=A[:, 4:4 + n], v_minus=A[:, 4 + n:4 + 2 * n],
                           v_plus=A[:, 4 + 2 * n:4 + 3 * n])
        else:
            for i, name in enumerate(_LED[:5]):
                out[name] = A[:, i].astype(np.int32) if name in _INT else A[:, i]
            for i, name in enumerate(_LED[5:]):
                out[name] = A[:, 5 + i * n:5 + (i + 1) * n]
        self._cache[g] = out
        return out

    @property
    def impacts(self) -> Dict[str, np.ndarray]:
        return self._table(0)

    @property
    def samples(self) -> Dict[str, np.ndarray]:
        return self._table(1)

    @property
    def ledger(self) -> Dict[str, np.ndarray]:
        return self._table(2)

    @property
    def stats(self) -> Dict[str, int]:
        out = {}
        for k in range(64):
            name = lib.vi_stat_name(k)
            if name == ffi.NULL:
                break
            out[_s(name)] = int(lib.vi_sim_stat(self._sim, k))
        return out

    @property
    def method_used(self) -> str:
        return _s(lib.vi_method_name(lib.vi_sim_method_used(self._sim)))

    @property
    def method_note(self) -> str:
        return _s(lib.vi_sim_method_note(self._sim))

    def _state(self):
        t = ffi.new("double *")
        x = np.empty(self.n)
        v = np.empty(self.n)
        lib.vi_sim_state(self._sim, t, _ptr(x), _ptr(v))
        return t[0], x, v

    @property
    def t(self) -> float:
        return self._state()[0]

    @property
    def x(self) -> np.ndarray:
        return self._state()[1]

    @property
    def v(self) -> np.ndarray:
        return self._state()[2]

    def impact_times(self, kind: str = "impact") -> np.ndarray:
        """Times of the events of one kind ("impact", "stick", "release")."""
        ev = self.impacts
        return ev["t"][ev["kind"] == _KINDS[kind]]

    def to_hdf5(self, path: Union[str, os.PathLike], compress: bool = True) -> None:
        """Write the run as ``vibroimpact run -o`` does (doc/hdf5-layout.md):
        root attributes, /scene (a scene's run), /model, /modal (a model's
        run), /impacts, /trajectory, /ledger and /run.  The file appears
        under its name only once complete (written as PATH.part)."""
        if self._model._generation != self._generation:
            raise Error("the model's parameters changed since this run: "
                        "its HDF5 file would describe another model", lib.VI_ERR_STATE)
        if self.impacts["t"].size and "x" not in self.impacts:
            raise Error("to_hdf5 needs the events' states: run with states=True", lib.VI_ERR_ARG)
        d = ffi.new("vi_diag *")
        wp = ffi.new("vi_writer **")
        st = lib.vi_writer_create(os.fsencode(os.fspath(path)), self._model._m,
                                  1 if compress else 0, wp, d)
        if st:
            raise diag_error(d, st)
        w = wp[0]
        try:
            sc = self._scene._sc if self._scene is not None else ffi.NULL
            st = lib.vi_writer_write_header(w, sc, self._rtol, self._atol, self._method)
            if not st:
                st = lib.vi_py_replay(self._run, w)
            if not st:
                st = lib.vi_writer_run_info(w, self._sim)
            if not st:
                st = lib.vi_writer_finish(w, 1 if self.status == "ok" else 0)
            if st:
                raise Error(_s(lib.vi_writer_errmsg(w)), st)
        finally:
            lib.vi_writer_abort(wp)

    def __repr__(self):
        ev = self.impacts
        return "<vibroimpact.Result %s: %d events (%d impacts), t = %.6g, method %s>" % (
            self.status, ev["t"].size, int(np.sum(ev["kind"] == 0)), self.t,
            self.method_used)


def _simulate(model, sim, t_end, method, rtol, atol, *, samples_dt=0.0, ledger=False,
              states=True, scene=None):
    """Attach the collectors, run with the GIL released (cffi releases it
    around every C call) and Ctrl-C on the cancel hook, wrap the result."""
    run = lib.vi_py_run_new(model.n, 1 if states else 0)
    if run == ffi.NULL:
        raise MemoryError("vibroimpact: no memory for a run's buffers")
    run = ffi.gc(run, lib.vi_py_run_free)
    st = lib.vi_py_prepare(run, sim, method, rtol, atol, samples_dt, 1 if ledger else 0)
    if st < 0:
        raise Error(_s(lib.vi_sim_errmsg(sim)) or _s(lib.vi_strerror(st)), st)
    intr = ffi.new("int *")
    st = lib.vi_py_sim_run(sim, run, t_end, intr)
    if intr[0]:
        _nothing()  # the main thread's KeyboardInterrupt is raised here
        if threading.current_thread() is not threading.main_thread():
            raise KeyboardInterrupt
    if st == 1 and lib.vi_py_nomem(run):  # the collectors ran out of memory
        raise MemoryError("vibroimpact: out of memory collecting the run's events")
    if st < 0:
        raise Error(_s(lib.vi_sim_errmsg(sim)) or _s(lib.vi_strerror(st)), st)
    return Result(model, sim, run, st, scene=scene, rtol=rtol, atol=atol,
                  method=method, generation=model._generation)


# A simulation holds its C model (vi_sim_destroy gives the hold back): the
# model's handle stays alive until the simulation is freed, whatever order
# Python drops the two in.
_sim_models: Dict[int, Any] = {}


def _free_sim(p):
    lib.vi_py_sim_free(p)
    _sim_models.pop(int(ffi.cast("uintptr_t", p)), None)


def _on_model(model: "Model", call: Callable[[], int]) -> None:
    """Run a call that reports through the model's message (a handle's
    create, a derived model): its failure carries that message only if the
    call wrote it, not one an earlier failure left there."""
    before = _s(lib.vi_model_errmsg(model._m))
    st = call()
    if st < 0:
        after = _s(lib.vi_model_errmsg(model._m))
        raise Error(after if after and after != before else _s(lib.vi_strerror(st)), st)


def _new_sim(model):
    sp = ffi.new("vi_sim **")
    _on_model(model, lambda: lib.vi_sim_create(model._m, sp))
    _sim_models[int(ffi.cast("uintptr_t", sp[0]))] = model._m
    return ffi.gc(sp[0], _free_sim)


def _sim_check(sim, st):
    if st < 0:
        raise Error(_s(lib.vi_sim_errmsg(sim)) or _s(lib.vi_strerror(st)), st)


# ---- models --------------------------------------------------------------
class Model:
    """A linear structure with stops and harmonic forcing (WB 1-2),

        M x'' + C x' + K x = a cos(omega t) + b sin(omega t) + f0,
        w_k . x <= xs_k,  Newton restitution r_k,

    built once (validated, modal analysis done) and simulated many times.

    Parameters
    ----------
    M, C, K : (n, n) array_like
        Mass (symmetric positive definite), damping (None: undamped) and
        stiffness (symmetric positive semidefinite).
    stops : list of dict
        ``{"w": w, "xs": x_s, "r": r}`` each (``w`` a length-n vector), or
        ``{"dof": i, "direction": +1 or -1, "xs": .., "r": ..}`` with i
        0-based.
    forcing : dict, optional
        ``{"omega": W, "a": a, "b": b, "f0": f0}``; vectors of length n,
        omitted ones zero.
    rayleigh : (alpha, beta), optional
        C = alpha M + beta K instead of C.

    Raises
    ------
    vibroimpact.Error
        with the library's message and status when the model is invalid.
    """

    def __init__(self, M=None, C=None, K=None, stops: Optional[List[Mapping[str, Any]]] = None,
                 forcing: Optional[Mapping[str, Any]] = None, *, stop=None,
                 rayleigh: Optional[Sequence[float]] = None, _handle=None, _fe=None,
                 _dofs=None):
        self._generation = 0
        self._lock = threading.Lock()
        self._fe = _fe
        if _handle is not None:
            self._m = _handle
            self.n = lib.vi_model_n(self._m)
            self.dofs = _dofs if _dofs is not None else self.n
            return
        if K is None:
            raise Error("Model needs K (and M, or the identity)", lib.VI_ERR_ARG)
        Ka = np.asarray(K, dtype=np.float64)
        if Ka.ndim != 2 or Ka.shape[0] != Ka.shape[1] or Ka.shape[0] < 1:
            raise Error("K must be a square matrix, not %s" % (Ka.shape,), lib.VI_ERR_DIM)
        n = Ka.shape[0]
        mp = ffi.new("vi_model **")
        check(lib.vi_model_create(n, mp), what="vi_model_create")
        self._m = _own(mp[0], lib.vi_model_destroy, "vi_model")
        self.n = self.dofs = n
        Mm = _dmat(np.eye(n) if M is None else M, n, "M")
        Km = _dmat(Ka, n, "K")
        self._call(lib.vi_model_set_mass(self._m, _ptr(Mm), n))
        self._call(lib.vi_model_set_stiffness(self._m, _ptr(Km), n))
        if C is not None:
            Cm = _dmat(C, n, "C")
            self._call(lib.vi_model_set_damping(self._m, _ptr(Cm), n))
        self._configure(stops if stops is not None else ([stop] if stop else []),
                        forcing, rayleigh)

    def _call(self, st: int) -> int:
        if st < 0:
            raise Error(_s(lib.vi_model_errmsg(self._m)) or _s(lib.vi_strerror(st)), st)
        return st

    def _configure(self, stops, forcing, rayleigh):
        n = self.n
        if forcing:
            unknown = set(forcing) - {"omega", "a", "b", "f0"}
            if unknown:
                raise Error("forcing: unknown keys %s (omega, a, b, f0)" % sorted(unknown),
                            lib.VI_ERR_ARG)
            vec = [_dvec(forcing.get(k), n, "forcing." + k) for k in ("a", "b", "f0")]
            self._call(lib.vi_model_set_forcing(self._m, float(forcing.get("omega", 0.0)),
                                                *[_ptr(v) for v in vec]))
        if not stops:
            raise Error("a model needs at least one stop", lib.VI_ERR_STOP_VECTOR)
        for k, s in enumerate(stops):
            w = _stop_vector(s, n, k)
            self._call(lib.vi_model_add_stop(self._m, _ptr(w), float(s.get("xs", 0.0)),
                                             float(s.get("r", 1.0))))
        if rayleigh is not None:
            alpha, beta = rayleigh
            self._call(lib.vi_model_set_param(self._m, b"damping.alpha", float(alpha)))
            self._call(lib.vi_model_set_param(self._m, b"damping.beta", float(beta)))
        self._call(lib.vi_model_setup(self._m))

    # ---- builders ------------------------------------------------------
    @classmethod
    def chain(cls, n: int, m: ArrayLike = 1.0, k: ArrayLike = 1.0, c: ArrayLike = 0.0,
              stops: Optional[List[Mapping[str, Any]]] = None,
              forcing: Optional[Mapping[str, Any]] = None, *, band: bool = False,
              rayleigh=None) -> "Model":
        """The paper's fixed-free chain of n masses (the scene key model.chain):
        element j joins mass j-1 (mass 0 to the ground) to mass j with spring
        k_j and dashpot c_j; m, k, c scalars or length-n vectors.  band=True
        keeps the matrices in band storage (long chains: O(n) per step, no
        modes: the exact method and orbits need the dense form)."""
        n = int(n)
        if n < 1:
            raise Error("a chain needs n >= 1 masses", lib.VI_ERR_DIM)
        _check_memory(n, 1 if band else -1)
        mv, kv, cv = (_dvec(v, n, name) for v, name in ((m, "m"), (k, "k"), (c, "c")))
        if band:
            mp = ffi.new("vi_model **")
            st = lib.vi_model_create_chain(n, _ptr(mv), _ptr(kv), _ptr(cv), mp)
            check(st, what="chain")
            self = cls.__new__(cls)
            self._generation = 0
            self._lock = threading.Lock()
            self._fe = None
            self._m = _own(mp[0], lib.vi_model_destroy, "vi_model")
            self.n = self.dofs = n
            self._configure(stops or [], forcing, rayleigh)
            return self
        M = np.zeros((n, n), order="F")
        C = np.zeros((n, n), order="F")
        K = np.zeros((n, n), order="F")
        check(lib.vi_build_chain(n, _ptr(mv), _ptr(kv), _ptr(cv), _ptr(M), _ptr(C),
                                 _ptr(K), n), what="chain")
        return cls(M=M, C=C, K=K, stops=stops, forcing=forcing, rayleigh=rayleigh)

    @classmethod
    def cantilever(cls, modes: int, omega1: float = 1.0, zeta: float = 0.0, *,
                   xs: float = 0.1, r: float = 0.7, xi_stop: float = 1.0,
                   base: Optional[float] = None, omega: Optional[float] = None,
                   forcing: Optional[Mapping[str, Any]] = None) -> "Model":
        """The paper's clamped-free Euler-Bernoulli cantilever in its first
        ``modes`` modes (the scene key model.cantilever, vi_build_cantilever):
        omega_j = omega1 (beta_j / beta_1)^2, modal damping zeta, the stop at
        xi_stop along the span (1: the tip) at x_s with restitution r.  A base
        acceleration ``base`` cos(omega t) gives the forcing a = -base gamma;
        or pass modal ``forcing`` yourself.  Coordinates are modal."""
        k = int(modes)
        if not 1 <= k <= 201:
            raise Error("a cantilever has 1..201 modes, not %d" % k, lib.VI_ERR_DIM)
        M, C, K = (np.zeros((k, k), order="F") for _ in range(3))
        w, gamma = np.zeros(k), np.zeros(k)
        check(lib.vi_build_cantilever(k, float(omega1), float(zeta), float(xi_stop), _ptr(M),
                                      _ptr(C), _ptr(K), k, _ptr(w), _ptr(gamma)),
              what="cantilever")
        if base is not None:
            if omega is None:
                raise Error("a base acceleration needs its frequency omega", lib.VI_ERR_FREQUENCY)
            forcing = {"omega": omega, "a": -float(base) * gamma}
        return cls(M=M, C=C, K=K, stops=[{"w": w, "xs": xs, "r": r}], forcing=forcing)

    @classmethod
    def from_sparse(cls, M, K, C=None, *, modes: Optional[int] = None,
                    zeta: Optional[ArrayLike] = None, rayleigh=None,
                    stops: Optional[List[Mapping[str, Any]]] = None,
                    forcing: Optional[Mapping[str, Any]] = None,
                    rigid_modes: Optional[int] = None, accuracy: Optional[float] = None,
                    keep_shapes: bool = True) -> "Model":
        """A finite-element structure from scipy.sparse M, K (and C), reduced
        by the library (vi_sparse.h) to its ``modes`` lowest modes
        (shift-invert Lanczos on a sparse Cholesky factor; None: every finite
        mode, up to 1000 dofs).  The model's coordinates are then modal
        (x ~ Psi q); stops and forcing are given in physical dofs:
        ``{"dof": i (0-based), "direction": +1 | -1, "xs": .., "r": ..}`` or
        ``{"w": w (length dofs), ...}``; forcing vectors have length dofs.
        zeta: modal damping ratio(s) (one, or one per mode); rayleigh:
        (alpha, beta); C: a sparse damping matrix.  keep_shapes keeps Psi
        so that simulate() takes physical x0, v0 and to_physical() works."""
        import scipy.sparse as sp
        Ms = sp.csc_matrix(M, dtype=np.float64)
        Ks = sp.csc_matrix(K, dtype=np.float64)
        n = Ks.shape[0]
        if Ks.shape != (n, n) or Ms.shape != (n, n):
            raise Error("M and K must be square and of one size (%s, %s)"
                        % (Ms.shape, Ks.shape), lib.VI_ERR_DIM)
        fp = ffi.new("vi_fe **")
        check(lib.vi_fe_create(n, fp), what="vi_fe_create")
        fe = _own(fp[0], lib.vi_fe_destroy, "vi_fe")

        def call(st):
            if st < 0:
                raise Error(_s(lib.vi_fe_errmsg(fe)) or _s(lib.vi_strerror(st)), st)

        keep = []  # arrays the library reads during each call

        def set_csc(setter, A):
            A = sp.csc_matrix(A, dtype=np.float64)
            A.sum_duplicates()
            A.sort_indices()
            cp = np.ascontiguousarray(A.indptr, dtype=np.intc)
            ri = np.ascontiguousarray(A.indices, dtype=np.intc)
            va = np.ascontiguousarray(A.data, dtype=np.float64)
            keep.append((cp, ri, va))
            call(setter(fe, 0, 0, ffi.cast("int *", ffi.from_buffer(cp)),
                        ffi.cast("int *", ffi.from_buffer(ri)), _ptr(va)))

        set_csc(lib.vi_fe_set_mass_csc, Ms)
        set_csc(lib.vi_fe_set_stiffness_csc, Ks)
        if modes is not None:
            call(lib.vi_fe_set_modes(fe, int(modes)))
        if C is not None:
            set_csc(lib.vi_fe_set_damping_csc, C)
        elif rayleigh is not None:
            call(lib.vi_fe_set_rayleigh(fe, float(rayleigh[0]), float(rayleigh[1])))
        elif zeta is not None:
            z = np.ascontiguousarray(np.atleast_1d(np.asarray(zeta, dtype=np.float64)))
            call(lib.vi_fe_set_modal_damping(fe, z.size, _ptr(z)))
        if rigid_modes is not None:
            call(lib.vi_fe_set_rigid_modes(fe, int(rigid_modes)))
        if accuracy is not None:
            call(lib.vi_fe_set_accuracy(fe, float(accuracy)))
        if keep_shapes:
            call(lib.vi_fe_set_keep_shapes(fe, 1))
        if not stops:
            raise Error("a model needs at least one stop", lib.VI_ERR_STOP_VECTOR)
        for k, s in enumerate(stops):
            if "dof" in s:
                call(lib.vi_fe_add_stop_dof(fe, int(s["dof"]), int(s.get("direction", 1)),
                                            float(s.get("xs", 0.0)), float(s.get("r", 1.0))))
            else:
                w = _stop_vector(s, n, k)
                call(lib.vi_fe_add_stop(fe, _ptr(w), float(s.get("xs", 0.0)),
                                        float(s.get("r", 1.0))))
        if forcing:
            vec = [_dvec(forcing.get(k), n, "forcing." + k) for k in ("a", "b", "f0")]
            call(lib.vi_fe_set_forcing(fe, float(forcing.get("omega", 0.0)),
                                       *[_ptr(v) for v in vec]))
        call(lib.vi_fe_setup(fe))
        mp = ffi.new("vi_model **")
        call(lib.vi_fe_create_model(fe, mp))
        return cls(_handle=_own(mp[0], lib.vi_model_destroy, "vi_model"), _fe=fe,
                   _dofs=n)

    # ---- queries -------------------------------------------------------
    def _view(self, p, shape) -> np.ndarray:
        if p == ffi.NULL:
            return None
        size = int(np.prod(shape))
        a = np.frombuffer(ffi.buffer(p, size * 8), dtype=np.float64).copy()
        return a.reshape(shape[::-1]).T if len(shape) == 2 else a

    @property
    def omega(self) -> Optional[np.ndarray]:
        """Natural frequencies (rad per time unit), ascending; None for band models."""
        return self._view(lib.vi_model_omega(self._m), (self.n,))

    @property
    def zeta(self) -> Optional[np.ndarray]:
        """Modal damping ratios."""
        return self._view(lib.vi_model_zeta(self._m), (self.n,))

    @property
    def shapes(self) -> Optional[np.ndarray]:
        """Mass-normalised mode shapes Psi (n x n, column j = mode j)."""
        ld = ffi.new("int *")
        return self._view(lib.vi_model_modal_shapes(self._m, ld), (self.n, self.n))

    @property
    def M(self) -> Optional[np.ndarray]:
        return self._view(lib.vi_model_mass(self._m), (self.n, self.n))

    @property
    def C(self) -> Optional[np.ndarray]:
        return self._view(lib.vi_model_damping(self._m), (self.n, self.n))

    @property
    def K(self) -> Optional[np.ndarray]:
        return self._view(lib.vi_model_stiffness(self._m), (self.n, self.n))

    @property
    def forcing_omega(self) -> float:
        return lib.vi_model_omega_forcing(self._m)

    @property
    def period(self) -> float:
        """The forcing period 2 pi / omega (inf without harmonic forcing)."""
        w = self.forcing_omega
        return 2 * math.pi / w if w > 0 else math.inf

    @property
    def fe_omega(self) -> Optional[np.ndarray]:
        """The FE reduction's kept natural frequencies (from_sparse models)."""
        if self._fe is None:
            return None
        return self._view(lib.vi_fe_omega(self._fe), (lib.vi_fe_num_modes(self._fe),))

    def fe_summary(self) -> Dict[str, Any]:
        """What the FE reduction did: modes kept, rule, massless dofs, rigid
        modes, orthogonality and largest mode residual."""
        if self._fe is None:
            raise Error("not a from_sparse model", lib.VI_ERR_UNSUPPORTED)
        a, b, c = ffi.new("int *"), ffi.new("int *"), ffi.new("int *")
        o = ffi.new("double *")
        check(lib.vi_fe_summary(self._fe, a, b, c, o))
        return {"modes": lib.vi_fe_num_modes(self._fe), "dofs": self.dofs,
                "massless": a[0], "rigid": b[0],
                "rule": {0: "whole", 1: "given", 2: "host"}.get(c[0], c[0]),
                "orthogonality": o[0], "max_residual": lib.vi_fe_residual(self._fe)}

    def to_modal(self, x: ArrayLike) -> np.ndarray:
        """Modal coordinates q = Psi^T M x of physical dofs x (from_sparse
        models kept with keep_shapes=True)."""
        if self._fe is None:
            return np.array(_dvec(x, self.n, "x"))
        xv = _dvec(x, self.dofs, "x")
        q = np.empty(self.n)
        st = lib.vi_fe_to_modal(self._fe, _ptr(xv), _ptr(q))
        if st < 0:
            raise Error(_s(lib.vi_fe_errmsg(self._fe)) or _s(lib.vi_strerror(st)), st)
        return q

    def to_physical(self, q: ArrayLike) -> np.ndarray:
        """Physical dofs x = Psi q (rows of q: one state each) of a from_sparse model."""
        if self._fe is None:
            return np.asarray(q, dtype=np.float64).copy()
        ld = ffi.new("int *")
        p = lib.vi_fe_shapes(self._fe, ld)
        if p == ffi.NULL:
            raise Error("the mode shapes were not kept (keep_shapes=False)", lib.VI_ERR_STATE)
        Psi = self._view(p, (self.dofs, self.n))
        return np.asarray(q, dtype=np.float64) @ Psi.T

    # ---- parameters ----------------------------------------------------
    def set_param(self, key: str, value: float) -> None:
        """Change one number by its key, redoing only what it touches
        (vi_param.h: forcing.omega, forcing.a[i], stop.xs, stop.r,
        stops[k].r, damping.alpha, damping.zeta, mass.scale,
        stiffness.scale, ...; indices 1-based as in scenes).  Do not call
        it while another thread runs this model: copy() it instead.  While
        a result of an earlier run still holds the C model (the library
        refuses to change a held model), this Model goes on with a changed
        copy and the result keeps the model it ran on."""
        with self._lock:
            st = lib.vi_model_set_param(self._m, key.encode(), float(value))
            if st == lib.VI_ERR_STATE:
                # a result's simulation still holds the model (the library
                # keeps a held model immutable): change a copy, which this
                # Model becomes; the results keep the model they ran on
                mp = ffi.new("vi_model **")
                if lib.vi_model_copy(self._m, mp) == 0:
                    new = _own(mp[0], lib.vi_model_destroy, "vi_model")
                    st = lib.vi_model_set_param(new, key.encode(), float(value))
                    if st:
                        raise Error(_s(lib.vi_model_errmsg(new)) or _s(lib.vi_strerror(st)), st)
                    # views made before (omega, shapes, ...) still read the old one
                    self.__dict__.setdefault("_former", []).append(self._m)
                    self._m = new
            self._call(st)
            self._generation += 1

    def get_param(self, key: str) -> float:
        """The current value of a parameter key."""
        v = ffi.new("double *")
        self._call(lib.vi_model_param(self._m, key.encode(), v))
        return v[0]

    def copy(self) -> "Model":
        """An independent deep copy (for another thread's parameter changes)."""
        mp = ffi.new("vi_model **")
        check(lib.vi_model_copy(self._m, mp), what="copy")
        return Model(_handle=_own(mp[0], lib.vi_model_destroy, "vi_model"), _fe=self._fe,
                     _dofs=self.dofs)

    def energy(self, x: ArrayLike, v: ArrayLike) -> float:
        """1/2 v^T M v + 1/2 x^T K x."""
        return lib.vi_model_energy(self._m, _ptr(_dvec(x, self.n, "x")),
                                   _ptr(_dvec(v, self.n, "v")))

    # ---- runs ----------------------------------------------------------
    def simulate(self, t_end: Optional[float] = None, *, periods: Optional[float] = None,
                 x0: Optional[ArrayLike] = None, v0: Optional[ArrayLike] = None,
                 q0: Optional[ArrayLike] = None, qd0: Optional[ArrayLike] = None,
                 t0: float = 0.0, method: Union[str, int] = "auto", rtol: float = 1e-8,
                 atol: float = 1e-10, impact_resolution: Optional[float] = None,
                 samples_per_period: int = 0, sample_dt: float = 0.0,
                 ledger: bool = False, states: bool = True,
                 max_step: Optional[float] = None,
                 springs: Optional[Iterable[Mapping[str, Any]]] = None) -> Result:
        """Simulate from (t0, x0, v0) to t_end (or t0 + periods forcing periods).

        Events come back as arrays (Result.impacts), not one Python call per
        impact; the GIL is released during the run, so threads run in
        parallel; Ctrl-C cancels it and raises KeyboardInterrupt.

        x0, v0 are the model's coordinates, physical dofs for a from_sparse
        model (projected on the kept modes; q0, qd0 give modal ones); a
        scalar is taken for every coordinate.  samples_per_period (or
        sample_dt) samples the state uniformly; ledger=True keeps the
        per-mode energy ledger; states=False leaves the events' states
        out (faster on large models).  springs: built-in nonlinear springs,
        ``{"type": "cubic", "i": i, "j": j, "k3": k3}`` or
        ``{"type": "bilinear", "i", "j", "k", "gap"}`` (1-based, j = 0
        the ground)."""
        if t_end is None:
            if periods is None:
                raise Error("simulate needs t_end or periods", lib.VI_ERR_TIME)
            if not self.forcing_omega > 0:
                raise Error("periods needs harmonic forcing (forcing.omega)", lib.VI_ERR_FREQUENCY)
            t_end = t0 + periods * self.period
        meth = _METHOD_IDS.get(method)
        if meth is None:
            meth = _method(method)
        sim = _new_sim(self)
        if impact_resolution is not None:
            _sim_check(sim, lib.vi_sim_set_impact_resolution(sim, float(impact_resolution)))
        if max_step is not None:
            _sim_check(sim, lib.vi_sim_set_max_step(sim, float(max_step)))
        for s in springs or ():
            typ = {"cubic": 0, "bilinear": 1}[s.get("type", "cubic")]
            kk = s.get("k3", s.get("k", 0.0))
            _sim_check(sim, lib.vi_sim_add_spring(sim, typ, int(s["i"]), int(s.get("j", 0)),
                                                  float(kk), float(s.get("gap", 0.0))))
        if x0 is not None or v0 is not None or q0 is not None or qd0 is not None or t0:
            if self._fe is not None:
                q0 = self.to_modal(x0) if x0 is not None else q0
                qd0 = self.to_modal(v0) if v0 is not None else qd0
            else:
                q0 = x0 if x0 is not None else q0
                qd0 = v0 if v0 is not None else qd0
            xa, va = _dvec(q0, self.n, "x0"), _dvec(qd0, self.n, "v0")
            _sim_check(sim, lib.vi_sim_set_initial(sim, float(t0), _ptr(xa), _ptr(va)))
        dt = sample_dt
        if samples_per_period:
            period = self.period if self.forcing_omega > 0 else (t_end - t0) / 100
            dt = period / samples_per_period
        return _simulate(self, sim, float(t_end), meth, float(rtol), float(atol),
                         samples_dt=float(dt), ledger=ledger, states=states)

    def __repr__(self):
        kind = "FE reduction of %d dofs to %d modes" % (self.dofs, self.n) if self._fe is not None \
            else "%d coordinates" % self.n
        return "<vibroimpact.Model: %s, %d stop(s), Omega = %g>" % (
            kind, lib.vi_model_num_stops(self._m), self.forcing_omega)


def _check_memory(n: int, kd: int) -> None:
    """Refuse, before allocating, a model this process cannot hold: the
    machine's free memory capped by the address-space limit
    (vi_scene_memory_available, the scene reader's budget)."""
    b = ffi.new("vi_int64 *")
    st = lib.vi_model_memory_estimate(n, kd, 1, 3, 0, b)
    need = float(b[0]) if st == 0 else math.inf
    avail = lib.vi_scene_memory_available() or math.inf  # 0: not known
    if need > avail:
        raise Error("a %s model of %d coordinates needs %.3g bytes, %.3g are available%s"
                    % ("band" if kd >= 0 else "dense", n, need, avail,
                       "" if kd >= 0 else " (band=True stores a chain in O(n))"), lib.VI_ERR_LIMIT)


def _stop_vector(s: Mapping[str, Any], n: int, k: int) -> np.ndarray:
    unknown = set(s) - {"w", "xs", "r", "dof", "direction", "mass"}
    if unknown:
        raise Error("stops[%d]: unknown keys %s (w | dof, direction, xs, r)"
                    % (k, sorted(unknown)), lib.VI_ERR_ARG)
    if "w" in s:
        return _dvec(s["w"], n, "stops[%d].w" % k)
    dof = s.get("dof", s.get("mass"))
    if dof is None:
        raise Error("stops[%d] needs w or dof" % k, lib.VI_ERR_STOP_VECTOR)
    dof = int(dof)
    if not 0 <= dof < n:
        raise Error("stops[%d].dof = %d outside 0..%d (0-based)" % (k, dof, n - 1), lib.VI_ERR_DIM)
    d = int(s.get("direction", 1))
    if d not in (1, -1):
        raise Error("stops[%d].direction must be +1 or -1, not %d" % (k, d), lib.VI_ERR_ARG)
    w = np.zeros(n)
    w[dof] = d
    return w


# ---- scenes ---------------------------------------------------------------
class Scene:
    """A scene file (YAML, doc/cli.md): plain, validated data.  Read with
    load_scene(path) or parse_scene(text).  ``run()`` simulates it as
    ``vibroimpact run`` does."""

    def __init__(self, handle, name: str, path: Optional[str] = None):
        self._sc = handle
        self.path = path
        self._name = name

    @property
    def name(self) -> str:
        return _s(lib.vi_scene_name(self._sc))

    @property
    def text(self) -> str:
        return _s(lib.vi_scene_text(self._sc))

    @property
    def n(self) -> int:
        return lib.vi_scene_n(self._sc)

    @property
    def t_end(self) -> float:
        return lib.vi_scene_t_end(self._sc)

    def with_settings(self, settings: Mapping[str, Any], *, max_memory: float = 0) -> "Scene":
        """A new scene with keys changed as ``--set KEY=VALUE`` does
        (``{"forcing.omega": 0.8, "stop.r": 0.5, "forcing.a[1]": 1}``);
        its vectors checked against max_memory bytes (0: the machine's
        MemAvailable) before they are allocated, as load_scene."""
        d = ffi.new("vi_diag *")
        ep = ffi.new("vi_scene_edit **")
        text = self.text.encode()
        st = lib.vi_scene_edit_create(text, len(text), self._name.encode(), ep, d)
        if st:
            raise diag_error(d, st)
        e = _own(ep[0], lib.vi_scene_edit_destroy, "vi_scene_edit")
        for k, v in settings.items():
            if isinstance(v, (list, tuple, np.ndarray)):
                v = "[" + ", ".join(repr(float(x)) for x in np.ravel(v)) + "]"
            elif isinstance(v, bool):
                v = "true" if v else "false"
            elif isinstance(v, float):
                v = repr(v)
            st = lib.vi_scene_edit_assign(e, ("%s=%s" % (k, v)).encode(), d)
            if st:
                raise diag_error(d, st)
        sp = ffi.new("vi_scene **")
        st = lib.vi_scene_edit_parse_within(e, float(max_memory), sp, d)
        if st:
            raise diag_error(d, st)
        return Scene(_own(sp[0], lib.vi_scene_destroy, "vi_scene"), self._name, self.path)

    def _copy(self) -> "Scene":
        return self.with_settings({})

    def model(self, max_memory: float = 0) -> Model:
        """The scene's model, built and set up (its keys' errors name the
        line), after checking the memory it needs against max_memory bytes
        (0: the machine's MemAvailable), as the program's --max-memory."""
        d = ffi.new("vi_diag *")
        st = lib.vi_scene_check_memory(self._sc, float(max_memory), d)
        mp = ffi.new("vi_model **")
        if not st:
            st = lib.vi_scene_create_model(self._sc, mp, d)
        if st:
            raise diag_error(d, st)
        return Model(_handle=_own(mp[0], lib.vi_model_destroy, "vi_model"),
                     _dofs=lib.vi_scene_dofs(self._sc))

    def run(self, method: Optional[Union[str, int]] = None, rtol: Optional[float] = None,
            atol: Optional[float] = None, periods: Optional[float] = None, *,
            ledger: Optional[bool] = None, samples_per_period: Optional[int] = None,
            states: bool = True, max_memory: float = 0, **settings: Any) -> Result:
        """Simulate the scene as ``vibroimpact run`` does, with its method,
        tolerances, initial state and outputs; arguments override the
        scene's run section (as --method, --rtol, --atol, --periods), and
        keyword settings named by scene key override the scene's keys
        (``scene.run(**{"forcing.omega": 0.8})``, as --set).  A model that
        needs more than max_memory bytes (0: the machine's MemAvailable) is
        refused before anything is allocated (--max-memory)."""
        sc = self.with_settings(settings) if settings else self
        if any(v is not None for v in (method, rtol, atol, periods)):
            if sc is self:
                sc = self._copy()
            st = lib.vi_scene_set_run(sc._sc, float(rtol or 0), float(atol or 0),
                                      float(periods or 0),
                                      -1 if method is None else _method(method))
            if st:
                raise Error("run overrides refused: %s" % _s(lib.vi_strerror(st)), st)
        model = sc.model(max_memory)
        sim = _new_sim(model)
        d = ffi.new("vi_diag *")
        st = lib.vi_scene_configure_sim(sc._sc, sim, d)
        if st:
            if not ffi.string(d.message):
                msg = lib.vi_sim_errmsg(sim)
                ffi.memmove(d.message, msg, min(len(ffi.string(msg)), 511))
            raise diag_error(d, st)
        outs = lib.vi_scene_outputs(sc._sc)
        if ledger is None:
            ledger = bool(outs & 2)
        spp = lib.vi_scene_samples_per_period(sc._sc) if samples_per_period is None \
            else samples_per_period
        t0, t_end = lib.vi_scene_t0(sc._sc), lib.vi_scene_t_end(sc._sc)
        w = model.forcing_omega
        period = 2 * math.pi / w if w > 0 else (t_end - t0) / 100
        dt = period / spp if spp and spp > 0 else 0.0
        return _simulate(model, sim, t_end, lib.vi_scene_method(sc._sc),
                         lib.vi_scene_rtol(sc._sc), lib.vi_scene_atol(sc._sc),
                         samples_dt=dt, ledger=ledger, states=states, scene=sc)

    def __repr__(self):
        return "<vibroimpact.Scene %r (n = %d)>" % (self.name, self.n)


def load_scene(path: Union[str, os.PathLike], *, max_bytes: int = 0, max_depth: int = 0,
               max_memory: float = 0) -> Scene:
    """Read and validate a scene file.  Raises vibroimpact.Error naming the
    file, line, column, key and value of what is wrong.  The scene's own
    vectors (56 bytes per dof) are checked against max_memory bytes (0:
    the machine's MemAvailable) before they are allocated, so that a
    matrix file whose header claims a huge n is refused at once, as the
    program's --max-memory does."""
    p = os.fspath(path)
    d = ffi.new("vi_diag *")
    sp = ffi.new("vi_scene **")
    st = lib.vi_scene_load_within(os.fsencode(p), int(max_bytes), int(max_depth),
                                  float(max_memory), sp, d)
    if st:
        raise diag_error(d, st)
    return Scene(_own(sp[0], lib.vi_scene_destroy, "vi_scene"), p, p)


def parse_scene(text: str, name: str = "<string>") -> Scene:
    """A scene from YAML text (``name`` stands for the file in messages;
    relative matrix files are found from the working directory)."""
    d = ffi.new("vi_diag *")
    sp = ffi.new("vi_scene **")
    b = text.encode()
    st = lib.vi_scene_parse(b, len(b), name.encode(), sp, d)
    if st:
        raise diag_error(d, st)
    return Scene(_own(sp[0], lib.vi_scene_destroy, "vi_scene"), name)


def default_scene() -> Scene:
    """The embedded default scene: the paper's Fig. 2."""
    return parse_scene(_s(lib.vi_scene_default_text()), "<default scene: fig2>")

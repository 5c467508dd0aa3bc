"""vibroimpact: multi-degree-of-freedom vibro-impact systems in Python.

A thin layer over the C library (libvibroimpact, its scene and HDF5
companions): models from numpy or scipy.sparse matrices, scenes from YAML
files, the exact closed-form integrator and the SUNDIALS methods, events
returned as numpy arrays, and the library's parameter studies.

    import vibroimpact as vi
    res = vi.load_scene("share/scenes/fig2.yaml").run()
    res.impacts["t"], res.impacts["vn"]

    m = vi.Model.chain(2, m=1, k=1, c=0.1,
                       stops=[{"w": [0, 1], "xs": 0.1, "r": 0.7}],
                       forcing={"omega": 0.9, "a": [0.5, 0]})
    res = m.simulate(periods=100, method="exact", rtol=1e-10, atol=1e-12)

Errors raise vibroimpact.Error (message, status, and for scenes file,
line, key).  The guide: doc/python.md.
"""
from ._errors import Error, strerror
from ._core import (METHODS, Model, Result, Scene, default_scene, load_scene,
                    parse_scene)
from ._vi import ffi as _ffi, lib as _lib
from .studies import (basins, continuation, curve, energy, identify, orbits, sweep,
                      truncated_model, truncation, truncation_study)

__version__ = _ffi.string(_lib.vi_version_string()).decode()


def library_version() -> str:
    """Version of the C library this package runs (and of SUNDIALS under it)."""
    return "%s (SUNDIALS %s)" % (__version__, _ffi.string(_lib.vi_sundials_version()).decode())


__all__ = ["Error", "Model", "Result", "Scene", "load_scene", "parse_scene",
           "default_scene", "strerror", "METHODS", "library_version", "sweep",
           "basins", "orbits", "continuation", "curve", "energy", "truncation",
           "truncated_model", "truncation_study", "identify"]

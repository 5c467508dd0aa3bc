"""Build of the Python package vibroimpact over the C library.

The C library comes from a CMake build of this repository, found in this
order: $VIBROIMPACT_BUILD_DIR, ../build/rel, ../build/test-release,
../build/python; if none holds it, ../build/python is configured and built
(Release, the three libraries only).  The extension records the library's
folder as its run path, so the build folder must stay where it is."""
import os
import subprocess
import sys

from setuptools import setup

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
LIBS = ("libvibroimpact.so", "libvibroimpact_scene.so", "libvibroimpact_h5.so")


def _complete(d):
    return all(os.path.exists(os.path.join(d, f)) for f in LIBS) and \
        os.path.exists(os.path.join(d, "include", "vibroimpact", "vi_export.h"))


def find_library():
    """The CMake build folder holding the three libraries (built if needed)."""
    env = os.environ.get("VIBROIMPACT_BUILD_DIR")
    if env:
        if not _complete(env):
            sys.exit("vibroimpact: VIBROIMPACT_BUILD_DIR=%s holds no built "
                     "library (%s)" % (env, ", ".join(LIBS)))
        return os.path.abspath(env)
    for name in ("rel", "test-release", "python"):
        d = os.path.join(ROOT, "build", name)
        if _complete(d):
            return d
    d = os.path.join(ROOT, "build", "python")
    print("vibroimpact: building the C library in %s" % d, flush=True)
    subprocess.check_call(["cmake", "-S", ROOT, "-B", d,
                           "-DCMAKE_BUILD_TYPE=Release", "-DVI_BUILD_TESTS=OFF"])
    subprocess.check_call(["cmake", "--build", d, "-j%d" % (os.cpu_count() or 1),
                           "--target", "vibroimpact", "vibroimpact_scene",
                           "vibroimpact_h5"])
    return d


if "egg_info" not in sys.argv and "dist_info" not in sys.argv:
    build = find_library()
    os.environ["VI_PY_INCLUDE"] = os.pathsep.join(
        [os.path.join(ROOT, "include"), os.path.join(build, "include")])
    os.environ["VI_PY_LIBDIR"] = build

setup(cffi_modules=["_vi_build.py:ffibuilder"])

#!/usr/bin/env bash
# Build the Python package against a CMake build of the library and run its
# tests: a venv that sees Debian's numpy, scipy, cffi and pytest
# (--system-site-packages), pip install --no-build-isolation --no-index (no
# package registry is needed), pytest from outside the source folder so the
# installed package is the one imported.  The venv gets no pip of its own
# (ensurepip cost 5.5 of the suite's 27 CPU-s): Debian's python3-pip, seen
# through the system's site-packages, installs into it.
#   python/run-tests.sh BUILD_DIR [pytest arguments]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=$(cd "$1" && pwd)
shift
venv="$build/python-venv"
# setuptools' object cache knows no header dependencies: start clean
rm -rf "$here/build" "$here/vibroimpact.egg-info"
[ -x "$venv/bin/python" ] || /usr/bin/python3 -m venv --without-pip --system-site-packages "$venv"
# -g0: the wrapper's debug information (Python's own flags ask for -g) is
# nobody's here, and a fifth of its compile time
CFLAGS="${CFLAGS:-} -g0" VIBROIMPACT_BUILD_DIR="$build" "$venv/bin/python" -m pip install -q \
  --no-build-isolation --no-index --force-reinstall --no-deps "$here"
cd "$here/tests"
VIBROIMPACT_PROGRAM="$build/vibroimpact" "$venv/bin/python" -m pytest -q "$@"

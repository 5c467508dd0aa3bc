#!/usr/bin/env bash
# Build and run every test twice: a warning-free (-Werror) Release build, and
# an AddressSanitizer + UndefinedBehaviorSanitizer build (asserts on).
#  - The packaging tests (install, outside consumers, exported symbols) run
#    in the Release build only: consumers of a sanitized library need its
#    runtime.
#  - So does the lint (clang-tidy, cppcheck): it reads the sources, not the
#    binaries, and the Release flags leave it the most to check (with NDEBUG
#    no assert() tells the analyser what holds); the sanitizer flags change
#    nothing it reads.  Its files are checked on every core.
#  - So do the figure tests (label plot): what they add to the program's
#    runs, which the sanitized build's own tests make (sweep, basins,
#    curves, truncation and run with -o), is matplotlib drawing in Python,
#    which no sanitizer sees (18 CPU-s of a sanitized run).
#  - So do the checks against mpmath's closed forms (label reference):
#    most of their time is the Python reference, which no sanitizer sees;
#    the sanitized build runs the same invocations of the program with
#    cheap checks (curves_runs, tests/CMakeLists.txt).
#  - The sanitized build is compiled at -O1, the level AddressSanitizer's
#    documentation advises for speed (at -O0 its slowest tests took about
#    ten times as long), with -g1: the line tables its reports' file:line
#    need, without the variables' debug information nobody reads here
#    (14 % less compile time: vi_sim.c 2.20 -> 1.88 CPU-s).  The tests'
#    own code is compiled at -O0 there (tests/CMakeLists.txt says why).
#  - It compiles while the Release tests run, and its tests follow; the
#    Python package's tests run beside them (their output at the end).
# About 720-790 CPU-seconds on a 2-core machine once SUNDIALS is built (README.md).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
"$root/share/scripts/deps.sh"
jobs=$(nproc)
rel="$root/build/test-release" asan="$root/build/test-asan"
quiet() { grep -Ev '^\[|^Consolidate|^Scanning|^Built target' || true; }
echo "== configure"
mkdir -p "$root/build"
# the two configurations side by side (cmake's checks use one core each)
"$root/share/scripts/configure.sh" "$asan" "$root" -DCMAKE_BUILD_TYPE=Debug -DVI_WERROR=ON -DVI_SANITIZE=ON \
  -DCMAKE_C_FLAGS_DEBUG="-g1 -O1" \
  -DCMAKE_Fortran_FLAGS_DEBUG="-g1 -O1" >"$root/build/asan-configure.log" 2>&1 &
configurer=$!
"$root/share/scripts/configure.sh" "$rel" "$root" -DCMAKE_BUILD_TYPE=Release -DVI_WERROR=ON >/dev/null
if ! wait "$configurer"; then
  cat "$root/build/asan-configure.log"
  echo "the asan configuration failed"
  exit 1
fi
echo "== release build"
cmake --build "$rel" -j"$jobs" 2>&1 | quiet
status=0
# the sanitized build and the Python package's tests (one core, against
# the release build) in the background, their output kept for the end
log="$asan/build.log" pylog="$rel/python-tests.log"
( cmake --build "$asan" -j"$jobs" >"$log" 2>&1; echo $? >"$log.rc" ) &
builder=$!
( "$root/python/run-tests.sh" "$rel" >"$pylog" 2>&1; echo $? >"$pylog.rc" ) &
pytests=$!
echo "== release tests (the asan build and the python tests run meanwhile)"
ctest --test-dir "$rel" --output-on-failure -j"$jobs" || status=1
wait "$builder" || true
echo "== asan build"
quiet <"$log"
if [ "$(cat "$log.rc")" != 0 ]; then
  echo "the asan build failed"
  wait "$pytests" || true
  exit 1
fi
echo "== asan tests"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 \
UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir "$asan" --output-on-failure -j"$jobs" -LE 'packaging|lint|plot|reference' || status=1
wait "$pytests" || true
echo "== python package (pytest, against the release build)"
cat "$pylog"
[ "$(cat "$pylog.rc")" = 0 ] || status=1
exit $status

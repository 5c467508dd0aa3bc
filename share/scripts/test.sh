#!/usr/bin/env bash
# Build and run every test twice: a warning-free (-Werror) Release build, and
# an AddressSanitizer + UndefinedBehaviorSanitizer Debug build.  The
# packaging tests (install, outside consumers, exported symbols) run in the
# Release build only: consumers of a sanitized library need its runtime.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
"$root/share/scripts/deps.sh"
jobs=$(nproc)
status=0
for cfg in release asan; do
  dir="$root/build/test-$cfg"
  if [ "$cfg" = release ]; then
    flags=(-DCMAKE_BUILD_TYPE=Release -DVI_WERROR=ON)
    select=()
  else
    flags=(-DCMAKE_BUILD_TYPE=Debug -DVI_WERROR=ON -DVI_SANITIZE=ON)
    select=(-LE packaging)
  fi
  echo "== $cfg build"
  cmake -S "$root" -B "$dir" "${flags[@]}" >/dev/null
  cmake --build "$dir" -j"$jobs" 2>&1 | grep -Ev '^\[|^Consolidate|^Scanning|^Built target' || true
  echo "== $cfg tests"
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 \
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    ctest --test-dir "$dir" --output-on-failure -j"$jobs" "${select[@]}" || status=1
done
exit $status

#!/usr/bin/env bash
# configure.sh BUILD SRC [cmake options...]: configure SRC into BUILD with
# Ninja (Debian's ninja-build, installed by deps.sh).  On a 2-core machine a
# full build of the suite is 60 s either way, but Ninja's own overhead is
# smaller than make's recursive one (about 7 CPU-s of 117) and it keeps both
# cores busy to the end.  A build directory that another generator made is
# removed first: cmake refuses to switch generators in place.
set -euo pipefail
build=$1 src=$2
shift 2
if [ -f "$build/CMakeCache.txt" ] &&
   ! grep -qx 'CMAKE_GENERATOR:INTERNAL=Ninja' "$build/CMakeCache.txt"; then
  rm -rf "$build"
fi
exec cmake -G Ninja -S "$src" -B "$build" "$@"

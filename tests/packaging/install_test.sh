#!/usr/bin/env bash
# Install the build tree into a temporary prefix, then build and run two
# outside consumers against it: C with CMake's find_package, Fortran with
# pkg-config and a plain gfortran command line.
set -euo pipefail
build=$1 src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cmake --install "$build" --prefix "$tmp/prefix" >/dev/null
libdir=$(dirname "$(find "$tmp/prefix" -name libvibroimpact.so | head -n1)")
export LD_LIBRARY_PATH="$libdir${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"

echo "== C consumer (find_package)"
cmake -S "$src/tests/consumers/c" -B "$tmp/c" -DCMAKE_PREFIX_PATH="$tmp/prefix" >/dev/null
cmake --build "$tmp/c" >/dev/null
"$tmp/c/consumer"

echo "== Fortran consumer (pkg-config)"
export PKG_CONFIG_PATH="$libdir/pkgconfig"
gfortran "$src/tests/consumers/fortran/main.f90" -o "$tmp/fconsumer" \
  $(pkg-config --cflags --libs vibroimpact-fortran)
"$tmp/fconsumer"

echo "== C with pkg-config, static archive"
gcc -std=c99 "$src/tests/consumers/c/main.c" -o "$tmp/cstatic" \
  $(pkg-config --cflags vibroimpact) "$libdir/libvibroimpact.a" \
  $(pkg-config --static --libs-only-l vibroimpact | sed 's/-lvibroimpact//') -lm
"$tmp/cstatic"
echo "1 passed, 0 failed"

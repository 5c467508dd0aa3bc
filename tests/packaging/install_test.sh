#!/usr/bin/env bash
# Install the build tree into a temporary prefix, then build and run
# outside consumers against it: C with CMake's find_package (the core, the
# scene and HDF5 libraries, and vibroimpact::io), Fortran with
# find_package (vibroimpact::fortran), C and Fortran with pkg-config and a
# plain compiler command line.
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
"$tmp/c/consumer_scene"
"$tmp/c/consumer_h5" "$tmp/h5.h5"
"$tmp/c/consumer_io" "$tmp/io.h5"
"$tmp/c/consumer_io_old" "$tmp/io_old.h5"
# the scene library needs no HDF5, the HDF5 one brings the scene library
if readelf -d "$tmp/c/consumer_scene" | grep 'libvibroimpact_h5\|libhdf5' >/dev/null; then
  echo "FAIL: consumer_scene links HDF5"; exit 1
fi

echo "== Fortran consumer (find_package, vibroimpact::fortran)"
cmake -S "$src/tests/consumers/fortran" -B "$tmp/f" -DCMAKE_PREFIX_PATH="$tmp/prefix" >/dev/null
cmake --build "$tmp/f" >/dev/null
"$tmp/f/fconsumer"
"$tmp/f/fconsumer_old"

echo "== Fortran consumer (pkg-config)"
export PKG_CONFIG_PATH="$libdir/pkgconfig"
gfortran "$src/tests/consumers/fortran/main.f90" -o "$tmp/fconsumer" \
  $(pkg-config --cflags --libs vibroimpact-fortran)
"$tmp/fconsumer"

echo "== C I/O with pkg-config (vibroimpact-scene, vibroimpact-h5)"
gcc -std=c99 -DSCENE_ONLY "$src/tests/consumers/c/io.c" -o "$tmp/pscene" \
  $(pkg-config --cflags --libs vibroimpact-scene)
"$tmp/pscene"
gcc -std=c99 "$src/tests/consumers/c/io.c" -o "$tmp/ph5" \
  $(pkg-config --cflags --libs vibroimpact-h5)
"$tmp/ph5" "$tmp/p.h5"

echo "== C with pkg-config, static archive"
gcc -std=c99 "$src/tests/consumers/c/main.c" -o "$tmp/cstatic" \
  $(pkg-config --cflags vibroimpact) "$libdir/libvibroimpact.a" \
  $(pkg-config --static --libs-only-l vibroimpact | sed 's/-lvibroimpact//') -lm
"$tmp/cstatic"
echo "1 passed, 0 failed"

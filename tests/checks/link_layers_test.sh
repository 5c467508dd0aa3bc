#!/usr/bin/env bash
# The libraries link one way, as the layers do (README, doc/linking.md):
#   libvibroimpact        the numerical core: no YAML, no HDF5
#   libvibroimpact_scene  YAML scenes: libyaml and the core, no HDF5
#   libvibroimpact_h5     HDF5 output: HDF5, the scene library and the core
#   vibroimpact           the program: the scene library, and the HDF5 one
#                         shared or in its static form (VI_APP_STATIC_HDF5),
#                         never opened with dlopen
# Read from each file's own DT_NEEDED list (readelf -d) and dynamic symbols.
#   link_layers_test.sh LIBVIBROIMPACT LIBSCENE LIBH5 PROGRAM
set -euo pipefail
core=$1 scene=$2 h5=$3 app=$4
fail=0
needed() { readelf -d "$1" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p'; }
has() { grep -Eq "$2" <<<"$(needed "$1")"; }
check() { # FILE PATTERN want(yes|no) what
  if has "$1" "$2"; then got=yes; else got=no; fi
  if [ "$got" != "$3" ]; then
    echo "FAIL: $(basename "$1") $4 (NEEDED: $(needed "$1" | tr '\n' ' '))"
    fail=1
  fi
}
check "$core" 'libhdf5' no "links HDF5"
check "$core" 'libyaml' no "links libyaml"
check "$scene" 'libhdf5' no "links HDF5"
check "$scene" 'libyaml' yes "does not link libyaml"
check "$scene" '^libvibroimpact\.so' yes "does not link the core"
check "$h5" 'libhdf5' yes "does not link HDF5"
check "$h5" '^libvibroimpact_scene\.so' yes "does not link the scene library"
check "$app" '^libvibroimpact_scene\.so' yes "does not link the scene library"
# no library below links one above it
check "$core" '^libvibroimpact_(scene|h5)\.so' no "links an I/O library"
check "$scene" '^libvibroimpact_h5\.so' no "links the HDF5 library"
# the program opens no I/O library itself (no dlopen trick) and takes its
# scene reader from the scene library (no private copy)
undef=$(nm -D --undefined-only "$app")
if grep -q 'libvibroimpact_io' "$app"; then
  echo "FAIL: $(basename "$app") names libvibroimpact_io (a dlopen?)"; fail=1
fi
if ! has "$app" '^libvibroimpact_h5\.so' &&
   ! grep -q ' T vi_writer_create$' <<<"$(nm "$app" 2>/dev/null)"; then
  echo "FAIL: $(basename "$app") links the HDF5 writer neither shared nor static"
  fail=1
fi
if grep -q ' T vi_scene_load$' <<<"$(nm "$app" 2>/dev/null)"; then
  echo "FAIL: $(basename "$app") carries its own scene reader"; fail=1
fi
if ! grep -Eq ' vi_scene_(load|parse)' <<<"$undef"; then
  echo "FAIL: $(basename "$app") does not take its scene reader from the scene library"
  fail=1
fi
for f in "$core" "$scene" "$h5" "$app"; do
  echo "$(basename "$f"): $(needed "$f" | grep -E 'vibroimpact|yaml|hdf5' | tr '\n' ' ')"
done
[ $fail -eq 0 ] && echo "1 passed, 0 failed"
exit $fail

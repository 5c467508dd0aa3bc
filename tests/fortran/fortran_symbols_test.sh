#!/usr/bin/env bash
# The Fortran modules bind the whole public API: every vi_ function that
# libvibroimpact, libvibroimpact_scene and libvibroimpact_h5 export has a bind(C, name="...")
# interface in src/fortran/*.f90, every such interface names an exported
# function and matches its C prototype (fortran_signatures.py: arguments,
# by value or by reference, result), and every enumerator of the public
# headers is a generated Fortran constant.  Fails listing what is wrong.
#   fortran_symbols_test.sh SRC BUILD LIB IOLIB...
set -euo pipefail
src=$1 build=$2 lib=$3
shift 3 # then the I/O libraries
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0

for l in "$lib" "$@"; do
  nm -D --defined-only "$l" | awk '$2 == "T" && $3 ~ /^vi_/ {print $3}'
done | sort -u > "$tmp/c"
grep -ho 'bind(C, *name *= *"[^"]*")' "$src"/src/fortran/*.f90 \
  | sed 's/.*"\(.*\)".*/\1/' | grep -v '^strlen$' | sort -u > "$tmp/f"

missing=$(comm -23 "$tmp/c" "$tmp/f")
stale=$(comm -13 "$tmp/c" "$tmp/f")
if [ -n "$missing" ]; then
  echo "FAIL: exported C functions without a Fortran binding in src/fortran:"
  printf '  %s\n' $missing
  fail=1
fi
if [ -n "$stale" ]; then
  echo "FAIL: Fortran bindings of functions the libraries do not export:"
  printf '  %s\n' $stale
  fail=1
fi

# Enumerators: VI_NAME = value inside the public headers' enums, and the
# status list X(VI_NAME, value, "...").
sed -n 's/^[[:space:]]*\(VI_[A-Z0-9_]*\)[[:space:]]*=[[:space:]]*-\{0,1\}[0-9].*/\1/p; s/^[[:space:]]*X(\(VI_[A-Z0-9_]*\),.*/\1/p' \
  "$src"/include/vibroimpact/*.h | sort -u > "$tmp/enum"
cat "$build"/fortran/vi_*constants.inc | sed -n 's/.*:: \(VI_[A-Z0-9_]*\) = .*/\1/p' \
  | sort -u > "$tmp/const"
nomiss=$(comm -23 "$tmp/enum" "$tmp/const")
if [ -n "$nomiss" ]; then
  echo "FAIL: enumerators of the public headers missing from src/fortran/vi_gen_constants.c:"
  printf '  %s\n' $nomiss
  fail=1
fi

# ... and each binding's arguments and result match the C prototype
python3 "$src/tests/fortran/fortran_signatures.py" "$src" || fail=1

echo "C exports: $(wc -l < "$tmp/c"), Fortran bindings: $(wc -l < "$tmp/f"), \
enumerators: $(wc -l < "$tmp/enum"), Fortran constants: $(wc -l < "$tmp/const")"
[ $fail -eq 0 ] && echo "1 passed, 0 failed"
exit $fail

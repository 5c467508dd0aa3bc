#!/bin/bash
# Every function exported by libvibroimpact and the I/O libraries
# (libvibroimpact_scene, libvibroimpact_h5) is called
# in the misuse tests (test_misuse.c, test_misuse_io.c), so that a new
# function cannot be added without its NULL / range / order checks.
# usage: misuse_coverage_test.sh TESTS_DIR LIBVIBROIMPACT IOLIB...
set -u
dir=$1
shift
files=("$dir/api/test_misuse.c" "$dir/io/test_misuse_io.c")
for f in "${files[@]}" "$@"; do
  [ -r "$f" ] || { echo "misuse_coverage: cannot read $f"; exit 1; }
done
# the names called: followed by '(' (not only a mention in a comment),
# read once
called=$(grep -ohE '\bvi_[A-Za-z0-9_]+\(' "${files[@]}" | tr -d '(' | sort -u)
missing=0 total=0
for lib in "$@"; do
  syms=$(nm -D --defined-only "$lib" | awk '$2 == "T" && $3 ~ /^vi_/ {print $3}' | sort -u)
  [ -n "$syms" ] || { echo "misuse_coverage: no vi_ symbols in $lib"; exit 1; }
  total=$((total + $(wc -l <<< "$syms")))
  while read -r s; do
    [ -n "$s" ] || continue
    echo "not called in the misuse tests: $s ($(basename "$lib"))"
    missing=$((missing + 1))
  done < <(comm -23 <(echo "$syms") <(echo "$called"))
done
echo "misuse_coverage: $((total - missing)) of $total exported functions called"
[ "$missing" -eq 0 ]

#!/usr/bin/env bash
# Build SUNDIALS' CVODES and ARKODE with optimisation (-O3) from Debian's own
# source package, of the very version libsundials-dev installed, into
# build/sundials (or $VI_SUNDIALS_PREFIX).  Debian compiles the binary
# package without optimisation, and an Adams run spends most of its time
# inside it.  The top CMakeLists.txt uses this prefix when it exists (with an
# rpath to it) and Debian's package otherwise.
#
# Where the sources cannot be had (no network, no deb-src, VI_SUNDIALS=system)
# it says so and leaves the build on Debian's binary package.
#
# A build is also kept in a cache outside the tree ($VI_SUNDIALS_CACHE, by
# default ~/.cache/vibroimpact), named by the SUNDIALS version and a hash
# of this script, the compiler and the machine: another clone on the same
# machine copies it (a second) instead of compiling it again (a minute or
# two of a 2-core machine).  Any change to the recipe or the compiler
# names another entry.  VI_SUNDIALS_CACHE=off: no cache.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
prefix=${VI_SUNDIALS_PREFIX:-$root/build/sundials}
say() { echo "vibroimpact: $*" >&2; }
fallback() {
  say "$1; using Debian's binary SUNDIALS package (built without optimisation)"
  exit 0
}

[ "${VI_SUNDIALS:-}" = system ] && fallback "VI_SUNDIALS=system"
ver=$(dpkg-query -W -f='${source:Version}' libsundials-dev 2>/dev/null) ||
  fallback "libsundials-dev is not installed"
stamp="$prefix/.vi-sundials-version"
[ -f "$stamp" ] && [ "$(cat "$stamp")" = "$ver" ] && exit 0

cache=${VI_SUNDIALS_CACHE:-${XDG_CACHE_HOME:-${HOME:-/nonexistent}/.cache}/vibroimpact}
entry=""
if [ "$cache" != off ]; then
  key=$( { cat "$0"; cc --version 2>/dev/null | head -n1; uname -m; } | sha256sum | cut -c1-16)
  entry="$cache/sundials-$ver-$key"
  # complete entries only: an entry is renamed into place after its install
  if [ -f "$entry/.vi-sundials-version" ] &&
     [ "$(cat "$entry/.vi-sundials-version")" = "$ver" ]; then
    rm -rf "$prefix"
    mkdir -p "$(dirname "$prefix")"
    if cp -a "$entry" "$prefix.tmp$$" && mv "$prefix.tmp$$" "$prefix"; then
      say "optimised SUNDIALS $ver copied from $entry"
      exit 0
    fi
    rm -rf "$prefix.tmp$$"
    say "copying $entry failed; building SUNDIALS"
  fi
fi

sudo=""
[ "$(id -u)" -ne 0 ] && sudo="sudo"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
get() { apt-get source --download-only "sundials=$ver" >/dev/null 2>&1; }
if ! get; then
  # No deb-src entry: add one mirroring the Debian 'deb' entries.
  list=/etc/apt/sources.list.d/vibroimpact-deb-src.sources
  if [ ! -f $list ]; then
    src=""
    for f in /etc/apt/sources.list.d/*.sources; do
      [ -f "$f" ] || continue
      grep -q '^URIs:.*debian' "$f" || continue
      src+=$(sed -n '/^Types:/{s/.*/Types: deb-src/;p;d};/^\(URIs\|Suites\|Components\|Signed-By\):/p;/^$/p' "$f")
      src+=$'\n\n'
    done
    if [ -z "$src" ] && [ -f /etc/apt/sources.list ]; then
      src=$(sed -n 's/^deb \(.*debian.*\)/deb-src \1/p' /etc/apt/sources.list)
      list=/etc/apt/sources.list.d/vibroimpact-deb-src.list
    fi
    [ -n "$src" ] || fallback "no Debian apt source to derive a deb-src entry from"
    say "adding Debian's source packages to apt ($list)"
    printf '%s\n' "$src" | $sudo tee "$list" >/dev/null
  fi
  $sudo apt-get update -qq >/dev/null 2>&1 || true
  get || fallback "the source package sundials $ver cannot be downloaded"
fi

orig=$(ls sundials_*.orig.tar.* | head -n1)
say "building CVODES and ARKODE $ver at -O3 into $prefix (once)"
tar xf "$orig"
srcdir=$(find . -mindepth 1 -maxdepth 1 -type d | head -n1)
# Debian's patches concern its packaging (install paths, docs, Fortran), not
# the solvers: the solvers are the upstream sources as Debian ships them.
jobs=$(nproc)
cmake -S "$srcdir" -B build -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_C_FLAGS_RELEASE="-O3 -DNDEBUG" \
  -DCMAKE_INSTALL_PREFIX="$prefix" -DCMAKE_INSTALL_LIBDIR=lib \
  -DBUILD_CVODES=ON -DBUILD_ARKODE=ON -DBUILD_CVODE=OFF -DBUILD_IDA=OFF \
  -DBUILD_IDAS=OFF -DBUILD_KINSOL=OFF -DBUILD_SHARED_LIBS=ON \
  -DBUILD_STATIC_LIBS=ON -DCMAKE_POSITION_INDEPENDENT_CODE=ON \
  -DSUNDIALS_INDEX_SIZE=64 -DSUNDIALS_PRECISION=double \
  -DEXAMPLES_ENABLE_C=OFF -DEXAMPLES_ENABLE_CXX=OFF -DEXAMPLES_INSTALL=OFF \
  -DBUILD_FORTRAN_MODULE_INTERFACE=OFF >build.log 2>&1 ||
  { tail -n 20 build.log >&2; fallback "configuring SUNDIALS failed"; }
cmake --build build -j"$jobs" >>build.log 2>&1 ||
  { tail -n 20 build.log >&2; fallback "building SUNDIALS failed"; }
rm -rf "$prefix"
cmake --install build >>build.log 2>&1 || fallback "installing SUNDIALS failed"
echo "$ver" >"$stamp"
say "optimised SUNDIALS $ver in $prefix"
# into the cache for the next clone (no cache: nothing lost)
if [ -n "$entry" ] && mkdir -p "$cache" 2>/dev/null &&
   cp -a "$prefix" "$entry.tmp$$" 2>/dev/null; then
  rm -rf "$entry"
  mv "$entry.tmp$$" "$entry" 2>/dev/null || rm -rf "$entry.tmp$$"
else
  rm -rf "$entry.tmp$$" 2>/dev/null || true
fi

#!/usr/bin/env bash
# The work-precision benchmark (not part of the tests): installs Debian's
# python3-scipy, python3-mpmath and python3-siconos, builds the library
# (Release, with the optimised SUNDIALS of share/scripts/deps.sh) and the
# driver bench/vi_wp.c, then runs bench/workprec.py, which writes
# bench/workprec.md, bench/workprec.png and bench/workprec.json.
# Takes 10-20 minutes on 2 cores.  Usage: bench/run.sh [--quick]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/share/scripts/deps.sh"
pkgs=(python3-scipy python3-mpmath python3-numpy python3-matplotlib python3-siconos)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" ||
    missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  echo "bench: installing ${missing[*]}" >&2
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  # siconos is optional: the benchmark goes on without it
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null ||
    $sudo apt-get install -y -qq --no-install-recommends \
      python3-scipy python3-mpmath python3-numpy python3-matplotlib >/dev/null
fi
build=$root/build/bench
# the optimised SUNDIALS where deps.sh put it (or $VI_SUNDIALS_PREFIX)
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DVI_BUILD_TESTS=OFF \
  -DVI_SUNDIALS_PREFIX="${VI_SUNDIALS_PREFIX:-$root/build/sundials}" >/dev/null
cmake --build "$build" -j"$(nproc)" >/dev/null
gcc -O2 -std=c99 -Wall -Wextra -D_GNU_SOURCE "$root/bench/vi_wp.c" \
  -I"$root/include" -I"$build/include" -L"$build" -lvibroimpact_h5 -lvibroimpact_scene -lvibroimpact \
  -Wl,-rpath,"$build" -o "$build/vi_wp"
gcc -O2 -shared -fPIC -Wall "$root/bench/vi_siconos_plugin.c" \
  -o "$build/vi_siconos_plugin.so" -lm
exec /usr/bin/python3 "$root/bench/workprec.py" "$build" "$@"

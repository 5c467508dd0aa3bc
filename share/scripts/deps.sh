#!/usr/bin/env bash
# Install the Debian 12 packages vibroimpact needs, only those missing.
set -euo pipefail
pkgs=(cmake ninja-build make gcc g++ gfortran binutils pkg-config libsundials-dev libgsl-dev
      liblapacke-dev libcmocka-dev libhdf5-dev libyaml-dev
      libarpack2-dev libsuitesparse-dev
      python3-h5py python3-matplotlib doxygen xz-utils)
pkgs+=(libopenmpi-dev openmpi-bin)  # vibroimpact sweep under mpirun
pkgs+=(clang clang-tidy cppcheck)    # the fuzz targets (libFuzzer) and the lint test
pkgs+=(python3-dev python3-venv python3-pip python3-setuptools python3-wheel python3-cffi
       python3-numpy python3-scipy python3-pytest)  # the Python package (python/)
pkgs+=(python3-mpmath python3-gmpy2)  # the tests' closed-form references
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" \
    || missing+=("$p")
done
export DEBIAN_FRONTEND=noninteractive
if [ ${#missing[@]} -gt 0 ]; then
  echo "vibroimpact: installing ${missing[*]}" >&2
  sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
# An optimised build of SUNDIALS from Debian's sources (once; falls back to
# the binary package where the sources cannot be had).
"$(dirname "$0")/build-sundials.sh"

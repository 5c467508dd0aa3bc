#!/usr/bin/env bash
# Install the Debian 12 packages vibroimpact needs, only those missing.
set -euo pipefail
pkgs=(cmake make gcc g++ gfortran binutils pkg-config libsundials-dev libgsl-dev
      liblapacke-dev libcmocka-dev libhdf5-dev libyaml-dev
      python3-h5py python3-matplotlib doxygen)
pkgs+=(libopenmpi-dev openmpi-bin)  # vibroimpact sweep under mpirun
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" \
    || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
echo "vibroimpact: installing ${missing[*]}" >&2
sudo=""
[ "$(id -u)" -ne 0 ] && sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null

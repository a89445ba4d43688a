#!/usr/bin/env bash
# Install every Debian package Biota needs that is not yet installed (non-interactive).
set -euo pipefail
PACKAGES=(
  cmake g++ make pkg-config git python3 python3-matplotlib python3-numpy
  libopenmpi-dev openmpi-bin
  petsc-dev
  libhdf5-openmpi-dev
  libtomlplusplus-dev librandom123-dev libcli11-dev libspdlog-dev libfmt-dev
  libgtest-dev libbenchmark-dev
  paraview-dev paraview python3-paraview xvfb xauth
  clang-format
  libembree-dev libnanoflann-dev libtinyobjloader-dev libstb-dev libpng-dev libxsimd-dev
)
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "install-deps: installing ${missing[*]}"
  SUDO=""
  [[ $(id -u) -ne 0 ]] && SUDO="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "install-deps: all ${#PACKAGES[@]} packages present"
fi

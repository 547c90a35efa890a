#!/usr/bin/env bash
# Installs everything librt needs from Debian 12 packages. Idempotent: packages
# already installed are skipped, and apt is not touched when nothing is missing.
set -euo pipefail

packages=(
  g++ cmake make pkg-config git
  libglm-dev libtinyobjloader-dev libstb-dev libtinygltf-dev nlohmann-json3-dev libtinyexr-dev
  zlib1g-dev libpng-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libcli11-dev libembree-dev
  libopenmpi-dev openmpi-bin
  libdraco-dev libmeshoptimizer-dev libwebp-dev
  pybind11-dev python3-dev python3-numpy python3-pytest
  clang libclang-rt-14-dev clang-format
  doxygen
  gnuplot-nox time
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo_cmd=()
  [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "setup: all packages present"
fi

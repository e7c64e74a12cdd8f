#!/usr/bin/env bash
# Installs the Debian 12 packages Candela builds against, plus any named as arguments (`make fuzz`: clang),
# but only those missing (quiet when all present).
set -euo pipefail
packages=(cmake ninja-build pkg-config g++ libembree-dev libtbb-dev libglm-dev libglfw3-dev libosmesa6-dev
  libegl-dev libgl-dev libgl1-mesa-dri libopenimageio-dev libtinygltf-dev libgtest-dev libgmock-dev
  libbenchmark-dev libcli11-dev nlohmann-json3-dev libimgui-dev libhwy-dev xvfb xauth gnuplot-nox
  pybind11-dev python3-dev python3-numpy python3-pytest python3-matplotlib "$@")
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
echo "Installing missing Debian packages: ${missing[*]}"
sudo=""
[ "$(id -u)" -ne 0 ] && sudo="sudo"
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"

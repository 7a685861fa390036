#!/usr/bin/env bash
# Installs the Debian 12 packages ray builds with, if any is missing.
set -euo pipefail

packages=(cmake make g++ pkg-config
          libtinyxml2-dev libtinyobjloader-dev libopenimageio-dev libpng-dev libjpeg-dev
          ocl-icd-opencl-dev opencl-c-headers opencl-clhpp-headers pocl-opencl-icd clinfo
          catch2 libcli11-dev nlohmann-json3-dev
          pybind11-dev python3-pybind11 python3-numpy python3-pytest python3-pil
          util-linux mount  # setpriv, mount: tests/fault_injection.sh
          libcpp-httplib-dev chromium chromium-driver python3-selenium
          libopenmpi-dev openmpi-bin)  # mpirun -n N ray: tests/mpi.sh

missing=()
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "installing: ${missing[*]}"
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"

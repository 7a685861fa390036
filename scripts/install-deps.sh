#!/usr/bin/env bash
# Installs the Debian 12 packages ray builds with, if any is missing.
#   scripts/install-deps.sh           what the build and the tests need
#   scripts/install-deps.sh --bench   that, and what bench/ needs beyond it: POV-Ray 3.7
#                                     (the baseline) and matplotlib (the plots)
#   scripts/install-deps.sh --missing prints the missing packages of the first, one line
#                                     (empty when none), and installs nothing
set -euo pipefail

packages=(cmake make g++ pkg-config
          libexpat1-dev rapidjson-dev libtinyobjloader-dev libopenimageio-dev libpng-dev libjpeg-dev
          ocl-icd-opencl-dev opencl-c-headers opencl-clhpp-headers pocl-opencl-icd clinfo
          catch2 libcli11-dev nlohmann-json3-dev
          doxygen   # the C++ API reference: docs/Doxyfile, tests/api_reference.sh
          pybind11-dev python3-pybind11 python3-numpy python3-pytest python3-pil
          util-linux mount  # setpriv, mount: tests/fault_injection.sh
          patchelf          # scripts/gpu_bundle.sh: the bundle's $ORIGIN rpaths
          libcpp-httplib-dev chromium chromium-driver python3-selenium
          nodejs npm   # the viewer's page is bundled at build time from locked npm packages
          # docs/notebook.ipynb run headless (tests/notebook.py); ray(1) and the completions
          # as a user meets them (tests/reference_pages.py, the Debian package)
          jupyter-nbconvert python3-nbconvert python3-ipykernel python3-jupyter-client
          man-db bash-completion zsh
          libopenmpi-dev openmpi-bin   # mpirun -n N ray: tests/mpi.sh
          # the kernel as GPU drivers build it: scripts/kernel_resources.py (clang-15 and
          # libclc for AMD and NVIDIA), tests/rusticl.sh (Mesa's OpenCL), tests/oclgrind.sh
          clang-15 llvm-15 libclc-15 mesa-opencl-icd oclgrind)
list_only=0
if [ "${1:-}" = "--bench" ]; then
    packages+=(povray python3-matplotlib)  # bench/povray_side_by_side.py
elif [ "${1:-}" = "--missing" ]; then
    list_only=1
elif [ $# -gt 0 ]; then
    echo "usage: $0 [--bench | --missing]" >&2
    exit 2
fi

# Node.js and npm may come from elsewhere than Debian (NodeSource's nodejs holds npm, and
# Debian's npm would not install beside it): their commands are enough.
declare -A satisfied_by_command=([nodejs]=node [npm]=npm)

missing=()
for p in "${packages[@]}"; do
    command="${satisfied_by_command[$p]:-}"
    if [ -n "$command" ] && command -v "$command" >/dev/null; then continue; fi
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "$list_only" = 1 ]; then
    echo "${missing[*]}"
    exit 0
fi
[ ${#missing[@]} -eq 0 ] && exit 0

echo "installing: ${missing[*]}"
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"

#!/usr/bin/env bash
# The README's first command: installs what is missing, builds ray and its Python module
# cs123ray (installed into the user's site-packages of /usr/bin/python3, the Python
# Debian's pybind11 and NumPy are built for), and renders the bundled showpiece scene to
# showpiece.png.
#
# It prints one line a step and how it ended (scripts/steps.sh); apt's, CMake's and the
# compiler's output go to BUILD/setup.log, whose last lines it prints when a step fails.
#   RAY_BUILD_DIR    the build folder (default build)
#   RAY_CMAKE_ARGS   more arguments for CMake's configure step (split on spaces)
#   RAY_SKIP_INSTALL set: the packages are neither checked nor installed (tests/setup_script.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/steps.sh

build="$(realpath -m "${RAY_BUILD_DIR:-build}")"
python=/usr/bin/python3
steps_begin "$build/setup.log"

steps_install_deps

# shellcheck disable=SC2086 # RAY_CMAKE_ARGS is a list of arguments
step "configuring $build (CMake, Release)" \
    cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE="$python" ${RAY_CMAKE_ARGS:-}
step "building ray and cs123ray ($(nproc) jobs; minutes on a fresh checkout)" \
    cmake --build "$build" -j"$(nproc)" --target ray cs123ray

site="$("$python" -c 'import site; print(site.getusersitepackages())')"
install_module() {
    mkdir -p "$site" && cp "$build"/python/cs123ray*.so "$site"/ &&
        "$python" -c 'import cs123ray; print("imported", cs123ray.__file__)'
}
step "installing cs123ray into $site" install_module

stats="$build/showpiece-stats.txt"
render() {
    local status=0
    "$build/ray" scenes/showpiece.xml 800 600 -o showpiece.png --stats >"$stats" 2>&1 || status=$?
    cat "$stats"  # into the log
    return $status
}
step "rendering scenes/showpiece.xml to showpiece.png (800×600)" render
# The render's statistics, the one output worth reading when everything worked.
sed 's/^/    /' "$stats"
# The kernel for depths 5 to 10 as well (the showpiece's render built the one for depths up to
# 4; host/opencl/kernel_build.h kernelFrames), into the same cache, so that a newcomer's
# first renders at a greater depth do not wait for a build either.
prebuild_deeper_kernel() {
    local image status=0
    image="$(mktemp --suffix=.png)"
    "$build/ray" scenes/showpiece.xml 8 6 10 -o "$image" --quiet || status=$?
    rm -f "$image"
    return $status
}
step "building the kernel for depths 5 to 10" prebuild_deeper_kernel
echo "rendered $(pwd)/showpiece.png; $build/ray --help says what else ray does"

#!/usr/bin/env bash
# The README's second command (and CI's): builds ray with its tests and runs the suite.
#
# The install, configure and build steps print one line each (scripts/steps.sh), their
# output in BUILD/test-build.log, whose last lines they print on failure; CTest's own
# output follows as it is. The suite runs the longest tests first (tests/test_costs.cmake).
#   RAY_BUILD_DIR      the build folder (default build)
#   RAY_CMAKE_ARGS     more arguments for CMake's configure step (split on spaces)
#   RAY_SKIP_INSTALL   set: the packages are neither checked nor installed
#   RAY_FUZZ_SECONDS   fuzz_smoke's seconds per fuzz target (default 5; CI's .ci/run: more)
# Arguments are CTest's, after the defaults (e.g. -L kernel, -E fuzz_smoke).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/steps.sh

build="$(realpath -m "${RAY_BUILD_DIR:-build}")"
steps_begin "$build/test-build.log"
steps_install_deps
# shellcheck disable=SC2086 # RAY_CMAKE_ARGS is a list of arguments
step "configuring $build (CMake, Release)" cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release ${RAY_CMAKE_ARGS:-}
step "building ray and its tests ($(nproc) jobs; minutes on a fresh checkout)" cmake --build "$build" -j"$(nproc)"
cd "$build"
steps_note "running $(ctest -N "$@" | tail -1 | sed 's/Total Tests: //') tests (ctest -j$(nproc))"
ctest --output-on-failure -j"$(nproc)" --timeout 1800 "$@"

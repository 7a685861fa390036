#!/usr/bin/env bash
# The checks that need a GPU, in one command and one report, for a machine that has one
# (the project's own machines have none). Runs in under 8 minutes:
#   scripts/gpu_check.sh [--build-dir DIR] [--report FILE]
# 1. The OpenCL devices ray sees.
# 2. The kernel's cold build on the GPU: its time, and the driver's
#    CL_KERNEL_PRIVATE_MEM_SIZE (in --stats-json) beside LLVM's figures
#    (scripts/kernel_resources.py, where clang-15 is installed).
# 3. Kernel versus host on the GPU: the [kvh] tests (bundled scenes, and the course
#    corpus's INDEX scenes where ../shared is beside the checkout) with RAY_TEST_DEVICE=gpu.
# 4. Speed: Mrays/s on chess and 10^4 / 10^5 spheres, on the GPU and on PoCL's CPU device
#    in the same run (bench/ab.sh style: alternated, first run left out).
# Needs a build (scripts/test.sh or cmake --build) with its tests; exits 1 when there is no
# GPU or a check fails. The report is Markdown (default: gpu_check_report.md).
set -uo pipefail
cd "$(dirname "$0")/.."
build=build report=gpu_check_report.md
while [ $# -gt 0 ]; do
    case $1 in
        --build-dir) build=$2; shift 2 ;;
        --report) report=$2; shift 2 ;;
        *) sed -n '2,16p' "$0" >&2; exit 2 ;;
    esac
done
ray=$build/ray tests=$build/tests/ray_tests
[ -x "$ray" ] || { echo "gpu_check: $ray not found: build first (bash scripts/test.sh)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
status=0
exec 3>"$report"
say() { echo "$@" >&3; echo "$@"; }
block() { echo '```' >&3; cat "$1" >&3; echo '```' >&3; cat "$1"; }
json_number() { sed -n "s/.*\"$1\": *\\([0-9.eE+-]*\\).*/\\1/p" "$2" | head -1; }

say "# ray GPU check, $(date -u '+%Y-%m-%d %H:%M UTC'), $(git rev-parse --short HEAD 2>/dev/null)"
say ""
say "## Devices"
"$ray" --list-devices >"$work/devices.txt" 2>&1
block "$work/devices.txt"
if ! grep -q "GPU" "$work/devices.txt"; then
    say "No GPU device: nothing more to check."
    exit 1
fi

say "## Kernel build on the GPU (cold cache)"
export RAY_CACHE_DIR=$work/cache
timeout 300 "$ray" scenes/shadows.xml 64 48 --device gpu --quiet --stats-json "$work/build.json" \
    -o "$work/build.png" 2>"$work/build.err" || { block "$work/build.err"; status=1; }
if [ -s "$work/build.json" ]; then
    say "- kernel build: $(json_number kernel_build_seconds "$work/build.json") s"
    say "- CL_KERNEL_PRIVATE_MEM_SIZE: $(json_number kernel_private_bytes "$work/build.json") bytes a work-item"
fi
if command -v clang-15 >/dev/null && command -v python3 >/dev/null; then
    mapfile -t sources < <(sed -n 's|^ *\${CMAKE_SOURCE_DIR}/\(cl/[a-z_]*\.[a-z]*\)$|\1|p' CMakeLists.txt)
    timeout 240 python3 scripts/kernel_resources.py "${sources[@]}" >"$work/resources.txt" 2>&1 &&
        block "$work/resources.txt"
fi

say "## Kernel versus host on the GPU"
if [ -x "$tests" ]; then
    RAY_TEST_DEVICE=gpu timeout 300 "$tests" "[kvh]" --durations no >"$work/kvh.txt" 2>&1 || status=1
    grep -E "within 3/255|passed|failed|SKIPPED" "$work/kvh.txt" >"$work/kvh-summary.txt"
    block "$work/kvh-summary.txt"
else
    say "$tests not built: skipped"
fi

say "## Speed, GPU against PoCL in the same run"
bench_scenes=()
[ -f ../shared/cs123/scenes/chess.xml ] && bench_scenes+=(../shared/cs123/scenes/chess.xml)
if [ -x "$build/bench/ray_bench" ]; then
    "$build/bench/ray_bench" --write-scenes "$work/scenes" >/dev/null 2>&1 &&
        bench_scenes+=("$work/scenes/spheres_1e4.xml" "$work/scenes/spheres_1e5.xml")
fi
say "| scene | device | median render s | median Mrays/s |"
say "|---|---|---:|---:|"
for scene in "${bench_scenes[@]}"; do
    for device in gpu cpu; do  # a first run compiles (or loads) the kernel
        timeout 120 "$ray" "$scene" 1024 768 --aa off --device $device --quiet -o "$work/bench.png" >/dev/null 2>&1
    done
    for run in 1 2 3; do
        for device in gpu cpu; do
            timeout 120 "$ray" "$scene" 1024 768 --aa off --device $device --quiet \
                --stats-json "$work/$device-$run.json" -o "$work/bench.png" >/dev/null 2>&1 || status=1
        done
    done
    for device in gpu cpu; do
        seconds=$(for r in 1 2 3; do json_number render_seconds "$work/$device-$r.json"; done | sort -g | sed -n 2p)
        mrays=$(for r in 1 2 3; do json_number mrays_per_second "$work/$device-$r.json"; done | sort -g | sed -n 2p)
        say "| $(basename "$scene" .xml) | $device | ${seconds:--} | ${mrays:--} |"
    done
done
say ""
say "Result: $([ $status -eq 0 ] && echo "all checks passed" || echo "some checks FAILED")"
exit $status

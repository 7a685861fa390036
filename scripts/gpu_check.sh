#!/usr/bin/env bash
# The checks that need a GPU, in one command and one report, for a machine that has one
# (the project's own machines have none). Runs in under 8 minutes, from a checkout with a
# build, or from a bundle that carries everything (scripts/gpu_bundle.sh DIR, then
# DIR/gpu_check.sh on the GPU machine, from any folder, in any environment):
#   scripts/gpu_check.sh [--build-dir DIR] [--report FILE]
#   DIR/gpu_check.sh [--report FILE]
# 1. The machine (OS, kernel, glibc, driver, nvidia-smi) and the OpenCL devices ray sees.
# 2. The kernel's cold build on the GPU: its time, and the driver's
#    CL_KERNEL_PRIVATE_MEM_SIZE (in --stats-json) beside LLVM's figures
#    (scripts/kernel_resources.py, from a checkout where clang-15 is installed).
# 3. Kernel versus host on the GPU: the [kvh] tests (bundled scenes, and the course
#    corpus's INDEX scenes where ../shared is beside the checkout or in the bundle) with
#    RAY_TEST_DEVICE=gpu; from a bundle, also the GPU's images against the CPU images
#    made with the bundle.
# 4. Speed: Mrays/s on chess and 10^4 / 10^5 spheres, on the GPU and on PoCL's CPU device
#    in the same run (bench/ab.sh style: alternated, first run left out; PoCL only where
#    installed).
# Exits 1 when there is no GPU or a check fails. The report is Markdown (default:
# gpu_check_report.md in the current folder); a failed image comparison leaves its images
# in the folder named after the report, without .md.
set -uo pipefail
export PATH=${PATH:-/usr/local/bin:/usr/bin:/bin:/usr/local/sbin:/usr/sbin:/sbin}
here=$(cd "$(dirname "$0")" && pwd)
report=$PWD/gpu_check_report.md build=""
while [ $# -gt 0 ]; do
    case $1 in
        --build-dir) build=$(cd "$2" && pwd); shift 2 ;;
        --report) report=$(cd "$(dirname "$2")" && pwd)/$(basename "$2"); shift 2 ;;
        *) sed -n '2,21p' "$0" >&2; exit 2 ;;
    esac
done
if [ -f "$here/bundle.txt" ]; then  # a bundle: everything beside this script
    bundle=$here
    cd "$bundle"
    ray=$bundle/ray tests=$bundle/ray_tests bench=$bundle/ray_bench shared=$bundle/shared
    export RAY_TEST_SCENES_DIR=$bundle/scenes RAY_TEST_DATA_DIR=$bundle/tests/data RAY_SHARED_DIR=$bundle/shared
else  # a checkout
    bundle=""
    cd "$here/.."
    build=${build:-$PWD/build}
    ray=$build/ray tests=$build/tests/ray_tests bench=$build/bench/ray_bench shared=${RAY_SHARED_DIR:-../shared}
fi
[ -x "$ray" ] || { echo "gpu_check: $ray not found: build first (bash scripts/test.sh)" >&2; exit 2; }
export RAY_TEST_OUTPUT_DIR=${report%.md}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
status=0
exec 3>"$report"
say() { echo "$@" >&3; echo "$@"; }
block() { echo '```' >&3; cat "$1" >&3; echo '```' >&3; cat "$1"; }
json_number() { sed -n "s/.*\"$1\": *\\([0-9.eE+-]*\\).*/\\1/p" "$2" | head -1; }

commit=$(if [ -n "$bundle" ]; then sed -n 's/^commit: //p' bundle.txt; else git rev-parse --short HEAD 2>/dev/null; fi)
say "# ray GPU check, $(date -u '+%Y-%m-%d %H:%M UTC'), $commit"
say ""
say "## The machine"
{
    echo "os: $( (. /etc/os-release && echo "$PRETTY_NAME") 2>/dev/null || echo unknown)"
    echo "kernel: $(uname -srm)"
    echo "glibc: $(getconf GNU_LIBC_VERSION 2>/dev/null || echo unknown)"
    [ -n "$bundle" ] && sed 's/^/bundle /' bundle.txt
    [ -r /proc/driver/nvidia/version ] && sed -n 1p /proc/driver/nvidia/version
    if command -v nvidia-smi >/dev/null; then
        nvidia-smi --query-gpu=name,driver_version,memory.total,compute_cap --format=csv 2>&1
    else
        echo "nvidia-smi: not present"
    fi
} >"$work/machine.txt" 2>&1
block "$work/machine.txt"

# The OpenCL drivers: OCL_ICD_VENDORS, else /etc/OpenCL/vendors. Where neither names one
# but NVIDIA's OpenCL library is installed (a container often gets the library without its
# .icd file), a vendors folder of our own names it.
vendors=${OCL_ICD_VENDORS:-/etc/OpenCL/vendors}
if ! ls "$vendors"/*.icd >/dev/null 2>&1 && [ ! -f "$vendors" ]; then
    nvidia=$(ldconfig -p 2>/dev/null | awk '/libnvidia-opencl\.so\.1 / {print $NF; exit}')
    if [ -n "$nvidia" ]; then
        mkdir -p "$work/vendors" && echo "$nvidia" >"$work/vendors/nvidia.icd"
        export OCL_ICD_VENDORS=$work/vendors vendors=$work/vendors
    fi
fi
say "## OpenCL drivers ($vendors)"
{ for icd in "$vendors"/*.icd "$vendors"; do [ -f "$icd" ] && echo "$icd: $(cat "$icd")"; done; } >"$work/icd.txt" 2>&1
[ -s "$work/icd.txt" ] || echo "none: no .icd file names a driver" >"$work/icd.txt"
block "$work/icd.txt"

say "## Devices"
"$ray" --list-devices >"$work/devices.txt" 2>&1
block "$work/devices.txt"
if ! grep -q "GPU" "$work/devices.txt"; then
    say "No GPU device: no OpenCL driver here offers a GPU, so nothing was checked on one."
    if [ -n "$bundle" ] && grep -q "CPU" "$work/devices.txt"; then
        say "The bundle itself, on the CPU device instead (its images against those it was made with):"
        RAY_BUNDLE_DIR=$bundle RAY_TEST_DEVICE=cpu timeout 300 "$tests" "[bundle]" >"$work/self.txt" 2>&1 ||
            say "the bundle's self-check FAILED"
        grep -E "within 3/255|passed|failed|SKIPPED" "$work/self.txt" | tail -3 >"$work/self-summary.txt"
        block "$work/self-summary.txt"
    fi
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
if [ -z "$bundle" ] && command -v clang-15 >/dev/null && command -v python3 >/dev/null; then
    mapfile -t sources < <(sed -n '/set(RAY_CL_SOURCES/,/)/s|^ *\${CMAKE_SOURCE_DIR}/\(cl/[a-z_/]*\.[a-z]*\))\{0,1\}$|\1|p' CMakeLists.txt)
    timeout 240 python3 scripts/kernel_resources.py "${sources[@]}" >"$work/resources.txt" 2>&1 &&
        block "$work/resources.txt"
fi

say "## Kernel versus host on the GPU"
if [ -x "$tests" ]; then
    RAY_TEST_DEVICE=gpu timeout 300 "$tests" "[kvh]" --durations no >"$work/kvh.txt" 2>&1 || status=1
    grep -E "within 3/255|passed|failed|SKIPPED" "$work/kvh.txt" >"$work/kvh-summary.txt"
    block "$work/kvh-summary.txt"
    if [ -n "$bundle" ]; then
        say "## The GPU's images against the CPU images made with the bundle"
        RAY_BUNDLE_DIR=$bundle RAY_TEST_DEVICE=gpu timeout 300 "$tests" "[bundle]" >"$work/images.txt" 2>&1 || status=1
        grep -E "within 3/255|passed|failed|SKIPPED" "$work/images.txt" >"$work/images-summary.txt"
        block "$work/images-summary.txt"
    fi
else
    say "$tests not built: skipped"
fi

say "## Speed, GPU against PoCL in the same run"
speed_devices=(gpu)
grep -q "CPU" "$work/devices.txt" && speed_devices+=(cpu)  # a bare GPU machine has no PoCL
bench_scenes=()
[ -f "$shared/cs123/scenes/chess.xml" ] && bench_scenes+=("$shared/cs123/scenes/chess.xml")
if [ -x "$bench" ]; then
    "$bench" --write-scenes "$work/scenes" >/dev/null 2>&1 &&
        bench_scenes+=("$work/scenes/spheres_1e4.xml" "$work/scenes/spheres_1e5.xml")
fi
say "| scene | device | median render s | median Mrays/s |"
say "|---|---|---:|---:|"
for scene in "${bench_scenes[@]}"; do
    for device in "${speed_devices[@]}"; do  # a first run compiles (or loads) the kernel
        timeout 120 "$ray" "$scene" 1024 768 --aa off --device $device --quiet -o "$work/bench.png" >/dev/null 2>&1
    done
    for run in 1 2 3; do
        for device in "${speed_devices[@]}"; do
            timeout 120 "$ray" "$scene" 1024 768 --aa off --device $device --quiet \
                --stats-json "$work/$device-$run.json" -o "$work/bench.png" >/dev/null 2>&1 || status=1
        done
    done
    for device in "${speed_devices[@]}"; do
        seconds=$(for r in 1 2 3; do json_number render_seconds "$work/$device-$r.json"; done | sort -g | sed -n 2p)
        mrays=$(for r in 1 2 3; do json_number mrays_per_second "$work/$device-$r.json"; done | sort -g | sed -n 2p)
        say "| $(basename "$scene" .xml) | $device | ${seconds:--} | ${mrays:--} |"
    done
done
say ""
say "Result: $([ $status -eq 0 ] && echo "all checks passed" || echo "some checks FAILED")"
exit $status

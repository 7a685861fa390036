#!/usr/bin/env bash
# A second OpenCL implementation: Mesa's rusticl on llvmpipe (Debian mesa-opencl-icd), a
# compiler that inlines every call and runs work-items in SIMT lanes, as GPU drivers do.
#   tests/rusticl.sh RAY SOURCE_DIR OUTPUT_DIR
# 1. The kernel builds: the cold build's wall time and peak memory are printed, and the
#    memory must stay under 2 GB (it passed 16 GB, never finishing, when the kernel held
#    ~550 inlined traversals).
# 2. Bundled scenes at small sizes render byte-identical to PoCL. llvmpipe caps each
#    work-item at 65,535 loop iterations in all and then silently stops it, so the sizes
#    and --aa off keep every pixel far inside that.
# 3. ray never picks llvmpipe by itself (auto, all); chosen by index it renders and warns
#    about the cap.
# Skipped, saying so, without rusticl (Debian 12: mesa-opencl-icd) or PoCL.
set -uo pipefail
ray=$1 source_dir=$2 out=$3/rusticl
rusticl_icd=/etc/OpenCL/vendors/rusticl.icd
pocl_icd=/etc/OpenCL/vendors/pocl.icd
for f in "$rusticl_icd" "$pocl_icd"; do
    [ -f "$f" ] || { echo "SKIPPED: $f not found (Debian: apt-get install mesa-opencl-icd pocl-opencl-icd)"; exit 0; }
done
rm -rf "$out" && mkdir -p "$out/vendors-rusticl" "$out/vendors-pocl"
cp "$rusticl_icd" "$out/vendors-rusticl/"
cp "$pocl_icd" "$out/vendors-pocl/"
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# Each implementation sees only its own ICD file; rusticl lists llvmpipe only when asked.
# Mesa keeps compiled kernels in a cache of its own: a fresh one makes the first build cold.
rusticl() {
    OCL_ICD_VENDORS="$out/vendors-rusticl" RUSTICL_ENABLE=llvmpipe RAY_CACHE_DIR="$out/cache-rusticl" \
        MESA_SHADER_CACHE_DIR="$out/mesa-cache" "$@"
}
pocl() { OCL_ICD_VENDORS="$out/vendors-pocl" RAY_CACHE_DIR="$out/cache-pocl" "$@"; }

if ! rusticl "$ray" --list-devices >"$out/devices.txt" 2>&1 || ! grep -q llvmpipe "$out/devices.txt"; then
    echo "SKIPPED: rusticl lists no llvmpipe device here:"; cat "$out/devices.txt"; exit 0
fi

# 1. The cold build, measured on the first render (the kernel cache is empty).
scene=$source_dir/scenes/shadows.xml
if ! rusticl /usr/bin/time -f "%e %M" -o "$out/build.time" "$ray" "$scene" 8 6 --device 0 --aa off --quiet \
        -o "$out/first.png" 2>"$out/first.err"; then
    fail "the first render on rusticl failed:"; cat "$out/first.err"
else
    read -r seconds kilobytes <"$out/build.time"
    echo "rusticl cold kernel build and 8x6 render: ${seconds} s wall, peak $((kilobytes / 1024)) MiB"
    [ "$kilobytes" -lt $((2 * 1024 * 1024)) ] || fail "the rusticl build took $((kilobytes / 1024)) MiB (over 2 GB)"
fi

# 2. Bundled scenes, llvmpipe against PoCL, byte for byte.
scenes=(shadows primitives_all primitive_torus refraction reflection_depth texture_sphere bump_map
        light_area light_spot csg_die csg_nested mesh_vase motion_blur depth_of_field texture_filtering)
for name in "${scenes[@]}"; do
    args=("$source_dir/scenes/$name.xml" 24 18 --aa off --quiet)
    pocl "$ray" "${args[@]}" --device cpu -o "$out/$name-pocl.png" 2>"$out/$name-pocl.err" ||
        { fail "$name on PoCL:"; cat "$out/$name-pocl.err"; continue; }
    rusticl "$ray" "${args[@]}" --device 0 -o "$out/$name-rusticl.png" 2>"$out/$name-rusticl.err" ||
        { fail "$name on rusticl:"; cat "$out/$name-rusticl.err"; continue; }
    if cmp -s "$out/$name-pocl.png" "$out/$name-rusticl.png"; then
        echo "same image: $name"
    else
        fail "$name: llvmpipe's image differs from PoCL's ($out/$name-*.png)"
    fi
done

# 3. Never picked by itself; by index, with a warning about the cap.
for device in auto all; do
    if rusticl "$ray" "$scene" 8 6 --device "$device" --quiet -o "$out/auto.png" 2>"$out/auto.err"; then
        fail "--device $device picked llvmpipe"
    elif ! grep -qi "llvmpipe" "$out/auto.err"; then
        fail "--device $device with only llvmpipe: the message does not say why it was passed over:"
        cat "$out/auto.err"
    fi
done
if ! grep -qi "65,535\|65535" "$out/first.err"; then
    fail "--device 0 (llvmpipe) rendered without a warning about its loop cap:"; cat "$out/first.err"
fi

[ "$failures" -eq 0 ] && echo "rusticl: all checks passed" || exit 1

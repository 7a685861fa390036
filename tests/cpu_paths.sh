#!/usr/bin/env bash
# The two paths of a CPU device give the same image, byte for byte: the packet path
# (cl/device/cpu/packet_render.cl, the default on CPU devices) and one ray per work-item
# (RAY_CPU_PACKETS=0, the GPUs' path). Every bundled scene with the course's antialiasing,
# then the features that change how a pixel's rays are made (each antialiasing mode, the
# lens disk, the course's mesh distances, texture filters, Fresnel, a shallow and a deep
# tree, a traversal stack that overflows), the 4- and 8-ray packets of SSE and AVX2
# machines on a few scenes, and every course scene (small, --aa off; five larger, with the
# course's antialiasing).
#   tests/cpu_paths.sh RAY SOURCE_DIR OUTPUT_DIR
# Skipped, saying so, without an OpenCL CPU device.
set -uo pipefail
ray=$1 source_dir=$2 out=$3/cpu_paths
shared=$source_dir/../shared/cs123/scenes
rm -rf "$out" && mkdir -p "$out"
export RAY_CACHE_DIR="$out/cache"
if ! "$ray" --list-devices 2>/dev/null | grep -q "CPU,"; then
    echo "SKIPPED: no OpenCL CPU device (install pocl-opencl-icd)"; exit 0
fi
failures=0 compared=0
# compare NAME SCENE WIDTH HEIGHT [OPTIONS...]: both paths render it, to the same bytes; with
# REFUSED_ALIKE=1 a scene that both refuse with the same exit status passes (course scenes
# that ray refuses on purpose).
compare() {
    local name=$1 scene=$2 width=$3 height=$4; shift 4
    local args=("$scene" "$width" "$height" --device cpu --quiet "$@") packets=0 single=0
    "$ray" "${args[@]}" -o "$out/$name-packets.png" 2>"$out/$name-packets.err" || packets=$?
    RAY_CPU_PACKETS=0 "$ray" "${args[@]}" -o "$out/$name-single.png" 2>"$out/$name-single.err" || single=$?
    if [ "$packets" -ne 0 ] || [ "$single" -ne 0 ]; then
        [ "${REFUSED_ALIKE:-0}" = 1 ] && [ "$packets" = "$single" ] && return
        echo "FAIL: $name: exit $packets on the packet path, $single on the single-ray path:"
        cat "$out/$name-packets.err" "$out/$name-single.err"
        failures=$((failures + 1))
        return
    fi
    compared=$((compared + 1))
    if ! cmp -s "$out/$name-packets.png" "$out/$name-single.png"; then
        echo "FAIL: $name: the packet path's image differs from the single-ray path's ($*)"
        failures=$((failures + 1))
    fi
}
for scene in "$source_dir"/scenes/*.xml; do
    compare "$(basename "$scene" .xml)" "$scene" 37 29  # not a multiple of any block
done
scenes=$source_dir/scenes
compare aa-off "$scenes/showpiece.xml" 40 30 --aa off
compare aa-stratified "$scenes/showpiece.xml" 40 30 --aa stratified --samples 9
compare aa-adaptive "$scenes/light_area.xml" 40 30 --aa adaptive --samples 16
compare dof-disk "$scenes/depth_of_field.xml" 40 30 --dof disk --aa stratified --samples 4
compare course-meshes "$scenes/mesh_vase.xml" 40 30 --course-meshes
compare bilinear "$scenes/texture_filtering.xml" 40 30 --texture-filter bilinear
compare trilinear "$scenes/texture_filtering.xml" 40 30 --texture-filter trilinear
compare fresnel "$scenes/refraction.xml" 40 30 --fresnel
compare depth-1 "$scenes/reflection_depth.xml" 40 30 1
compare depth-8 "$scenes/reflection_depth.xml" 40 30 8
compare no-shadows "$scenes/shadows.xml" 40 30 --no-shadows
RAY_TEST_BVH_SHORT_STACK=1 compare short-stack "$scenes/primitives_all.xml" 40 30
# the narrower packets of AVX2 and SSE machines
for lanes in 4 8; do
    for name in showpiece light_area mesh_vase csg_die motion_blur; do
        RAY_CPU_PACKETS=$lanes compare "$name-$lanes-lanes" "$scenes/$name.xml" 37 29
    done
done
if [ -d "$shared" ]; then
    for name in chess ray_killer recursiveCones4 dof recursiveSpheres4_area; do
        [ -f "$shared/$name.xml" ] && compare "course-$name" "$shared/$name.xml" 48 36
    done
    # every course scene, small and without antialiasing
    for scene in "$shared"/*.xml; do
        REFUSED_ALIKE=1 compare "course-small-$(basename "$scene" .xml)" "$scene" 24 18 --aa off
    done
else
    echo "note: $shared not found; course scenes not compared"
fi
echo "$compared scenes and settings compared, $failures failed"
[ "$failures" -eq 0 ]

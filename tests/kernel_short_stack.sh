#!/usr/bin/env bash
# The traversal's short stack and its fallback (cl/traversal/stack.cl BvhStack): a walk that
# would push more than the stack holds tests every primitive under its root instead, which
# must find the same hits. RAY_TEST_BVH_SHORT_STACK=1 builds the kernel with a one-entry
# stack, so that nearly every walk of every scene overflows (the scene's and each mesh's);
# every bundled scene must then render byte-identical to the normal kernel.
#   tests/kernel_short_stack.sh RAY SOURCE_DIR OUTPUT_DIR
set -uo pipefail
ray=$1 source_dir=$2 out=$3/kernel_short_stack
rm -rf "$out" && mkdir -p "$out"
export RAY_CACHE_DIR="$out/cache"
failures=0 count=0
for scene in "$source_dir"/scenes/*.xml; do
    name=$(basename "$scene" .xml)
    args=("$scene" 32 24 --aa course --device cpu --quiet)
    "$ray" "${args[@]}" -o "$out/$name.png" || { echo "FAIL: $name"; failures=$((failures + 1)); continue; }
    RAY_TEST_BVH_SHORT_STACK=1 "$ray" "${args[@]}" -o "$out/$name-short.png" ||
        { echo "FAIL: $name with a one-entry stack"; failures=$((failures + 1)); continue; }
    count=$((count + 1))
    cmp -s "$out/$name.png" "$out/$name-short.png" ||
        { echo "FAIL: $name differs with a one-entry stack ($out/$name-short.png)"; failures=$((failures + 1)); }
done
echo "kernel_short_stack: $count scenes compared, $failures failures"
[ "$failures" -eq 0 ] && [ "$count" -gt 0 ]

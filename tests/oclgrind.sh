#!/usr/bin/env bash
# The kernel under Oclgrind (Debian oclgrind), the OpenCL simulator that checks every
# memory access of every work-item:
#   tests/oclgrind.sh RAY SOURCE_DIR OUTPUT_DIR
# Every bundled scene, small, under --check-api --data-races: out-of-bounds reads and
# writes, API misuse and races between work-items.
# Not yet --uninitialized: Oclgrind 21.10 reports a branch on an uninitialized value at the
# scene walk's first child test (cl/intersect.cl traceBvh) from the first work-item on,
# then an uninitialized store of the pixel, and then crashes (SIGSEGV) inside Oclgrind.
# Minimal kernels with the same constructs (a float3 ray passed by value, the child entry
# distances from select() on float4, the struct initializers) report nothing, so the cause
# is not found yet.
# A report is whatever Oclgrind writes: ray itself runs with --quiet and writes nothing on
# success, so any output fails the test. Skipped, saying so, without oclgrind.
set -uo pipefail
ray=$1 source_dir=$2 out=$3/oclgrind
command -v oclgrind >/dev/null || { echo "SKIPPED: oclgrind not found (Debian: apt-get install oclgrind)"; exit 0; }
rm -rf "$out" && mkdir -p "$out"
export RAY_CACHE_DIR="$out/cache"
failures=0 checked=0

check() {  # check NAME OCLGRIND-OPTIONS...: one render of scenes/NAME.xml at 8x6
    local name=$1; shift
    local log="$out/$name$(printf '%s' "$@" | tr -c 'a-z' '-').log"
    oclgrind "$@" "$ray" "$source_dir/scenes/$name.xml" 8 6 --aa off --device 0 --quiet -o "$out/$name.png" >"$log" 2>&1
    local status=$?
    checked=$((checked + 1))
    if [ $status -ne 0 ] || [ -s "$log" ]; then
        echo "FAIL: $name under oclgrind $* (exit $status):"; head -40 "$log"
        failures=$((failures + 1))
    fi
}

for scene in "$source_dir"/scenes/*.xml; do
    check "$(basename "$scene" .xml)" --check-api --data-races
done
echo "oclgrind: $checked runs, $failures with reports"
[ "$failures" -eq 0 ]

#!/usr/bin/env bash
# Four ray processes started at once on one empty kernel cache ($RAY_CACHE_DIR, which then
# also holds PoCL's cache): each exits 0 without a warning, each image is byte-identical to
# the same render made alone (on a cache of its own, also cold), no temporary file is left
# in the cache, and the cache they leave serves a fifth run, which gives the same image.
# (Two Renderers on two threads of one process: test_api_concurrency.cpp.)
# Usage: concurrency.sh RAY SOURCE_DIR OUT_DIR
set -u
ray=$1 src=$2 out=$3/concurrency
rm -rf "$out" && mkdir -p "$out"
unset POCL_CACHE_DIR  # ray puts PoCL's cache inside its own: both start cold
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

if ! "$ray" --list-devices 2>/dev/null | grep -qi "cpu"; then
    echo "SKIPPED: no OpenCL CPU device"
    exit 0
fi

# Two scenes, each rendered by two of the four processes.
scenes=("$src/scenes/showpiece.xml" "$src/scenes/primitives_all.xml")
render() {  # $1 cache, $2 scene, $3 output, $4 stderr
    RAY_CACHE_DIR="$1" timeout -k 5 600 "$ray" "$2" 160 120 --device cpu --quiet -o "$3" 2> "$4"
}

for s in 0 1; do
    render "$out/alone-cache-$s" "${scenes[$s]}" "$out/alone-$s.png" "$out/alone-$s.err" \
        || fail "scene $s alone: exit $?"
done

shared="$out/shared-cache"
pids=()
for p in 0 1 2 3; do
    render "$shared" "${scenes[$((p % 2))]}" "$out/together-$p.png" "$out/together-$p.err" &
    pids+=($!)
done
for p in 0 1 2 3; do
    wait "${pids[$p]}" || fail "process $p of 4 on one cold cache: exit $?"
    [ ! -s "$out/together-$p.err" ] || { fail "process $p printed:"; cat "$out/together-$p.err"; }
    cmp -s "$out/alone-$((p % 2)).png" "$out/together-$p.png" || fail "process $p: differs from the render alone"
done
leftovers=$(find "$shared" -name '.*.tmp*' | head -5)
[ -z "$leftovers" ] || fail "temporary files left in the cache: $leftovers"
[ -n "$(find "$shared" -type f ! -path '*/pocl/*' | head -1)" ] || fail "no kernel was cached"

# The cache they made serves a later run.
render "$shared" "${scenes[0]}" "$out/after.png" "$out/after.err" || fail "a run on the filled cache: exit $?"
cmp -s "$out/alone-0.png" "$out/after.png" || fail "a run on the filled cache: differs"

[ $failures -eq 0 ] && echo "concurrency: all passed"
exit $((failures > 0))

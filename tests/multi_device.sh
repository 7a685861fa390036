#!/usr/bin/env bash
# Several OpenCL devices on one frame (host/opencl/opencl_engine.h), through the ray command
# with PoCL's devices: POCL_DEVICES="pthread pthread" gives two in one process.
#   - --device all is byte-identical to --device 0 on every bundled scene and on the course
#     scenes of ../shared/cs123/reference/INDEX.tsv (with their options), each device
#     rendering some tiles (--stats-json);
#   - RAY_TEST_FAIL_DEVICE=1:2 (device 1 fails after 2 tiles): the same image, a warning;
#   - odd sizes: not a multiple of the tile, smaller than one tile, more devices than tiles;
#   - the fast/slow "pthread basic" pair.
# Usage: multi_device.sh RAY SOURCE_DIR OUT_DIR
set -u
ray=$1 src=$2 out=$3/multi_device
mkdir -p "$out"
export POCL_DEVICES="pthread pthread" RAY_CACHE_DIR="$out/cache"
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# Renders twice (device 0 alone, then every device) and compares the files byte for byte.
# $1 name, $2 scene, $3.. size and options.
same_on_all() {
    local name=$1 scene=$2; shift 2
    "$ray" "$scene" "$@" --quiet --device 0 -o "$out/$name.one.png" || { fail "$name: --device 0 exited $?"; return; }
    "$ray" "$scene" "$@" --quiet --device all -o "$out/$name.all.png" --stats-json "$out/$name.json" \
        || { fail "$name: --device all exited $?"; return; }
    cmp -s "$out/$name.one.png" "$out/$name.all.png" || fail "$name: --device all differs from --device 0"
}

# Each of the two devices kept tiles in most of the renders whose statistics are given.
# Not in every one: the scheduling is dynamic, and on a loaded machine one device can take
# (or win the end-of-frame duplicates of) a small frame's every tile.
every_device_worked() {
    python3 - "$@" <<'PY' || fail "a device rendered no tile in most scenes"
import json, sys
runs = [json.load(open(f))["devices"] for f in sys.argv[1:]]
for device in (0, 1):
    kept = sum(1 for r in runs if len(r) == 2 and r[device]["tiles"] > 0)
    print(f"device {device} kept tiles in {kept} of {len(runs)} scenes")
    if kept * 2 < len(runs): sys.exit(1)
PY
}

for scene in "$src"/scenes/*.xml; do
    name=$(basename "$scene" .xml)
    # 8-pixel tiles: enough of them that both devices get some.
    same_on_all "$name" "$scene" 96 72 --tile-size 8
done
every_device_worked "$out"/*.json

index="$src/../shared/cs123/reference/INDEX.tsv"
if [ -f "$index" ]; then
    tail -n +2 "$index" | while IFS=$'\t' read -r image scene settings options; do
        # shellcheck disable=SC2086 # the options column is a list of words
        same_on_all "course_${image%.png}" "$src/../shared/cs123/$scene" 80 60 4 $options --tile-size 16
    done
else
    echo "SKIPPED: the course scenes (../shared/cs123) are absent; bundled scenes only"
fi

base="$src/scenes/shadows.xml"
"$ray" "$base" 100 70 --quiet --device 0 -o "$out/hook.one.png"
RAY_TEST_FAIL_DEVICE=1:2 "$ray" "$base" 100 70 --device all --tile-size 8 -o "$out/hook.all.png" 2>"$out/hook.err" \
    || fail "failing device: exited $?"
cmp -s "$out/hook.one.png" "$out/hook.all.png" || fail "failing device: the image differs"
grep -q "warning: device 1 .*dropped" "$out/hook.err" || fail "failing device: no warning naming device 1"
RAY_TEST_FAIL_DEVICE=0:0 "$ray" "$base" 64 48 --quiet --device 0 -o "$out/hook.none.png" 2>/dev/null
[ $? -eq 3 ] || fail "the only device failing must exit 3"
[ ! -e "$out/hook.none.png" ] || fail "the only device failing must write nothing"

same_on_all odd_multiple "$base" 101 37 --tile-size 16   # not a multiple of the tile
same_on_all odd_small "$base" 5 3 --tile-size 64         # smaller than one tile
same_on_all odd_one_pixel "$base" 1 1                    # one tile for two devices

POCL_DEVICES="pthread basic" same_on_all pthread_basic "$base" 64 48 --tile-size 8

[ $failures -eq 0 ] && echo "multi_device: all passed"
exit $((failures > 0))

#!/usr/bin/env bash
# Fault injection for ray (issue 16): what happens when the disk or the environment fails.
# Usage: fault_injection.sh <ray binary> <scenes folder>. Needs root (tmpfs mount, dropping
# to nobody); prints "SKIPPED: why" otherwise. Each fault checks the exit code, the message,
# that an old output stays byte-identical and that no temporary file is left beside it.
set -uo pipefail
RAY_SRC=$1
SCENES=$2
if [ "$(id -u)" -ne 0 ]; then echo "SKIPPED: fault injection needs root (tmpfs mount, setpriv)"; exit 0; fi
for tool in setpriv mount umount mkfifo md5sum timeout; do
    command -v "$tool" >/dev/null || { echo "SKIPPED: $tool is missing"; exit 0; }
done

# A world-readable copy of the binary and scene: the CI clone may sit under /root, which
# nobody cannot enter.
WORK=$(mktemp -d /tmp/ray-faults.XXXXXX)
chmod 755 "$WORK"
FULL="$WORK/full"
cleanup() { mountpoint -q "$FULL" && umount "$FULL"; rm -rf "$WORK"; }
trap cleanup EXIT
install -m 755 "$RAY_SRC" "$WORK/ray"
install -m 644 "$SCENES/shadows.xml" "$WORK/scene.xml"
RAY="$WORK/ray"
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
as_nobody() { env -i PATH=/usr/bin:/bin HOME=/nonexistent setpriv --reuid=nobody --regid=nogroup --clear-groups "$@"; }
no_temporaries() { # $1 folder
    local left; left=$(find "$1" -maxdepth 1 -name '.*.tmp*' | head -1)
    [ -z "$left" ] || fail "temporary file left: $left"
}
expect() { # $1 name, $2 expected rc, $3 actual rc, $4 message pattern, $5 stderr file
    [ "$3" -eq "$2" ] || fail "$1: exit $3, expected $2"
    grep -q -- "$4" "$5" || { fail "$1: message lacks '$4'"; cat "$5"; }
    echo "$1: exit $3: $(grep -m1 -- "$4" "$5")"
}

# 1. Output on a full file system (a 64 KiB tmpfs): image and --stats-json.
mkdir "$FULL"
if ! mount -t tmpfs -o size=64k tmpfs "$FULL"; then echo "SKIPPED: cannot mount a tmpfs here"; exit 0; fi
"$RAY" "$WORK/scene.xml" 32 24 --device ref -o "$FULL/out.png" --quiet || fail "first render to the tmpfs"
echo '{"old": true}' > "$FULL/stats.json"
before=$(md5sum < "$FULL/out.png"); stats_before=$(md5sum < "$FULL/stats.json")
dd if=/dev/zero of="$FULL/filler" bs=4k 2>/dev/null
"$RAY" "$WORK/scene.xml" 160 120 --device ref -o "$FULL/out.png" --quiet 2>"$WORK/err"
expect "full disk, image" 3 $? "No space left on device" "$WORK/err"
[ "$(md5sum < "$FULL/out.png")" = "$before" ] || fail "full disk: the old image changed"
"$RAY" "$WORK/scene.xml" 16 12 --device ref -o "$WORK/ok.png" --stats-json "$FULL/stats.json" --quiet 2>"$WORK/err"
expect "full disk, --stats-json" 3 $? "stats.json: cannot write.*No space left on device" "$WORK/err"
[ "$(md5sum < "$FULL/stats.json")" = "$stats_before" ] || fail "full disk: the old stats JSON changed"
no_temporaries "$FULL"

# 2. An unwritable output folder (as nobody: root ignores permissions).
mkdir "$WORK/locked"; cp "$WORK/ok.png" "$WORK/locked/out.png"; chmod 755 "$WORK/locked"; chmod 644 "$WORK/locked/out.png"
before=$(md5sum < "$WORK/locked/out.png")
as_nobody "$RAY" "$WORK/scene.xml" 16 12 --device ref -o "$WORK/locked/out.png" --quiet 2>"$WORK/err"
expect "unwritable folder" 3 $? "locked/out.png: cannot write.*Permission denied" "$WORK/err"
[ "$(md5sum < "$WORK/locked/out.png")" = "$before" ] || fail "unwritable folder: the old image changed"
no_temporaries "$WORK/locked"

# 3. An OpenCL render as nobody, whose home does not exist (PoCL's cache must go elsewhere).
mkdir -m 777 "$WORK/public"
as_nobody "$RAY" "$WORK/scene.xml" 16 12 -o "$WORK/public/nobody.png" --quiet 2>"$WORK/err"
rc=$?
[ $rc -eq 0 ] && [ -s "$WORK/public/nobody.png" ] || { fail "render as nobody: exit $rc"; cat "$WORK/err"; }
echo "missing home (OpenCL as nobody): exit $rc"

# 4. kill -9 during the write: the old file stays whole. RAY_TEST_WRITE_PAUSE_MS is a test
# hook (core/atomic_file.cpp) that pauses halfway through writing the temporary file.
cp "$WORK/ok.png" "$WORK/public/kill.png"; before=$(md5sum < "$WORK/public/kill.png")
RAY_TEST_WRITE_PAUSE_MS=20000 "$RAY" "$WORK/scene.xml" 160 120 --device ref -o "$WORK/public/kill.png" --quiet &
pid=$!
for _ in $(seq 600); do
    [ -n "$(find "$WORK/public" -maxdepth 1 -name '.kill.tmp*' -size +0 | head -1)" ] && break
    sleep 0.1
done
[ -n "$(find "$WORK/public" -maxdepth 1 -name '.kill.tmp*')" ] || fail "kill -9: the write never started"
kill -9 $pid; wait $pid 2>/dev/null
[ "$(md5sum < "$WORK/public/kill.png")" = "$before" ] || fail "kill -9: the old image changed"
echo "kill -9 during the write: old image intact; the half-written temporary file stays (no process left to remove it)"

# 5. A texture that is a FIFO, or /dev/zero: a warning, no hang (timeout 60 s would fail).
# The FIFO's name is unique: the texture search also looks in the scene folder's parents
# (/tmp), where a regular file of a plain name like fifo.png would be found instead.
FIFO="$WORK/fifo-$(basename "$WORK").png"
mkfifo "$FIFO"
for texture in "$FIFO" /dev/zero; do
    sed "s#</scenefile>#<object type=\"tree\" name=\"t\"><transblock><object type=\"primitive\" name=\"cube\"><texture file=\"$texture\" u=\"1\" v=\"1\"/></object></transblock></object></scenefile>#" \
        "$WORK/scene.xml" > "$WORK/textured.xml"
    timeout 60 "$RAY" "$WORK/textured.xml" 16 12 --device ref -o "$WORK/tex.png" 2>"$WORK/err"
    expect "texture $texture" 0 $? "is not a regular file" "$WORK/err"
    timeout 60 "$RAY" "$WORK/textured.xml" 16 12 --device ref -o "$WORK/tex.png" --strict 2>"$WORK/err"
    expect "texture $texture --strict" 2 $? "is not a regular file" "$WORK/err"
done

[ $failures -eq 0 ] && echo "all faults handled" || { echo "$failures failure(s)"; exit 1; }

#!/usr/bin/env bash
# mpirun -n N ray ... (host/distributed/mpi_render.h), on this machine's PoCL CPU device:
#   - -n 1 and -n 3 are byte-identical to a plain ray run (the showpiece; chess.xml from
#     ../shared when present; the showpiece converted to the course's JSON, and a course JSON
#     scene), with the statistics per rank (--stats-json);
#   - odd sizes: not a multiple of the tile, more ranks than tiles;
#   - a bad scene (XML or JSON): exit 2, one message, no hang; a rank that cannot start: the same, its
#     message from rank 0; a rank whose scene file differs from rank 0's: refused;
#   - a rank whose every device fails: its tiles go to the others, the same image, a warning;
#   - a rank that hangs mid-frame (SIGSTOP): the same image within 30 s, the rank named,
#     the job ended without it (exit 4);
#   - a rank killed mid-frame: non-zero within seconds, the output untouched;
#   - Ctrl-C to mpirun: the output untouched, or written with --partial.
# Every mpirun runs under `timeout`: a hang is a failure, not a stuck CI job.
# Usage: mpi.sh RAY MPIRUN SOURCE_DIR OUT_DIR
set -u
ray=$1 mpirun=$2 src=$3 out=$4/mpi
rm -rf "$out" && mkdir -p "$out"
# Open MPI refuses to run as root (as CI does) without these; --oversubscribe lets 3 ranks
# share 2 cores; -q drops mpirun's own banner on a non-zero exit.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 RAY_CACHE_DIR="$out/cache"
mpi() { timeout -k 5 120 "$mpirun" -q --oversubscribe "$@"; }
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# $1 name, $2 ranks, $3 scene, $4.. size and options: a plain run, then mpirun -n $2.
same_as_plain() {
    local name=$1 ranks=$2 scene=$3; shift 3
    "$ray" "$scene" "$@" --quiet -o "$out/$name.plain.png" || { fail "$name: plain ray exited $?"; return; }
    mpi -n "$ranks" "$ray" "$scene" "$@" --quiet -o "$out/$name.mpi.png" --stats-json "$out/$name.json" \
        || { fail "$name: mpirun -n $ranks exited $?"; return; }
    cmp -s "$out/$name.plain.png" "$out/$name.mpi.png" || fail "$name: mpirun -n $ranks differs from a plain run"
    python3 - "$out/$name.json" "$ranks" <<'PY' || fail "$name: statistics"
import json, sys
stats, ranks = json.load(open(sys.argv[1])), int(sys.argv[2])
mpi = stats["mpi"]
assert mpi["ranks"] == ranks, mpi
assert sum(mpi["tiles_per_rank"]) == mpi["tiles"], mpi
assert sorted({d["rank"] for d in stats["devices"]}) == list(range(ranks)), stats["devices"]
assert stats["total_rays"] > 0
PY
}

showpiece="$src/scenes/showpiece.xml"
same_as_plain showpiece_1 1 "$showpiece" 160 120
same_as_plain showpiece_3 3 "$showpiece" 160 120 --tile-size 16
chess="$src/../shared/cs123/scenes/chess.xml"
if [ -f "$chess" ]; then
    same_as_plain chess_1 1 "$chess" 200 150
    same_as_plain chess_3 3 "$chess" 200 150 --tile-size 16
else
    echo "note: chess.xml is absent (../shared/cs123); the showpiece only"
fi
# A course JSON scene (issue 50): the ranks read the same JSON, the image is a plain run's.
if "$ray" convert "$showpiece" "$out/showpiece.json" >/dev/null; then
    same_as_plain showpiece_json_3 3 "$out/showpiece.json" 160 120 --tile-size 16
else
    fail "ray convert of the showpiece to JSON exited $?"
fi
course_json="$src/../shared/cs1230/scenefiles/illuminate/required/texture_tests/texture_cube.json"
[ -f "$course_json" ] && same_as_plain course_json_2 2 "$course_json" 120 90 --tile-size 16
base="$src/scenes/shadows.xml"
same_as_plain odd_multiple 3 "$base" 101 37 --tile-size 16   # not a multiple of the tile
same_as_plain more_ranks_than_tiles 3 "$base" 5 3 --tile-size 64

# A bad scene: every rank stops, exit 2, one message.
printf '<scenefile>\n<bad\n' > "$out/bad.xml"
mpi -n 3 "$ray" "$out/bad.xml" 32 24 -o "$out/bad.png" 2> "$out/bad.err"
code=$?
[ $code -eq 2 ] || fail "bad scene: exit $code, not 2"
[ "$(grep -c "bad.xml:" "$out/bad.err")" -eq 1 ] || { fail "bad scene: not one message"; cat "$out/bad.err"; }
[ ! -e "$out/bad.png" ] || fail "bad scene: an image was written"
# Bad JSON: every rank stops, exit 2, one message naming line and column.
printf '{\n  "cameraData": [1,\n' > "$out/bad.json"
mpi -n 3 "$ray" "$out/bad.json" 32 24 -o "$out/badjson.png" 2> "$out/badjson.err"
code=$?
[ $code -eq 2 ] || fail "bad JSON: exit $code, not 2"
[ "$(grep -c "bad.json:[0-9]*:[0-9]*:" "$out/badjson.err")" -eq 1 ] || { fail "bad JSON: not one message with line and column"; cat "$out/badjson.err"; }
[ ! -e "$out/badjson.png" ] || fail "bad JSON: an image was written"
# Rank 2 alone cannot open its scene (as a host missing the file would): rank 0 says so.
mpi -n 2 "$ray" "$base" 32 24 -o "$out/missing.png" : -n 1 "$ray" "$out/missing.xml" 32 24 -o "$out/missing.png" \
    2> "$out/missing.err"
code=$?
[ $code -eq 2 ] || fail "a rank missing the scene: exit $code, not 2"
grep -q "missing.xml: error: .*" "$out/missing.err" && grep -q "on rank 2" "$out/missing.err" \
    || { fail "a rank missing the scene: no message naming it"; cat "$out/missing.err"; }

# Rank 2 reads another copy of the scene that differs (a host with a stale copy): refused.
mkdir -p "$out/other"
sed 's/<scenefile>/<scenefile><!-- changed -->/' "$base" > "$out/other/shadows.xml"
cp -r "$src/scenes/textures" "$out/other/" 2>/dev/null
mpi -n 2 "$ray" "$base" 32 24 -o "$out/differs.png" : -n 1 "$ray" "$out/other/shadows.xml" 32 24 -o "$out/differs.png" \
    2> "$out/differs.err"
code=$?
[ $code -eq 2 ] || fail "a rank with another scene: exit $code, not 2"
grep -q "rank 2 differs from rank 0's" "$out/differs.err" || { fail "a rank with another scene: no message"; cat "$out/differs.err"; }

# Rank 2's only device fails after two tiles: the others finish the frame. The frame has
# 1200 tiles, so that it lasts well beyond the ranks' differences in start-up: with 117, the
# other ranks once finished it before rank 2 had rendered two (and it never failed).
"$ray" "$base" 320 240 --quiet -o "$out/hook.plain.png"
mpi -n 2 "$ray" "$base" 320 240 --tile-size 8 -o "$out/hook.mpi.png" : \
    -n 1 -x RAY_TEST_FAIL_DEVICE=0:2 "$ray" "$base" 320 240 --tile-size 8 -o "$out/hook.mpi.png" 2> "$out/hook.err" \
    || fail "a failing rank: exited $?"
cmp -s "$out/hook.plain.png" "$out/hook.mpi.png" || fail "a failing rank: the image differs"
grep -q "warning: rank 2 dropped" "$out/hook.err" || { fail "a failing rank: no warning naming it"; cat "$out/hook.err"; }

# A rank that hangs mid-frame (SIGSTOP: a wedged host, alive but silent): rank 0 gives its
# tiles to the others, writes the whole image, names the rank and ends the job without it
# (exit 4), within 30 s of the stop. RAY_TEST_STOP_AFTER_TILES=20 makes rank 2 stop itself
# after sending 20 tiles, a known point mid-frame, and says when; the clock starts there.
# The ranks of a job, by a word of their command line (its output file).
ranks_of() { for p in $(pgrep -x ray); do grep -qa "$1" "/proc/$p/cmdline" 2>/dev/null && echo "$p"; done; }
"$ray" --rank-timeout 0 "$base" 2> /dev/null
[ $? -eq 2 ] || fail "--rank-timeout 0: not refused with exit 2"
if [ -f "$chess" ]; then hung=("$chess" 1200 900); else hung=("$showpiece" 1200 900); fi
hung_victim=
state_of() { awk '{print $3}' "/proc/$1/stat" 2>/dev/null; }
# $1 mpirun's pid, hung: what it and its children were doing, before the test kills it.
show_hang() {
    echo "--- the hung job: processes"
    ps -eo pid,ppid,stat,etime,wchan:24,args | awk -v j="$1" 'NR == 1 || $1 == j || $2 == j || /[r]ay /'
    command -v gdb > /dev/null && timeout 60 gdb -batch -p "$1" -ex "thread apply all bt" 2>&1 | grep -E "^(Thread|#)"
    echo "--- mpirun's open files"; ls -l "/proc/$1/fd" 2>&1 | tail -n +2
}
release_victim() { [ -n "$hung_victim" ] && kill -CONT "$hung_victim" 2>/dev/null && kill -9 "$hung_victim" 2>/dev/null; true; }
trap release_victim EXIT
"$ray" "${hung[@]}" --quiet -o "$out/hung.plain.png" || fail "hung rank: plain ray exited $?"
# On busy cores rank 2 may start so late that the others finish the frame before its 20th
# tile (it then ends normally): one more try, on the caches the first one filled.
for attempt in 1 2; do
    rm -f "$out/hung.png"
    hung_victim=
    "$mpirun" -q --oversubscribe -n 2 "$ray" "${hung[@]}" -o "$out/hung.png" : \
        -n 1 -x RAY_TEST_STOP_AFTER_TILES=20 "$ray" "${hung[@]}" -o "$out/hung.png" 2> "$out/hung.err" &
    job=$!
    for _ in $(seq 1200); do  # at most 120 s for rank 2 to start and stop itself
        for p in $(ranks_of hung.png); do grep -qz "^OMPI_COMM_WORLD_RANK=2$" "/proc/$p/environ" 2>/dev/null && hung_victim=$p; done
        [ -n "$hung_victim" ] && [ "$(state_of "$hung_victim")" = T ] && break
        kill -0 $job 2>/dev/null || break
        sleep 0.1
    done
    [ "$(state_of "$hung_victim")" = T ] && break
    wait $job
    echo "note: attempt $attempt: rank 2 did not reach its 20th tile before the frame ended"
done
if [ "$(state_of "$hung_victim")" != T ]; then
    fail "hung rank: rank 2 never stopped (found: '$hung_victim')"; kill -9 $job 2>/dev/null
else
    code=hung
    for _ in $(seq 900); do  # at most 90 s
        kill -0 $job 2>/dev/null || { wait $job; code=$?; ended_at=$(date +%s.%N); break; }
        sleep 0.1
    done
    [ "$code" = hung ] && { show_hang $job; kill -9 $job; fail "hung rank: the job did not end within 90 s of the stop"; }
    [ "$code" = 4 ] || fail "hung rank: exit $code, not 4"
    # The rank says when it stopped itself (polling /proc here lags seconds on busy cores).
    stopped_at=$(sed -n 's/.*this rank stops itself (SIGSTOP) at \([0-9.]*\)$/\1/p' "$out/hung.err")
    cmp -s "$out/hung.plain.png" "$out/hung.png" || fail "hung rank: the image differs from a plain render"
    python3 - "$out/hung.png" "$stopped_at" "${ended_at:-0}" <<'PY' || fail "hung rank: not written and ended within 30 s of the stop"
import os, sys
stopped, ended = float(sys.argv[2]), float(sys.argv[3])
written = os.path.getmtime(sys.argv[1]) - stopped
print(f"hung rank: image written {written:.1f} s after the stop, job ended {ended - stopped:.1f} s after it")
sys.exit(not (0 < written <= 30 and ended - stopped <= 30))
PY
    grep -q "warning: rank 2 (host .*) does not answer" "$out/hung.err" && grep -q "ending the job without rank 2" "$out/hung.err" \
        || { fail "hung rank: no warning naming rank 2"; cat "$out/hung.err"; }
    sleep 1  # mpirun's kill reaches the stopped rank (SIGCONT, SIGTERM, SIGKILL)
    [ "$(state_of "$hung_victim")" != T ] || fail "hung rank: the stopped rank was left behind"
    [ -z "$(ranks_of hung.png)" ] || fail "hung rank: ranks left running"
fi
release_victim

# The same with --rank-timeout 2, rank 2 stopping after 3 tiles: rank 0 names it after 2 s
# (its tile late while the frame goes on, or, when the others have finished the frame by
# then, its silence; which one depends on how soon rank 2 started: test_tile_scheduler.cpp
# covers the late tile given to another rank).
"$mpirun" -q --oversubscribe -n 2 "$ray" "${hung[@]}" --rank-timeout 2 -o "$out/late.png" : \
    -n 1 -x RAY_TEST_STOP_AFTER_TILES=3 "$ray" "${hung[@]}" --rank-timeout 2 -o "$out/late.png" 2> "$out/late.err" &
job=$!
code=hung
for _ in $(seq 1200); do  # at most 120 s
    kill -0 $job 2>/dev/null || { wait $job; code=$?; break; }
    sleep 0.1
done
[ "$code" = hung ] && { show_hang $job; kill -9 $job; }
for p in $(ranks_of late.png); do kill -CONT "$p"; kill -9 "$p"; done 2>/dev/null
[ "$code" = 4 ] || fail "late rank (--rank-timeout 2): exit '$code', not 4"
cmp -s "$out/hung.plain.png" "$out/late.png" || fail "late rank: the image differs"
grep -Eq "warning: rank 2 \(host .*\) does not answer: it (held its tile .* past its deadline of 2.0 s|sent nothing for .* \(its deadline: 2.0 s\))" \
    "$out/late.err" || { fail "late rank: no warning with its 2 s deadline"; cat "$out/late.err"; }

# A rank that stops itself (test hooks: -x VAR=value on rank 2) before its first tile:
# silent (no heartbeat) for the usual 10 s deadline, it is dropped, not waited for as a
# start-up (the first tile's 120 s, or for ever in a collective): the same image within
# 30 s of the stop, the rank named, exit 4, the job ended. Rank 0 aborts 1 s after it tells
# rank 1 the frame is over (RAY_TEST_ABORT_AFTER_SECONDS): rank 1 then surely waits for the
# abort (while it called MPI_Finalize, mpirun hung or crashed in some runs: bench/mpi_abort_race.sh).
# $1 name, $2 the warning's pattern, $3.. mpirun's -x options for rank 2.
stopped_early() {
    local name=$1 warning=$2; shift 2
    RAY_TEST_ABORT_AFTER_SECONDS=1 "$mpirun" -q --oversubscribe -n 2 "$ray" "$base" 320 240 --tile-size 8 \
        -o "$out/$name.png" : -n 1 "$@" "$ray" "$base" 320 240 --tile-size 8 -o "$out/$name.png" 2> "$out/$name.err" &
    local job=$! code=hung ended_at=0
    for _ in $(seq 900); do  # at most 90 s
        kill -0 $job 2>/dev/null || { wait $job; code=$?; ended_at=$(date +%s.%N); break; }
        sleep 0.1
    done
    [ "$code" = hung ] && { show_hang $job; kill -9 $job; fail "$name: the job did not end within 90 s"; }
    for p in $(ranks_of "$name.png"); do fail "$name: rank $p left behind"; kill -CONT "$p"; kill -9 "$p"; done 2>/dev/null
    [ "$code" = 4 ] || fail "$name: exit $code, not 4"
    cmp -s "$out/hook.plain.png" "$out/$name.png" || fail "$name: the image differs"
    local stopped_at
    stopped_at=$(sed -n 's/.*this rank stops itself (SIGSTOP) at \([0-9.]*\)$/\1/p' "$out/$name.err")
    python3 - "$out/$name.png" "${stopped_at:-0}" "$ended_at" "$name" <<'PY' || fail "$name: not written and ended within 30 s of the stop"
import os, sys
stopped, ended = float(sys.argv[2]), float(sys.argv[3])
written = os.path.getmtime(sys.argv[1]) - stopped
print(f"{sys.argv[4]}: image written {written:.1f} s after the stop, job ended {ended - stopped:.1f} s after it")
sys.exit(not (0 < written <= 30 and 0 < ended - stopped <= 30))
PY
    grep -q "warning: rank 2 .*does not answer: it $warning" "$out/$name.err" \
        && grep -q "ending the job without rank 2" "$out/$name.err" \
        || { fail "$name: no warning naming rank 2"; cat "$out/$name.err"; }
}
# Stopped while it compiles (issue 34): its kernel build held for 30 s, stopped 2 s into
# its message loop.
stopped_early compiling "sent nothing for .*, not even a heartbeat" \
    -x RAY_TEST_SLOW_BUILD=0:30 -x RAY_TEST_STOP_AFTER_SECONDS=2
# Stopped while it loads its scene (its start-up 3 s longer, beating, then stopped), before
# it told rank 0 how the start-up went: no collective waits for it. (Rank 0 sends its
# start to the silent rank too: while it did not, Open MPI 4.1.4's mpirun hung or crashed
# after rank 0's MPI_Abort in 5 of 28 runs, the image written; in none of 15 since.)
stopped_early loading "sent nothing for .* in its start-up, not even a heartbeat" -x RAY_TEST_STOP_WHILE_LOADING=3

# A rank whose kernel build takes 15 s, longer than the 10 s a silent rank is given, but
# which answers (its heartbeats): waited for, exit 0, the same image, no warning, its
# statistics in (ranks 0 and 1 finish the frame long before).
started_at=$(date +%s.%N)
timeout -k 5 120 "$mpirun" -q --oversubscribe -n 2 "$ray" "$base" 320 240 --tile-size 8 -o "$out/slow_build.png" \
    --stats-json "$out/slow_build.json" : -n 1 -x RAY_TEST_SLOW_BUILD=0:15 "$ray" "$base" 320 240 --tile-size 8 \
    -o "$out/slow_build.png" --stats-json "$out/slow_build.json" 2> "$out/slow_build.err"
code=$?
took=$(python3 -c "import sys, time; print(f'{time.time() - float(sys.argv[1]):.1f}')" "$started_at")
echo "slow build: the job took $took s"
[ $code -eq 0 ] || { fail "slow build: exit $code, not 0"; cat "$out/slow_build.err"; }
cmp -s "$out/hook.plain.png" "$out/slow_build.png" || fail "slow build: the image differs"
grep -q "does not answer" "$out/slow_build.err" && { fail "slow build: rank 2 was taken for hung"; cat "$out/slow_build.err"; }
python3 - "$out/slow_build.json" "$took" <<'PY' || fail "slow build: rank 2 not waited for"
import json, sys
stats, took = json.load(open(sys.argv[1])), float(sys.argv[2])
assert 2 in {d["rank"] for d in stats["devices"]}, stats["devices"]  # its statistics came
assert stats["kernel_build_seconds"] >= 15, stats["kernel_build_seconds"]
assert took >= 15, took
PY

# A long frame (80 s on 2 busy cores), stopped after 5 s, when the ranks are surely
# rendering: mpirun in the background, watched.
long=("$showpiece" 2400 1800 --aa stratified --samples 64 --quiet)
# $1 pid: waits at most 20 s for it to end; prints its exit code (or "hung", killing it).
wait_briefly() {
    local pid=$1
    for _ in $(seq 200); do
        kill -0 "$pid" 2>/dev/null || { wait "$pid"; echo $?; return; }
        sleep 0.1
    done
    kill -9 "$pid"; echo hung
}

# A rank killed mid-frame: mpirun ends every rank, non-zero, the old file untouched.
echo old > "$out/killed.png"
"$mpirun" -q --oversubscribe -n 3 "$ray" "${long[@]}" -o "$out/killed.png" 2> "$out/killed.err" &
job=$!
sleep 5
victim=$(ranks_of killed.png | sort -n | tail -1)
[ -n "$victim" ] && kill -9 "$victim"
code=$(wait_briefly $job)
{ [ "$code" != hung ] && [ "$code" -ne 0 ]; } || fail "a rank killed: mpirun gave '$code', not a non-zero exit"
[ "$(cat "$out/killed.png")" = old ] || fail "a rank killed: the output was changed"
[ -z "$(ranks_of killed.png)" ] || fail "a rank killed: ranks left running"

# Ctrl-C to mpirun: every rank stops, the output untouched; with --partial, written.
for partial in "" --partial; do
    echo old > "$out/interrupted.png"
    "$mpirun" -q --oversubscribe -n 3 "$ray" "${long[@]}" $partial -o "$out/interrupted.png" 2> "$out/interrupted.err" &
    job=$!
    sleep 5
    kill -INT $job
    code=$(wait_briefly $job)
    { [ "$code" != hung ] && [ "$code" -ne 0 ]; } || fail "Ctrl-C$partial: mpirun gave '$code', not a non-zero exit"
    [ -z "$(ranks_of interrupted.png)" ] || fail "Ctrl-C$partial: ranks left running"
    if [ -z "$partial" ]; then
        [ "$(cat "$out/interrupted.png")" = old ] || fail "Ctrl-C: the output was changed"
    else
        # A PNG of the frame's size (its IHDR chunk).
        python3 -c "import struct, sys; b = open(sys.argv[1], 'rb').read(24)
assert b[:8] == b'\x89PNG\r\n\x1a\n' and struct.unpack('>II', b[16:24]) == (2400, 1800)" \
            "$out/interrupted.png" 2>/dev/null || fail "Ctrl-C --partial: no partial image written"
    fi
done

[ $failures -eq 0 ] && echo "mpi: all passed"
exit $((failures > 0))

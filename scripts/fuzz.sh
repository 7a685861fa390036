#!/usr/bin/env bash
# Builds ray's libFuzzer targets (fuzz/) with clang, AddressSanitizer and UBSan, and runs
# each for a while, seeded with the course corpus (read in place) and our own scenes.
#
#   bash scripts/fuzz.sh [--seconds N] [--build-dir DIR] [--only TARGET] [--no-install]
#
# --seconds N     run each target N seconds (default 60)
# --build-dir DIR where to build (default build-fuzz beside this script's checkout); the
#                 grown corpora are kept in DIR/corpus/<target>, crashes in DIR/artifacts/
# --only TARGET   run one target (fuzz_scene_loader, fuzz_json_scene, fuzz_course_config,
#                 fuzz_image_reader, fuzz_obj_loader,
#                 fuzz_scene_round_trip, fuzz_viewer_requests)
# --seconds-from-env  $RAY_FUZZ_SECONDS, else 5 (the test suite's fuzz_smoke: a few seconds a
#                 target find what breaks at once; CI's .ci/run sets a longer run)
# --jobs N        build with N jobs (default: one a core; CTest's fuzz_smoke: 1, since CTest
#                 runs another test on each other core)
# --no-install    do not apt-get clang when it is missing: print "SKIPPED:" and exit 0
#                 (what the test suite does)
#
# Exit status: 0 when no target crashed; 1 when one did (the input is in DIR/artifacts/:
# reproduce with DIR/fuzz/<target> <file>). The last line of each run is libFuzzer's
# "#execs DONE cov: C ft: F ..." (C: code edges covered, F: features).
set -euo pipefail

here="$(cd "$(dirname "$0")/.." && pwd)"
seconds=60
build="$here/build-fuzz"
only=""
install=1
jobs="$(nproc)"
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) seconds="$2"; shift 2 ;;
    --build-dir) build="$2"; shift 2 ;;
    --only) only="$2"; shift 2 ;;
    --no-install) install=0; shift ;;
    --jobs) jobs="$2"; shift 2 ;;
    --seconds-from-env) seconds="${RAY_FUZZ_SECONDS:-5}"; shift ;;
    *) echo "fuzz.sh: unknown argument '$1'" >&2; exit 2 ;;
  esac
done

# libFuzzer comes with Debian's clang (libclang-rt-14-dev ships libclang_rt.fuzzer).
fuzzer_works() {
  command -v clang++ >/dev/null 2>&1 || return 1
  local probe; probe="$(mktemp -d)"
  echo 'extern "C" int LLVMFuzzerTestOneInput(const unsigned char*, unsigned long) { return 0; }' > "$probe/p.cpp"
  clang++ -fsanitize=fuzzer,address "$probe/p.cpp" -o "$probe/p" >/dev/null 2>&1
  local ok=$?
  rm -rf "$probe"
  return $ok
}
if ! fuzzer_works; then
  if [ "$install" = 0 ]; then
    echo "SKIPPED: clang with libFuzzer is not installed (apt-get install clang libclang-rt-14-dev)"
    exit 0
  fi
  sudo_cmd=""; [ "$(id -u)" = 0 ] || sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  $sudo_cmd apt-get install -y -qq clang libclang-rt-14-dev
fi

cmake -S "$here" -B "$build" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DRAY_FUZZ=ON -DRAY_BUILD_TESTS=OFF >/dev/null
cmake --build "$build" --target fuzzers -j"$jobs" >/dev/null

shared="${RAY_SHARED_DIR:-$here/../shared}/cs123"
course="${RAY_SHARED_DIR:-$here/../shared}/cs1230"
seeds_for() {
  case "$1" in
    fuzz_scene_loader) echo "$shared/scenes $here/scenes $here/tests/data/fuzz/scene_loader" ;;
    fuzz_json_scene) echo "$course/scenefiles/intersect/required $course/scenefiles/illuminate/required/shadow $here/tests/data/fuzz/json_scene" ;;
    fuzz_course_config) echo "$course/template_inis/illuminate $course/template_inis/intersect $here/tests/data/fuzz/course_config" ;;
    fuzz_image_reader) echo "$shared/image $shared/textures $here/scenes/textures $here/tests/data/fuzz/image_reader" ;;
    fuzz_obj_loader) echo "$shared/mesh $here/scenes/meshes $here/tests/data/fuzz/obj_loader" ;;
    fuzz_scene_round_trip) echo "$shared/scenes $here/scenes $here/tests/data/fuzz/scene_loader" ;;
    fuzz_viewer_requests) echo "$here/tests/data/fuzz/viewer_requests" ;;
  esac
}
options_for() {
  case "$1" in
    fuzz_scene_loader) echo "-dict=$here/fuzz/scene.dict -max_len=100000" ;;
    fuzz_json_scene) echo "-dict=$here/fuzz/json_scene.dict -max_len=100000" ;;
    fuzz_course_config) echo "-dict=$here/fuzz/course_config.dict -max_len=4096" ;;
    fuzz_image_reader) echo "-max_len=65536" ;;  # big seeds are cut: truncated files are good tests too
    fuzz_obj_loader) echo "-max_len=65536" ;;
    fuzz_scene_round_trip) echo "-dict=$here/fuzz/scene.dict -max_len=100000" ;;
    fuzz_viewer_requests) echo "-dict=$here/fuzz/viewer.dict -max_len=4096" ;;
  esac
}

status=0
mkdir -p "$build/artifacts"
for binary in "$build"/fuzz/fuzz_*; do
  [ -x "$binary" ] || continue
  target="$(basename "$binary")"
  [ -z "$only" ] || [ "$only" = "$target" ] || continue
  corpus="$build/corpus/$target"
  mkdir -p "$corpus"
  seeds=()
  for dir in $(seeds_for "$target"); do [ -d "$dir" ] && seeds+=("$dir"); done
  log="$build/$target.log"
  echo "== $target: ${seconds}s, seeds: ${seeds[*]:-none}"
  # Leaks count as crashes, except those of fuzz/lsan.supp (inside OpenImageIO), which
  # need full stacks to be recognised.
  if ASAN_OPTIONS="fast_unwind_on_malloc=0:${ASAN_OPTIONS:-}" LSAN_OPTIONS="suppressions=$here/fuzz/lsan.supp:${LSAN_OPTIONS:-}" "$binary" "$corpus" "${seeds[@]}" $(options_for "$target") \
      -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
      -artifact_prefix="$build/artifacts/$target-" >"$log" 2>&1; then
    grep -E "^#[0-9]+[[:space:]]+DONE" "$log" | tail -1 || tail -1 "$log"
  else
    status=1
    echo "$target CRASHED; the last lines of $log:"
    tail -40 "$log"
  fi
done
exit $status

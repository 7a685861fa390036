#!/usr/bin/env bash
# The README's two commands' quiet output (scripts/steps.sh, issue 34): a step prints one
# line however much its command prints, the details go to the log the scripts name, and a
# failing step prints the log's tail and stops the script with its exit status. Then
# scripts/setup.sh and scripts/test.sh with a configure step that must fail (a compiler
# that does not exist, RAY_CMAKE_ARGS) in a build folder of their own, without apt
# (RAY_SKIP_INSTALL): a few seconds, nothing built.
#   tests/setup_script.sh SOURCE_DIR WORK_DIR
set -uo pipefail
source_dir="$1"
work="$2"
rm -rf "$work"
mkdir -p "$work"
failures=0
fail() {
    echo "FAIL: $*"
    failures=$((failures + 1))
}
expect_in() {  # expect_in FILE PATTERN WHAT
    grep -qE -- "$2" "$1" || fail "$3: no line matches '$2' in $1"
}

# 1. The steps themselves: a chatty step that works, then one that fails.
cat >"$work/steps_demo.sh" <<EOF
set -euo pipefail
source "$source_dir/scripts/steps.sh"
steps_begin "$work/demo/steps.log"
step "a chatty step" bash -c 'for i in \$(seq 500); do echo "chatter \$i"; done'
steps_note "a note"
step "a failing step" bash -c 'echo "the cause of the failure"; echo "to stderr" >&2; exit 7'
echo "not reached"
EOF
status=0
RAY_LOG_TAIL=5 bash "$work/steps_demo.sh" >"$work/demo.out" 2>&1 || status=$?
echo "--- steps demo (exit $status):"
cat "$work/demo.out"
[ "$status" -eq 7 ] || fail "a failing step should end the script with its exit status 7, not $status"
lines=$(wc -l <"$work/demo.out")
# details line, chatty ok, note, failing line, tail header, 5 tail lines, closing line
[ "$lines" -eq 11 ] || fail "the demo should print 11 lines (5 of them the log's tail), not $lines"
expect_in "$work/demo.out" "^details in $work/demo/steps.log$" "the log's path"
expect_in "$work/demo.out" "^a chatty step \.\.\. ok \([0-9]+ s\)$" "a step that works"
expect_in "$work/demo.out" "^a note$" "a note"
expect_in "$work/demo.out" "^a failing step \.\.\. FAILED \(exit 7 after [0-9]+ s\)$" "a step that fails"
expect_in "$work/demo.out" "^the cause of the failure$" "the log's tail"
expect_in "$work/demo.out" "^to stderr$" "the log's tail (stderr)"
expect_in "$work/demo.out" "the whole log: $work/demo/steps.log$" "the log's path after the failure"
grep -q "chatter" "$work/demo.out" && fail "a step that works printed its command's output"
grep -q "not reached" "$work/demo.out" && fail "the script went on after a failing step"
expect_in "$work/demo/steps.log" "^chatter 500$" "the log holds the chatty step's output"
expect_in "$work/demo/steps.log" "^=== a note$" "the log holds the note"

# 2. The two scripts with a configure step that fails.
for script in setup test; do
    build="$work/$script-build"
    status=0
    RAY_SKIP_INSTALL=1 RAY_BUILD_DIR="$build" RAY_CMAKE_ARGS="-DCMAKE_CXX_COMPILER=/nonexistent/c++" \
        bash "$source_dir/scripts/$script.sh" >"$work/$script.out" 2>&1 || status=$?
    echo "--- scripts/$script.sh with a compiler that does not exist (exit $status):"
    cat "$work/$script.out"
    [ "$status" -ne 0 ] || fail "$script.sh: a failing configure step should fail the script"
    log="$build/$script.log"
    [ "$script" = test ] && log="$build/test-build.log"
    [ -s "$log" ] || fail "$script.sh: no log at $log"
    lines=$(wc -l <"$work/$script.out")
    [ "$lines" -le 50 ] || fail "$script.sh: $lines lines for one failing step (the tail is 40)"
    expect_in "$work/$script.out" "^details in $log$" "$script.sh names its log"
    expect_in "$work/$script.out" "^Debian packages: not checked" "$script.sh: RAY_SKIP_INSTALL"
    expect_in "$work/$script.out" "^configuring .* \.\.\. FAILED \(exit [0-9]+" "$script.sh: the failing step"
    expect_in "$work/$script.out" "/nonexistent/c\+\+" "$script.sh: CMake's error, from the log's tail"
    expect_in "$work/$script.out" "the whole log: $log$" "$script.sh: the log's path after the failure"
    grep -q "^building" "$work/$script.out" && fail "$script.sh went on to build after configure failed"
done

if [ "$failures" -gt 0 ]; then
    echo "$failures failure(s)"
    exit 1
fi
echo "setup_script: all checks passed"

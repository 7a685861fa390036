# Sourced by scripts/setup.sh and scripts/test.sh: each step prints one line, what it does
# and how it ended, while its own output (apt's, CMake's, the compiler's) goes to one log
# file, whose path the first line names. A failing step prints the log's last lines and
# ends the script with the step's exit status, so that the cause shows without the noise
# of the steps that worked (issue 34: setup.sh printed 1,106 lines on a fresh machine).
#
#   steps_begin LOG      starts LOG afresh (its folder is created) and says where it is
#   step WHAT CMD...     runs CMD, its output appended to LOG: "WHAT ... ok (12 s)", or
#                        "WHAT ... FAILED (exit N after 12 s)", then LOG's tail, and exits
#   steps_note TEXT      one line to the terminal and to LOG
#
# RAY_LOG_TAIL: how many of the log's lines a failure shows (default 40).

steps_log=/dev/null

steps_begin() {
    steps_log="$1"
    mkdir -p "$(dirname "$steps_log")"
    : >"$steps_log"
    echo "details in $steps_log"
}

steps_note() {
    echo "$*"
    echo "=== $*" >>"$steps_log"
}

step() {
    local what="$1"
    shift
    local start=$SECONDS status=0
    printf '%s ... ' "$what"
    printf '\n=== %s: %s\n' "$what" "$*" >>"$steps_log"
    # `|| status=$?` rather than a bare command: the callers run under set -e.
    "$@" </dev/null >>"$steps_log" 2>&1 || status=$?
    local took=$((SECONDS - start))
    if [ "$status" -eq 0 ]; then
        echo "ok ($took s)"
        return 0
    fi
    echo "FAILED (exit $status after $took s)"
    echo "=== FAILED: $what (exit $status)" >>"$steps_log"
    local lines="${RAY_LOG_TAIL:-40}"
    echo "--- the last $lines lines of $steps_log:"
    tail -n "$lines" "$steps_log"
    echo "--- $what failed; the whole log: $steps_log"
    exit "$status"
}

# The Debian packages (scripts/install-deps.sh): one line when all are there, else the
# missing ones and an install step. RAY_SKIP_INSTALL set: neither checked nor installed.
steps_install_deps() {
    if [ -n "${RAY_SKIP_INSTALL:-}" ]; then
        steps_note "Debian packages: not checked (RAY_SKIP_INSTALL is set)"
        return 0
    fi
    local missing
    missing="$(bash scripts/install-deps.sh --missing)"
    if [ -z "$missing" ]; then
        steps_note "Debian packages: all present"
    else
        steps_note "Debian packages missing: $missing"
        step "installing them (apt-get)" bash scripts/install-deps.sh
    fi
}

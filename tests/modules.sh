#!/usr/bin/env bash
# ray's command modules (host/app/command_modules.h):
#   - the ray command links neither cpp-httplib (with OpenSSL) nor MPI: ldd lists none;
#   - a viewer module that is missing or is not one: `ray view` prints one message naming
#     it and RAY_VIEWER_MODULE, and exits 3;
#   - an MPI module that is missing, under mpirun -n 2: one message, exit 3, no hang.
# Usage: modules.sh RAY SCENE OUT_DIR [MPIRUN]
set -u
ray=$1 scene=$2 out=$3/modules mpirun=${4:-}
mkdir -p "$out"
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

linked=$(ldd "$ray" | grep -E "httplib|libssl|libcrypto|libmpi|libopen-(pal|rte)")
[ -z "$linked" ] || fail "ray links what only its modules should: $linked"

# $1 what, $2 the module named in the message, $3 exit code, $4 its stderr file.
one_message() {
    [ "$3" -eq 3 ] || fail "$1: exit $3, not 3"
    [ "$(grep -c "$2" "$4")" -eq 1 ] || { fail "$1: not one message naming $2"; cat "$4"; }
}

# Under `timeout`: a viewer that starts anyway would serve until stopped.
RAY_VIEWER_MODULE="$out/absent/libray_viewer.so" timeout -k 5 30 "$ray" view --port 0 "$scene" 2> "$out/viewer_absent.err"
one_message "viewer module absent" RAY_VIEWER_MODULE $? "$out/viewer_absent.err"
# A shared library that is not the viewer's module (it lacks the entry point).
RAY_VIEWER_MODULE="$(dirname "$ray")/libray_oiio.so" timeout -k 5 30 "$ray" view --port 0 "$scene" 2> "$out/viewer_wrong.err"
one_message "not the viewer module" "is not ray's viewer module" $? "$out/viewer_wrong.err"

if [ -n "$mpirun" ]; then
    export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1  # CI runs as root
    timeout -k 5 60 "$mpirun" -q --oversubscribe -n 2 -x RAY_MPI_MODULE="$out/absent/libray_mpi.so" \
        "$ray" "$scene" 32 24 -o "$out/mpi_absent.png" 2> "$out/mpi_absent.err"
    code=$?
    [ $code -ne 124 ] && [ $code -ne 137 ] || fail "MPI module absent: mpirun hung"
    one_message "MPI module absent" RAY_MPI_MODULE $code "$out/mpi_absent.err"
    [ ! -e "$out/mpi_absent.png" ] || fail "MPI module absent: an image was written"
fi

[ $failures -eq 0 ] && echo "modules: all passed"
exit $((failures > 0))

#!/usr/bin/env bash
# Compares the render speed of two (or more) builds of ray on one scene by alternating their
# runs, so that the drift of a shared machine's speed falls on all of them alike; prints the
# median and the fastest render seconds of each, and the median Mrays/s. The first run of
# each binary (its kernel compile) is left out of the median.
#
#   bench/ab.sh [-n RUNS] [-s WIDTHxHEIGHT] [-d DEPTH] SCENE BINARY... [-- RAY OPTIONS]
#   bench/ab.sh -n 8 ../shared/cs123/scenes/chess.xml /tmp/ray-before build/ray
#
# Default: 8 runs each at 1024x768, depth 4, --aa off, --device cpu.
set -euo pipefail

runs=8 size=1024x768 depth=4
while getopts "n:s:d:" opt; do
    case $opt in
        n) runs=$OPTARG ;;
        s) size=$OPTARG ;;
        d) depth=$OPTARG ;;
        *) sed -n '2,10p' "$0" >&2; exit 2 ;;
    esac
done
shift $((OPTIND - 1))
if [ $# -lt 2 ]; then sed -n '2,10p' "$0" >&2; exit 2; fi
scene=$1; shift
binaries=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do binaries+=("$1"); shift; done
[ "${1:-}" = "--" ] && shift
options=("$@")
[ ${#options[@]} -eq 0 ] && options=(--aa off --device cpu)

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
number() { sed -n "s/.*\"$1\": *\\([0-9.eE+-]*\\).*/\\1/p" "$2"; }

for ((run = 0; run <= runs; ++run)); do
    for ((b = 0; b < ${#binaries[@]}; ++b)); do
        "${binaries[$b]}" "$scene" "${size%x*}" "${size#*x}" "$depth" "${options[@]}" --quiet \
            --stats-json "$work/stats.json" -o "$work/image.png"
        ((run == 0)) && continue  # the first run compiles the kernel
        echo "$b $(number render_seconds "$work/stats.json") $(number total_rays "$work/stats.json")" >>"$work/times"
    done
done

for ((b = 0; b < ${#binaries[@]}; ++b)); do
    awk -v b="$b" '$1 == b { print $2, $3 }' "$work/times" | sort -g | awk -v name="${binaries[$b]}" '
        { t[++n] = $1; rays = $2 }
        END {
            median = n % 2 ? t[(n + 1) / 2] : (t[n / 2] + t[n / 2 + 1]) / 2
            printf "%-30s median %.4f s  fastest %.4f s  %.2f Mrays/s (median)  %d runs\n",
                   name, median, t[1], rays / median / 1e6, n
        }'
done

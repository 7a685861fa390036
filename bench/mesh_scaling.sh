#!/usr/bin/env bash
# ray against Intel Embree 3's bench on growing triangle meshes, in one command: for each grid
# of ../shared/embree/mesh_scenes.py (--grid 708, 1414, 2828: 1, 4 and 16 M triangles), each
# RAY binary and ../shared/embree's embree_bench run one after another on the same OBJ file,
# round after round, and one table gives each one's load, BVH build, render, peak memory and
# Mrays/s (medians over the rounds), and ray's over Embree's (docs/performance.md, "Meshes:
# memory and scaling").
#
#   bench/mesh_scaling.sh [RAY...] [-- OUT]   (from the checkout; RAY default build/ray,
#                                              OUT default bench/results/mesh_scaling)
#
# Environment: GRIDS (708,1414,2828), RUNS (3 rounds a grid), SIZE (1024x768), DEPTH (4),
# THREADS (2: Embree's build and tracing threads), SHARED (../shared beside the checkout, or
# $RAY_SHARED_DIR), MESHES (where the grids are written, default OUT/meshes: 16 M triangles
# are a 0.7 GB OBJ). ray: `ray mesh_grid.xml W H DEPTH --aa off --device cpu` and its
# --stats-json (load, "BVH build": the mesh's tree and records, render, Mrays/s); Embree:
# `embree_bench --modes p16 --runs 1 --warmup 0 --no-trace-only`, its 16-ray packets, one
# frame as ray's (load: its process's wall time less its build and frame: reading the OBJ
# and putting it in world space). Peak memory: each process's maximum resident set
# (/usr/bin/time -v); ray writes a PNG (a PPM or EXR would load OpenImageIO's libraries, whose
# pages count too). Writes OUT/runs.jsonl (one line a run), OUT/summary.json, OUT/summary.md.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
if [[ ${1:-} == -h || ${1:-} == --help ]]; then
    sed -n '2,21p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'
    exit 0
fi
rays=()
while [[ $# -gt 0 && $1 != -- ]]; do rays+=("$(readlink -f "$1")"); shift; done
[[ ${1:-} == -- ]] && shift
[[ ${#rays[@]} -eq 0 ]] && rays=("$(readlink -f "$here/../build/ray")")
out=$(realpath -m "${1:-$here/results/mesh_scaling}")
shared=${SHARED:-${RAY_SHARED_DIR:-$here/../../shared}}
grids=${GRIDS:-708,1414,2828}
runs=${RUNS:-3}
size=${SIZE:-1024x768}
depth=${DEPTH:-4}
threads=${THREADS:-2}
meshes=$(realpath -m "${MESHES:-$out/meshes}")
for ray in "${rays[@]}"; do
    [[ -x $ray ]] || { echo "mesh_scaling.sh: $ray is not an executable: build ray first" >&2; exit 2; }
done
[[ -f $shared/embree/embree_bench.cpp ]] || { echo "mesh_scaling.sh: no $shared/embree: set SHARED" >&2; exit 2; }
[[ -x /usr/bin/time ]] || { echo "mesh_scaling.sh: no /usr/bin/time (Debian's package time)" >&2; exit 2; }
[[ $size =~ ^([0-9]+)x([0-9]+)$ ]] || { echo "mesh_scaling.sh: SIZE is WIDTHxHEIGHT, not $size" >&2; exit 2; }
width=${BASH_REMATCH[1]} height=${BASH_REMATCH[2]}
[[ $grids =~ ^[0-9]+(,[0-9]+)*$ ]] || { echo "mesh_scaling.sh: GRIDS is a list of cells a side (708,1414)" >&2; exit 2; }
[[ $runs =~ ^[1-9][0-9]*$ ]] || { echo "mesh_scaling.sh: RUNS is a count of rounds, not $runs" >&2; exit 2; }
mkdir -p "$out/work"

# Embree 3's bench, built as ../shared/embree/run.sh builds it.
if [[ ! -f /usr/include/embree3/rtcore.h ]]; then
    echo "mesh_scaling.sh: no Embree 3 headers: apt-get install libembree-dev" >&2
    exit 2
fi
bench=$out/work/embree_bench
if [[ ! -x $bench || $shared/embree/embree_bench.cpp -nt $bench ]]; then
    echo "mesh_scaling.sh: building $bench" >&2
    g++ -O2 -std=c++20 -march=native -Wall -o "$bench" "$shared/embree/embree_bench.cpp" -lembree3 -lpthread
fi

# One run of a command: its JSON report, and /usr/bin/time's peak resident set and wall time,
# as one line of OUT/runs.jsonl.
timed() {  # GRID TOOL JSON COMMAND...
    local grid=$1 tool=$2 json=$3
    shift 3
    local load
    load=$(cut -d' ' -f1 /proc/loadavg)
    /usr/bin/time -v -o "$out/work/time.txt" "$@" >"$out/work/out.txt" 2>&1 ||
        { echo "mesh_scaling.sh: $* failed:" >&2; tail -5 "$out/work/out.txt" >&2; exit 1; }
    /usr/bin/python3 - "$grid" "$tool" "$json" "$out/work/time.txt" "$load" >>"$out/runs.jsonl" <<'PY'
import json, sys
grid, tool, report, timefile, load = sys.argv[1:]
t = {}
for line in open(timefile):
    key, _, value = line.strip().rpartition(": ")
    t[key] = value
wall = t["Elapsed (wall clock) time (h:mm:ss or m:ss)"].split(":")
seconds = sum(float(x) * 60 ** i for i, x in enumerate(reversed(wall)))
print(json.dumps({"grid": int(grid), "tool": tool, "load_average": float(load), "wall_seconds": seconds,
                  "peak_rss_bytes": int(t["Maximum resident set size (kbytes)"]) * 1024,
                  "report": json.load(open(report))}))
PY
}

: >"$out/runs.jsonl"
IFS=, read -r -a grid_list <<<"$grids"
for grid in "${grid_list[@]}"; do
    dir=$meshes/grid-$grid
    if [[ ! -f $dir/mesh_grid.xml || ! -f $dir/grid.obj ]]; then
        echo "mesh_scaling.sh: writing the $grid-cell grid into $dir" >&2
        /usr/bin/python3 "$shared/embree/mesh_scenes.py" "$dir" --grid "$grid" >&2
    fi
    /usr/bin/python3 "$shared/embree/scene_to_prims.py" "$dir/mesh_grid.xml" -o "$dir/mesh_grid.prims" >/dev/null
    for ((round = 1; round <= runs; round++)); do
        echo "mesh_scaling.sh: grid $grid, round $round of $runs (load $(cut -d' ' -f1 /proc/loadavg))" >&2
        for n in "${!rays[@]}"; do
            timed "$grid" "ray$n" "$out/work/ray.json" "${rays[$n]}" "$dir/mesh_grid.xml" "$width" "$height" "$depth" \
                --aa off --device cpu --quiet -o "$out/work/ray.png" --stats-json "$out/work/ray.json"
        done
        timed "$grid" embree "$out/work/embree.json" "$bench" "$dir/mesh_grid.prims" --size "$width" "$height" \
            --depth "$depth" --threads "$threads" --runs 1 --warmup 0 --modes p16 --no-trace-only \
            --json "$out/work/embree.json"
    done
done

/usr/bin/python3 - "$out" "${rays[@]}" <<'EOF'
import json, statistics, sys
out, rays = sys.argv[1], sys.argv[2:]
runs = [json.loads(line) for line in open(f"{out}/runs.jsonl")]
med = statistics.median

def figures(run):
    r = run["report"]
    if run["tool"] == "embree":
        frame = r["modes"]["p16"]
        load = run["wall_seconds"] - r["bvh_build_seconds"] - frame["frame_seconds"]
        return {"triangles": r["triangles"], "load": load, "build": r["bvh_build_seconds"],
                "render": frame["frame_seconds"], "mrays": frame["mrays_per_second"]}
    return {"triangles": r["mesh_triangles"], "load": r["load_seconds"], "build": r["bvh_build_seconds"],
            "render": r["render_seconds"], "mrays": r["mrays_per_second"]}

rows = []
for grid in sorted({run["grid"] for run in runs}):
    tools = {}
    for run in runs:
        if run["grid"] == grid:
            f = figures(run)
            f.update(peak=run["peak_rss_bytes"], wall=run["wall_seconds"])
            tools.setdefault(run["tool"], []).append(f)
    loads = [run["load_average"] for run in runs if run["grid"] == grid]
    e = {k: med([f[k] for f in tools["embree"]]) for k in tools["embree"][0]}
    for n, ray in enumerate(rays):
        r = {k: med([f[k] for f in tools[f"ray{n}"]]) for k in tools[f"ray{n}"][0]}
        rows.append({"grid": grid, "ray": ray, "rounds": len(tools[f"ray{n}"]), "ray_figures": r, "embree_figures": e,
                     "load_average": [min(loads), max(loads)]})

lines = ["| triangles | ray | load (ray / Embree) | BVH build | render | whole run | peak memory | peak / Embree "
         "(≤ 1.25) | bytes a triangle at peak | Mrays/s (ray / Embree p16) | 1-min load |",
         "|---|---|---|---|---|---|---|---|---|---|---|"]
for row in rows:
    r, e = row["ray_figures"], row["embree_figures"]
    pair = lambda k, unit: f"{r[k]:.3g} / {e[k]:.3g} {unit} ({r[k] / e[k]:.2f}×)"
    lines.append(f"| {r['triangles'] / 1e6:.1f} M | {row['ray']} | {pair('load', 's')} | {pair('build', 's')} | "
                 f"{pair('render', 's')} | {pair('wall', 's')} | {r['peak'] / 1e6:.0f} / {e['peak'] / 1e6:.0f} MB | "
                 f"{r['peak'] / e['peak']:.2f} | {r['peak'] / r['triangles']:.0f} / {e['peak'] / e['triangles']:.0f} | "
                 f"{r['mrays']:.2f} / {e['mrays']:.2f} ({r['mrays'] / e['mrays']:.2f}×) | "
                 f"{row['load_average'][0]:.1f}-{row['load_average'][1]:.1f} |")
json.dump(rows, open(f"{out}/summary.json", "w"), indent=2)
text = "\n".join(lines) + f"\n\nMedians of {rows[0]['rounds'] if rows else 0} rounds; ray's load, build and render from its --stats-json, Embree's from its bench (load: its wall time less build and frame).\n"
open(f"{out}/summary.md", "w").write(text)
print(text)
EOF

#!/usr/bin/env bash
# ray against Intel Embree 3's 16-ray packets on the scenes of docs/performance.md ("Past
# Embree's packets"), in one command: for each scene, ../shared/embree/run.sh times ray and
# Embree alternately on the same rays; this script collects the runs into one table of
# ray's Mrays/s over Embree's (single rays and 16-ray packets, whole frame) beside the
# targets (1.5x Embree's packets on the course scenes, 1.0x on the two mesh scenes).
#
#   bench/embree_ratio.sh [RAY...] [-- OUT]   (from the checkout; RAY default build/ray,
#                                              OUT default bench/results/embree_ratio)
#
# Several RAY binaries are measured one after another on each scene (give the build before a
# change and after it to see both against the same Embree figures of that hour).
# Environment: SCENES (chess,ray_killer,recursiveCones4,mesh_grid,dragons), RUNS (5
# alternating pairs a scene and binary), SHARED (../shared beside the checkout, or
# $RAY_SHARED_DIR). The mesh scenes are written by ../shared/embree/mesh_scenes.py into
# OUT/mesh_scenes. Writes OUT/SCENE-N.txt (run.sh's report for binary N), OUT/summary.json
# and OUT/summary.md.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
if [[ ${1:-} == -h || ${1:-} == --help ]]; then
    sed -n '2,17p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'
    exit 0
fi
rays=()
while [[ $# -gt 0 && $1 != -- ]]; do rays+=("$(readlink -f "$1")"); shift; done
[[ ${1:-} == -- ]] && shift
[[ ${#rays[@]} -eq 0 ]] && rays=("$(readlink -f "$here/../build/ray")")
out=$(realpath -m "${1:-$here/results/embree_ratio}")
shared=${SHARED:-${RAY_SHARED_DIR:-$here/../../shared}}
scenes=${SCENES:-chess,ray_killer,recursiveCones4,mesh_grid,dragons}
runs=${RUNS:-5}
for ray in "${rays[@]}"; do
    [[ -x $ray ]] || { echo "embree_ratio.sh: $ray is not an executable: build ray first" >&2; exit 2; }
done
[[ -x $shared/embree/run.sh ]] || { echo "embree_ratio.sh: no $shared/embree/run.sh: set SHARED" >&2; exit 2; }
mkdir -p "$out"

scene_file() {
    case $1 in
        mesh_grid | dragons)
            [[ -f $out/mesh_scenes/$1.xml ]] || /usr/bin/python3 "$shared/embree/mesh_scenes.py" "$out/mesh_scenes" >&2
            echo "$out/mesh_scenes/$1.xml" ;;
        *) echo "$shared/cs123/scenes/$1.xml" ;;
    esac
}

IFS=, read -r -a scene_list <<<"$scenes"
for scene in "${scene_list[@]}"; do
    file=$(scene_file "$scene")
    for n in "${!rays[@]}"; do
        echo "embree_ratio.sh: $scene, ${rays[$n]} ($runs alternating pairs)" >&2
        WORK="$out/work" RUNS=$runs "$shared/embree/run.sh" "${rays[$n]}" "$file" >"$out/$scene-$n.txt"
        cp "$out/work/summary.json" "$out/$scene-$n.json"
    done
done

/usr/bin/python3 - "$out" "$scenes" "${rays[@]}" <<'EOF'
import json, sys
out, scenes, rays = sys.argv[1], sys.argv[2].split(","), sys.argv[3:]
target = {"mesh_grid": 1.0, "dragons": 1.0}
rows, lines = [], ["| scene | ray | ray Mrays/s | Embree single | Embree 16-ray packets | ray / Embree 16 | target |",
                   "|---|---|---:|---:|---:|---:|---:|"]
for scene in scenes:
    for n, ray in enumerate(rays):
        s = json.load(open(f"{out}/{scene}-{n}.json"))
        r = s["ray_mrays_per_second"]
        single = s["embree_frame"]["single"]["mrays_per_second"]
        p16 = s["embree_frame"]["p16"]["mrays_per_second"]
        rows.append({"scene": scene, "ray": ray, "ray_mrays_per_second": r, "embree_single": single,
                     "embree_p16": p16, "ratio_p16": r / p16, "target": target.get(scene, 1.5)})
        lines.append(f"| {scene} | {ray} | {r:.1f} | {single:.1f} | {p16:.1f} | {r / p16:.2f} | "
                     f"≥ {target.get(scene, 1.5):.1f} |")
json.dump(rows, open(f"{out}/summary.json", "w"), indent=2)
text = "\n".join(lines) + "\n"
open(f"{out}/summary.md", "w").write(text)
print(text)
EOF

#!/usr/bin/env bash
# ray on the CPU against its two anchors, in one run: Intel Embree 3 (the limit: the same
# rays through the best CPU traversal there is, ../shared/embree/run.sh) and POV-Ray 3.7
# (the peer a user would pick instead, bench/povray_side_by_side.py), then one summary
# against the targets of docs/performance.md ("On CPUs: ray packets").
#
#   bench/cpu_limits.sh [RAY] [OUT]     (from the checkout; RAY default build/ray,
#                                        OUT default bench/results/cpu_limits)
#
# Environment: RUNS (5: alternating pairs for Embree, runs of each for POV-Ray), SCENES
# (chess,ray_killer,recursiveCones4,spheres_1e4,spheres_1e5: the POV-Ray scenes), SHARED
# (../shared beside the checkout, or $RAY_SHARED_DIR). Embree (libembree-dev) is a bench
# dependency alone, installed by run.sh when missing and never linked into ray; POV-Ray
# comes from scripts/install-deps.sh --bench. Writes OUT/embree.txt, OUT/embree.json,
# OUT/povray.md, OUT/povray.json and OUT/summary.md.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
if [[ ${1:-} == -h || ${1:-} == --help ]]; then
    sed -n '2,15p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'
    exit 0
fi
ray=$(readlink -f "${1:-$here/../build/ray}")
out=${2:-$here/results/cpu_limits}
shared=${SHARED:-${RAY_SHARED_DIR:-$here/../../shared}}
runs=${RUNS:-5}
scenes=${SCENES:-chess,ray_killer,recursiveCones4,spheres_1e4,spheres_1e5}
[[ -x $ray ]] || { echo "cpu_limits.sh: $ray is not an executable: build ray first (cmake --build build)" >&2; exit 2; }
[[ -x $shared/embree/run.sh ]] || { echo "cpu_limits.sh: no $shared/embree/run.sh: set SHARED" >&2; exit 2; }
mkdir -p "$out"

echo "cpu_limits.sh: Embree on chess ($runs alternating pairs)" >&2
WORK="$out/embree_work" RUNS=$runs "$shared/embree/run.sh" "$ray" | tee "$out/embree.txt"
cp "$out/embree_work/summary.json" "$out/embree.json"

echo "cpu_limits.sh: POV-Ray on $scenes ($runs runs each)" >&2
/usr/bin/python3 "$here/povray_side_by_side.py" --ray "$ray" --shared "$shared" --out "$out" \
    --runs "$runs" --scenes "$scenes"

/usr/bin/python3 - "$out" <<'EOF'
import json, sys
out = sys.argv[1]
embree = json.load(open(f"{out}/embree.json"))
pov = json.load(open(f"{out}/povray.json"))["rows"]
ray = embree["ray_mrays_per_second"]
single = embree["embree_frame"]["single"]["mrays_per_second"]
lines = ["| measure | figure | target |", "|---|---:|---:|",
         f"| chess: ray Mrays/s / Embree single rays ({ray:.1f} / {single:.1f}) | {ray / single:.2f} | ≥ 0.80 |"]
def ratio(row, key):  # absent where a run of either program failed
    return f"{row[key]:.2f}" if row.get(key) else "–"
for r in pov:
    lines.append(f"| {r['scene']}: ray Mrays/s / POV-Ray's | {ratio(r, 'mrays_ratio')} | ≥ 3 |")
    lines.append(f"| {r['scene']}: POV-Ray wall s / ray's | {ratio(r, 'wall_ratio')} | ≥ 3 |")
text = "\n".join(lines) + "\n"
open(f"{out}/summary.md", "w").write(text)
print(text)
EOF

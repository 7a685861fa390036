"""An edit and its frame in a long-lived renderer, against a plain frame and a whole `ray`
process rendering the same view (issue 33's incremental re-render).

Usage: /usr/bin/python3 bench/edit_frame.py [--ray build/ray] [--scene chess.xml]
       [--size 320x240] [--device cpu] [--runs 15] [--edit material|light|transform] [--json FILE]

Each round runs, alternating so that a machine's drift weighs on all three alike:
  frame    renderer.render() with nothing edited (the median frame);
  edit     one edit to renderer.scene, then renderer.render();
  process  `ray SCENE W H --aa off --device D --quiet -o tmp.png`, from start to exit.
Reported: each one's median (and min, max), the edited frames' pack / BVH / upload seconds,
and the two checks of the issue: edit <= 1.25 * frame + 5 ms, edit <= process / 2.

--edit material: object.set_material (a diffuse color) where the module has the scene document
(scene.objects), else scene.add_material: either repacks and uploads the material table only.
--edit light: scene.add_light (a faint point light): the light table only.
--edit transform: object.set_transform (moved up a little each round): its records, the tree
refitted (no BVH build).
Needs PYTHONPATH to hold the cs123ray module (build/python)."""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import cs123ray

root = Path(__file__).resolve().parents[1]
parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--ray", default=str(root / "build" / "ray"))
parser.add_argument("--scene", default=str(root.parent / "shared" / "cs123" / "scenes" / "chess.xml"))
parser.add_argument("--size", default="320x240")
parser.add_argument("--device", default="cpu")
parser.add_argument("--runs", type=int, default=15)
parser.add_argument("--edit", choices=["material", "light", "transform"], default="material")
parser.add_argument("--json")
args = parser.parse_args()
width, height = (int(v) for v in args.size.split("x"))

renderer = cs123ray.Renderer(cs123ray.load_scene(args.scene), device=args.device)
renderer.set_options(width=width, height=height, aa="off")
renderer.render()  # the first frame packs, uploads and builds the kernel: not what is measured
renderer.render()
scene = renderer.scene
objects = getattr(scene, "objects", None)


def edit(i):
    """One edit, different each time (so that every one changes a table)."""
    shade = (i % 10) / 10
    if args.edit == "light":
        scene.add_light("point", color=(0.001, 0.001, 0.001), position=(0, 6 + i, 0))
    elif args.edit == "transform":
        target = objects[len(objects) // 2]
        target.set_transform(cs123ray.Transform.translate(0, 0.001, 0) @ target.transform)
    elif objects is not None:
        target = objects[len(objects) // 2]
        target.set_material(diffuse=(shade, 0.2, 0.2))
    else:
        scene.add_material(diffuse=(shade, 0.2, 0.2))


output = Path(tempfile.mkdtemp(prefix="edit_frame_")) / "frame.png"
command = [args.ray, args.scene, str(width), str(height), "--aa", "off", "--device", args.device, "--quiet",
           "-o", str(output)]
frame, edited, process, tables = [], [], [], []
for i in range(args.runs):
    start = time.perf_counter()
    renderer.render()
    frame.append(time.perf_counter() - start)

    start = time.perf_counter()
    edit(i)
    renderer.render()
    edited.append(time.perf_counter() - start)
    stats = renderer.stats
    tables.append((stats["pack_seconds"], stats["bvh_build_seconds"], stats["upload_seconds"]))

    start = time.perf_counter()
    subprocess.run(command, check=True)
    process.append(time.perf_counter() - start)


def summary(values):
    return {"median_ms": statistics.median(values) * 1e3, "min_ms": min(values) * 1e3, "max_ms": max(values) * 1e3}


result = {
    "scene": args.scene, "size": args.size, "device": args.device, "runs": args.runs, "edit": args.edit,
    "edit_api": {"material": "set_material" if objects is not None else "add_material", "light": "add_light",
                 "transform": "set_transform"}[args.edit],
    "frame": summary(frame), "edit_and_frame": summary(edited), "ray_process": summary(process),
    "edited_pack_ms_median": statistics.median(t[0] for t in tables) * 1e3,
    "edited_bvh_build_seconds_max": max(t[1] for t in tables),
    "edited_upload_ms_median": statistics.median(t[2] for t in tables) * 1e3,
}
m_frame, m_edit, m_process = (statistics.median(v) for v in (frame, edited, process))
result["edit_within_25_percent_plus_5_ms"] = m_edit <= 1.25 * m_frame + 0.005
result["edit_within_half_a_process"] = m_edit <= 0.5 * m_process
print(f"{args.scene} {args.size} --aa off on {args.device}, {args.runs} alternating rounds, edit: {result['edit_api']}")
for name, values in (("frame", frame), ("edit + frame", edited), ("ray process", process)):
    s = summary(values)
    print(f"  {name:13s} median {s['median_ms']:8.2f} ms  (min {s['min_ms']:.2f}, max {s['max_ms']:.2f})")
print(f"  edited frames: pack {result['edited_pack_ms_median']:.3f} ms, upload {result['edited_upload_ms_median']:.3f} ms "
      f"(medians), BVH build at most {result['edited_bvh_build_seconds_max']} s")
print(f"  edit + frame <= 1.25 x frame + 5 ms: {result['edit_within_25_percent_plus_5_ms']} "
      f"({m_edit * 1e3:.2f} <= {(1.25 * m_frame + 0.005) * 1e3:.2f})")
print(f"  edit + frame <= ray process / 2:    {result['edit_within_half_a_process']} "
      f"({m_edit * 1e3:.2f} <= {m_process * 1e3 / 2:.2f})")
if args.json:
    Path(args.json).write_text(json.dumps(result, indent=2) + "\n")
sys.exit(0 if result["edit_within_25_percent_plus_5_ms"] and result["edit_within_half_a_process"] else 1)

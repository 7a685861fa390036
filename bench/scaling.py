#!/usr/bin/env python3
"""Several devices and several ranks on one frame, side by side on this machine.

Renders one scene with each configuration below, alternating them round after round so
that the machine's drift falls on all alike, and prints a Markdown table: the whole
process's wall time (what a user waits for) and the render's, their ratio to one device
in one process, the tiles each rank and device kept, and for MPI the hand-out cost (the
messages and bytes rank 0 handled and its time per tile).

  bench/scaling.py [--ray build/ray] [--scene ../shared/cs123/scenes/chess.xml]
                   [--size 1024x768] [--rounds 3] [--ranks 1,2,4] [--json out.json]

Configurations: one PoCL pthread device; two ("pthread pthread", --device all: they share
one thread pool, so this measures the scheduler's overhead, not a speed-up); the
fast/slow pair "pthread basic" against its pthread device alone; mpirun -n 1, 2, 4 on
this machine's one device per rank (on a 2-core machine the ranks share the cores: the
table shows the overhead, not a speed-up). The first round (kernel builds into fresh
caches) is left out of the medians.
"""
import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


def configurations(ranks):
    """(name, environment, launcher, device options) of each row."""
    one = {"POCL_DEVICES": "pthread"}
    yield "1 device (pthread)", one, [], ["--device", "0"]
    yield "2 devices (pthread pthread)", {"POCL_DEVICES": "pthread pthread"}, [], ["--device", "all"]
    yield "pthread alone (of pthread basic)", {"POCL_DEVICES": "pthread basic"}, [], ["--device", "0"]
    yield "pthread + basic", {"POCL_DEVICES": "pthread basic"}, [], ["--device", "all"]
    mpirun = shutil.which("mpirun")
    if not mpirun:
        print("note: no mpirun; the MPI rows are left out", file=sys.stderr)
        return
    as_root = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1"}
    for n in ranks:
        yield f"mpirun -n {n}", dict(one, **as_root), [mpirun, "-q", "--oversubscribe", "-n", str(n)], ["--device", "0"]


def run_once(ray, config, scene, size, work):
    _, env_extra, launcher, device = config
    stats_file = work / "stats.json"
    args = launcher + [ray, str(scene), str(size[0]), str(size[1])] + device + [
        "--quiet", "--stats-json", str(stats_file), "-o", str(work / "image.png")]
    env = dict(os.environ, RAY_CACHE_DIR=str(work / "cache"), **env_extra)
    start = time.perf_counter()
    done = subprocess.run(args, env=env, capture_output=True, text=True, timeout=1200)
    wall = time.perf_counter() - start
    if done.returncode != 0:
        raise SystemExit(f"{' '.join(args)} exited {done.returncode}:\n{done.stderr}")
    return wall, json.loads(stats_file.read_text())


def tiles_by_device(stats):
    devices = stats["devices"]
    if "mpi" in stats:
        return "/".join(str(t) for t in stats["mpi"]["tiles_per_rank"]) + " by rank"
    if len(devices) < 2:
        return "all"
    return "/".join(str(d["tiles"]) for d in devices) + " by device"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--ray", default=str(HERE.parent / "build" / "ray"))
    parser.add_argument("--scene", default=str(HERE.parent.parent / "shared" / "cs123" / "scenes" / "chess.xml"))
    parser.add_argument("--size", default="1024x768")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--ranks", default="1,2,4")
    parser.add_argument("--json")
    args = parser.parse_args()
    size = tuple(int(v) for v in args.size.split("x"))
    ranks = [int(n) for n in args.ranks.split(",")]
    configs = list(configurations(ranks))
    results = {config[0]: [] for config in configs}
    with tempfile.TemporaryDirectory() as temp:
        work = Path(temp)
        for round_index in range(args.rounds + 1):
            for config in configs:
                wall, stats = run_once(args.ray, config, args.scene, size, work)
                if round_index > 0:
                    results[config[0]].append((wall, stats))
            print(f"round {round_index} done", file=sys.stderr)

    base_name = configs[0][0]
    base_wall = statistics.median(w for w, _ in results[base_name])
    base_render = statistics.median(s["render_seconds"] for _, s in results[base_name])
    print(f"{Path(args.scene).name} {size[0]}x{size[1]}, median of {args.rounds} rounds, "
          f"{os.cpu_count()} cores\n")
    print("| configuration | whole process s | render s | process vs 1 device | tiles kept | "
          "rank 0: messages, bytes | rank 0 ms a tile |")
    print("|---|---|---|---|---|---|---|")
    table = []
    for config in configs:
        name = config[0]
        runs = results[name]
        wall = statistics.median(w for w, _ in runs)
        render = statistics.median(s["render_seconds"] for _, s in runs)
        last = runs[-1][1]
        mpi = last.get("mpi")
        handout = f"{mpi['messages']}, {mpi['bytes'] / 1e6:.2f} MB" if mpi else "-"
        per_tile = f"{statistics.median(s['mpi']['dispatch_ms_per_tile'] for _, s in runs):.3f}" if mpi else "-"
        print(f"| {name} | {wall:.2f} | {render:.2f} | {base_wall / wall:.2f}x | {tiles_by_device(last)} "
              f"| {handout} | {per_tile} |")
        table.append({"configuration": name, "wall_seconds": wall, "render_seconds": render,
                      "tiles": tiles_by_device(last), "mpi": mpi})
    print(f"\n(one device: whole process {base_wall:.2f} s, render {base_render:.2f} s)")
    if args.json:
        Path(args.json).write_text(json.dumps(table, indent=2) + "\n")


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""ray against POV-Ray 3.7, side by side in one run, as a user would time them.

For each scene, ray and POV-Ray run alternately (ray, povray, ray, povray, ...) so that the
drift of a shared machine's speed falls on both alike. Every run is a whole child process:
the bench measures its wall time and peak resident memory from outside (os.wait4), and reads
the render/trace time and ray counts each program reports itself (ray: --stats-json; POV-Ray:
its statistics on stderr). The table gives medians and the ratios ray / POV-Ray.

    bench/povray_side_by_side.py [--runs 5] [--size 1024x768] [--depth 4] [--quick]
                                 [--ray build/ray] [--shared ../shared] [--out DIR]
                                 [--scenes chess,ray_killer,...] [--no-recursive]

The scenes are converted primitive for primitive by ../shared/povray/cs123_to_pov.py, which
also gives POV-Ray's command line (no antialiasing, 2 threads, no display, linear output).
Conversions are cached in the output folder (recursiveSpheres10's takes ~40 s and 540 MB).
Outputs: DIR/povray.md (the table), DIR/povray.json (every run), DIR/povray_ratios.png and
DIR/povray_scaling.png (matplotlib, when it is installed).

Needs the Debian packages povray, python3-numpy (the converter) and python3-matplotlib (the
plots; scripts/install-deps.sh --bench installs them); this script and the converter run on
Debian's python3, not on another one on PATH.
"""
import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
DEBIAN_PYTHON = "/usr/bin/python3"

# Scene name -> how to get it: ("corpus", file stem) or ("spheres", count).
SCENES = {
    "chess": ("corpus", "chess"),
    "ray_killer": ("corpus", "ray_killer"),
    "recursiveCones4": ("corpus", "recursiveCones4"),
    "spheres_1e3": ("spheres", 1000),
    "spheres_1e4": ("spheres", 10000),
    "spheres_1e5": ("spheres", 100000),
    "recursiveSpheres10": ("corpus", "recursiveSpheres10"),
}
SCALING = ["spheres_1e3", "spheres_1e4", "spheres_1e5"]


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=5, help="runs of each program per scene (median)")
    ap.add_argument("--size", default="1024x768")
    ap.add_argument("--depth", type=int, default=4)
    ap.add_argument("--quick", action="store_true", help="256x192, 2 runs, no recursiveSpheres10")
    ap.add_argument("--ray", type=Path, default=HERE.parent / "build" / "ray")
    ap.add_argument("--shared", type=Path, default=Path(os.environ.get("RAY_SHARED_DIR", HERE.parent.parent / "shared")))
    ap.add_argument("--out", type=Path, default=HERE / "results")
    ap.add_argument("--scenes", default=",".join(SCENES), help="comma-separated subset of: " + ", ".join(SCENES))
    ap.add_argument("--no-recursive", action="store_true", help="leave out recursiveSpheres10")
    ap.add_argument("--device", default="cpu", help="ray's --device (default cpu)")
    a = ap.parse_args()
    if a.quick:
        a.size, a.runs, a.no_recursive = "256x192", 2, True
    a.width, a.height = (int(v) for v in a.size.lower().split("x"))
    a.scene_list = [s for s in a.scenes.split(",") if s]
    unknown = [s for s in a.scene_list if s not in SCENES]
    if unknown:
        ap.error("unknown scene(s): " + ", ".join(unknown))
    if a.no_recursive and "recursiveSpheres10" in a.scene_list:
        a.scene_list.remove("recursiveSpheres10")
    return a


def run_measured(argv, env=None, cwd=None):
    """Runs argv as a child process; returns (exit code, wall seconds, peak MiB, stderr text)."""
    with tempfile.TemporaryFile() as err:
        start = time.perf_counter()
        proc = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=err, env=env, cwd=cwd)
        _, status, usage = os.wait4(proc.pid, 0)
        wall = time.perf_counter() - start
        proc.returncode = os.waitstatus_to_exitcode(status)
        err.seek(0)
        text = err.read().decode(errors="replace")
    return proc.returncode, wall, usage.ru_maxrss / 1024.0, text


def prepare_scene(name, a, work):
    """Writes (or finds) the scene's XML and its POV-Ray conversion; returns (xml, pov) or None."""
    kind, what = SCENES[name]
    if kind == "corpus":
        xml = a.shared / "cs123" / "scenes" / (what + ".xml")
        if not xml.exists():
            print(f"skipping {name}: {xml} not found", file=sys.stderr)
            return None
    else:
        xml = work / f"{name}.xml"
        if not xml.exists():
            subprocess.run([DEBIAN_PYTHON, str(a.shared / "povray" / "spheres.py"), str(what), "-o", str(xml)], check=True)
    pov = work / f"{name}_{a.width}x{a.height}_d{a.depth}.pov"
    if not pov.exists():
        print(f"converting {name} for POV-Ray ...", file=sys.stderr, flush=True)
        tmp = pov.with_suffix(".pov.part")
        subprocess.run([DEBIAN_PYTHON, str(a.shared / "povray" / "cs123_to_pov.py"), str(xml), "-o", str(tmp),
                        "--width", str(a.width), "--height", str(a.height), "--depth", str(a.depth),
                        "--search", str(xml.parent)], check=True, stderr=subprocess.DEVNULL)
        tmp.rename(pov)
    return xml, pov


def ray_run(a, xml, work):
    stats = work / "ray_stats.json"
    argv = [str(a.ray), str(xml), str(a.width), str(a.height), str(a.depth), "--aa", "off",
            "--device", a.device, "--quiet", "--stats-json", str(stats), "-o", str(work / "ray.png")]
    code, wall, mib, err = run_measured(argv)
    if code != 0:
        return {"status": f"exit {code}", "stderr": err[-500:]}
    s = json.loads(stats.read_text())
    return {"status": "ok", "wall_s": wall, "peak_mib": mib, "render_s": s["render_seconds"],
            "load_s": s.get("load_seconds", 0.0), "rays": s["total_rays"],
            "mrays": s["total_rays"] / s["render_seconds"] / 1e6 if s["render_seconds"] > 0 else 0.0}


# POV-Ray's statistics (stderr): camera rays, shadow tests, and reflected/refracted rays.
POV_COUNTS = {
    "camera": re.compile(r"^Rays:\s+(\d+)", re.M),
    "shadow": re.compile(r"^Shadow Ray Tests:\s+(\d+)", re.M),
    "reflected": re.compile(r"^Reflected Rays:\s+(\d+)", re.M),
    "refracted": re.compile(r"^Refracted Rays:\s+(\d+)", re.M),
    "transmitted": re.compile(r"^Transmitted Rays:\s+(\d+)", re.M),
}
POV_TIME = {
    "trace_s": re.compile(r"Trace Time:.*\(([\d.]+) seconds\)"),
    "parse_s": re.compile(r"Parse Time:.*\(([\d.]+) seconds\)"),
    "bound_s": re.compile(r"Bounding Time:.*\(([\d.]+) seconds\)"),
}


def pov_run(a, pov, work):
    argv = ["povray", f"+I{pov}", f"+W{a.width}", f"+H{a.height}", "-A", "+WT2", "-D",
            f"+O{work / 'pov.png'}", "+FN", "File_Gamma=1.0"]
    code, wall, mib, err = run_measured(argv, cwd=str(work))
    times = {k: float(m.group(1)) if (m := r.search(err)) else 0.0 for k, r in POV_TIME.items()}
    if code != 0 or times["trace_s"] <= 0:
        return {"status": f"exit {code}", "stderr": err[-500:]}
    rays = sum(int(m.group(1)) for r in POV_COUNTS.values() if (m := r.search(err)))
    return {"status": "ok", "wall_s": wall, "peak_mib": mib, "render_s": times["trace_s"],
            "load_s": times["parse_s"] + times["bound_s"], "rays": rays, "mrays": rays / times["trace_s"] / 1e6}


def median_of(runs, key):
    values = [r[key] for r in runs if r["status"] == "ok"]
    return statistics.median(values) if values else None


def summarize(name, ray_runs, pov_runs):
    row = {"scene": name}
    for who, runs in (("ray", ray_runs), ("pov", pov_runs)):
        for key in ("wall_s", "render_s", "load_s", "mrays", "peak_mib"):
            row[f"{who}_{key}"] = median_of(runs, key)
    if row["ray_mrays"] and row["pov_mrays"]:
        row["mrays_ratio"] = row["ray_mrays"] / row["pov_mrays"]
    if row["ray_wall_s"] and row["pov_wall_s"]:
        row["wall_ratio"] = row["pov_wall_s"] / row["ray_wall_s"]
    return row


def fmt(v, spec=".2f"):
    return "–" if v is None else format(v, spec)


def markdown_table(rows, a):
    lines = [f"{a.width}×{a.height}, depth {a.depth}, `--aa off --device {a.device}` against POV-Ray 3.7 "
             f"`+WT2 -A`; medians of {a.runs} alternating whole-process runs. Speed-ups are POV-Ray / ray "
             "for time and ray / POV-Ray for Mrays/s (above 1: ray is ahead).", "",
             "| scene | ray Mrays/s | POV-Ray Mrays/s | × Mrays/s | ray wall s | POV-Ray wall s | × wall | "
             "ray load s | POV-Ray parse+bound s | peak MiB ray / POV |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
    for r in rows:
        lines.append(f"| {r['scene']} | {fmt(r['ray_mrays'])} | {fmt(r['pov_mrays'])} | {fmt(r.get('mrays_ratio'))} | "
                     f"{fmt(r['ray_wall_s'])} | {fmt(r['pov_wall_s'])} | {fmt(r.get('wall_ratio'))} | "
                     f"{fmt(r['ray_load_s'])} | {fmt(r['pov_load_s'])} | "
                     f"{fmt(r['ray_peak_mib'], '.0f')} / {fmt(r['pov_peak_mib'], '.0f')} |")
    return "\n".join(lines) + "\n"


def plot(rows, out):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib not installed: no plots", file=sys.stderr)
        return
    names = [r["scene"] for r in rows]
    fig, ax = plt.subplots(figsize=(8, 3.6))
    xs = range(len(rows))
    ax.bar([x - 0.2 for x in xs], [r.get("mrays_ratio") or 0 for r in rows], 0.4, label="Mrays/s, ray ÷ POV-Ray")
    ax.bar([x + 0.2 for x in xs], [r.get("wall_ratio") or 0 for r in rows], 0.4, label="whole process, POV-Ray s ÷ ray s")
    ax.axhline(1, color="black", linewidth=0.8)
    ax.set_xticks(list(xs), names, rotation=20, ha="right")
    ax.set_ylabel("speed-up over POV-Ray")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "povray_ratios.png", dpi=100)
    plt.close(fig)

    scaling = [r for r in rows if r["scene"] in SCALING]
    if len(scaling) >= 2:
        counts = [SCENES[r["scene"]][1] for r in scaling]
        fig, (left, right) = plt.subplots(1, 2, figsize=(8, 3.4))
        for who, label in (("ray", "ray"), ("pov", "POV-Ray")):
            left.plot(counts, [r[f"{who}_wall_s"] or float("nan") for r in scaling], "o-", label=label)
            right.plot(counts, [r[f"{who}_mrays"] or float("nan") for r in scaling], "o-", label=label)
        for axis, title in ((left, "whole process, s"), (right, "trace Mrays/s")):
            axis.set_xscale("log")
            axis.set_xlabel("spheres")
            axis.set_title(title, fontsize=9)
            axis.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(out / "povray_scaling.png", dpi=100)
        plt.close(fig)


def main():
    a = parse_args()
    if not a.ray.exists():
        sys.exit(f"{a.ray}: not found; build ray first (cmake --build build) or pass --ray")
    if not (a.shared / "povray" / "cs123_to_pov.py").exists():
        sys.exit(f"{a.shared}/povray/cs123_to_pov.py not found; pass --shared DIR")
    if subprocess.run(["which", "povray"], capture_output=True).returncode != 0:
        sys.exit("povray not found: apt-get install povray")
    a.out.mkdir(parents=True, exist_ok=True)
    work = a.out / "povray_work"
    work.mkdir(exist_ok=True)

    prepared = {n: p for n in a.scene_list if (p := prepare_scene(n, a, work))}
    rows, every_run = [], {}
    for name, (xml, pov) in prepared.items():
        print(f"{name}: warming up", file=sys.stderr, flush=True)
        ray_run(a, xml, work)  # the first run of a scene compiles or loads the kernel cache
        ray_runs, pov_runs = [], []
        for i in range(a.runs):
            ray_runs.append(ray_run(a, xml, work))
            pov_runs.append(pov_run(a, pov, work))
            print(f"{name}: run {i + 1}/{a.runs}: ray {ray_runs[-1].get('wall_s', 0):.2f} s, "
                  f"POV-Ray {pov_runs[-1].get('wall_s', 0):.2f} s", file=sys.stderr, flush=True)
        every_run[name] = {"ray": ray_runs, "povray": pov_runs}
        rows.append(summarize(name, ray_runs, pov_runs))

    table = markdown_table(rows, a)
    (a.out / "povray.md").write_text(table)
    (a.out / "povray.json").write_text(json.dumps({"size": [a.width, a.height], "depth": a.depth, "runs": a.runs,
                                                   "rows": rows, "every_run": every_run}, indent=1))
    plot(rows, a.out)
    print(table)


if __name__ == "__main__":
    main()

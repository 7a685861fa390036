#!/usr/bin/env python3
"""The kernel's GPU resource report: what a GPU driver's compiler would give each kernel.

Compiles ray's OpenCL kernel (the sources in the order the host concatenates them) with
Debian's clang-15 and libclc for two GPUs ray has never run on here, and prints, per
kernel, the private memory a work-item needs, its registers, the occupancy they allow and
the code size:

  gfx906  AMD GCN (Vega 20), Mesa's triple amdgcn-mesa-mesa3d: clang -O3, linked with
          libclc, opt -O3, llc; LLVM's own report (ScratchSize, NumVgprs, Occupancy in
          waves per SIMD of 10, codeLenInByte). Built twice: "inlined", every call inlined
          (-amdgpu-function-calls=false), as Mesa and most GPU drivers build OpenCL; and
          "calls", LLVM's choice, where each call level adds its frame and spills.
  sm_80   NVIDIA Ampere through the nvptx64 back end and libclc's nvptx library; the
          PTX's local depot is its private memory. When CUDA's ptxas is on the machine
          (not a Debian package; /usr/local/cuda/bin is searched) it also gives registers,
          stack frame and spills, and occupancy in warps per SM of 64.

With --check it exits 1 when either gfx906 build of a kernel (inlined, or with LLVM's own
calls) needs more scratch than --max-scratch or reaches an occupancy below --min-occupancy (a GPU-ready kernel: little
private memory a work-item, several waves in flight to hide latency). The defaults are
the goal (2 KB, 4 waves), which CTest checks too (tests/CMakeLists.txt).

  scripts/kernel_resources.py [--depth 4] [--check] cl/shared_types.h ... cl/kernel.cl
(CTest runs it as kernel_resources, with the sources listed in CMakeLists.txt.)
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

LLVM_VERSION = "15"
LIBCLC = Path("/usr/lib/clc")
DEFAULT_MAX_SCRATCH = 2048
DEFAULT_MIN_OCCUPANCY = 4


def tool(name):
    path = shutil.which(f"{name}-{LLVM_VERSION}") or shutil.which(name)
    if not path:
        sys.exit(f"kernel_resources: {name}-{LLVM_VERSION} not found (Debian: apt-get install clang-15 llvm-15 libclc-15)")
    return path


def run(command):
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"kernel_resources: {' '.join(map(str, command))} failed:\n{result.stderr[-4000:]}")
    return result


def embedded_name(source):
    """A source's name in the program: its path under cl/ (cmake/embed_kernel.cmake)."""
    parts = Path(source).parts
    return "/".join(parts[len(parts) - 1 - parts[::-1].index("cl") + 1:]) if "cl" in parts else Path(source).name


def program_source(sources):
    """The program as host/opencl/kernel_source.cpp assembles it."""
    return "".join(f'#line 1 "{embedded_name(s)}"\n{Path(s).read_text()}\n' for s in sources)


def compile_to_ir(source_file, triple, cpu_flags, library, depth, work, llvm_flags=()):
    """clang -O3 for the target, linked with libclc, optimized again as a driver would."""
    name = triple + "".join(llvm_flags)
    bitcode, linked, optimized = work / f"{name}.bc", work / f"{name}.linked.bc", work / f"{name}.opt.bc"
    run([tool("clang"), "-x", "cl", "-cl-std=CL1.2", "-Xclang", "-finclude-default-header", "-target", triple,
         *cpu_flags, *[f for flag in llvm_flags for f in ("-mllvm", flag)], "-O3", "-emit-llvm", "-c",
         f"-DRAY_MAX_FRAMES={depth + 1}", str(source_file), "-o", str(bitcode)])
    if not library.exists():
        sys.exit(f"kernel_resources: {library} not found (Debian: apt-get install libclc-15)")
    run([tool("llvm-link"), str(bitcode), str(library), "-o", str(linked)])
    run([tool("opt"), "-O3", *llvm_flags, str(linked), "-o", str(optimized)])
    return optimized


def kernel_names(source):
    names = re.findall(r"__kernel\s+(?:\w+\s+)*void\s+(\w+)\s*\(", source)
    if not names:
        sys.exit("kernel_resources: no __kernel function found in the sources")
    return names


def amd_report(source, source_file, depth, work, inline_all):
    llvm_flags = ["-amdgpu-function-calls=false"] if inline_all else []
    optimized = compile_to_ir(source_file, "amdgcn-mesa-mesa3d", ["-mcpu=gfx906", "-nogpulib"],
                              LIBCLC / "gfx906-amdgcn-mesa-mesa3d.bc", depth, work, llvm_flags)
    assembly = work / f"gfx906-{'inlined' if inline_all else 'calls'}.s"
    run([tool("llc"), "-O3", "-mtriple=amdgcn-mesa-mesa3d", "-mcpu=gfx906", *llvm_flags, str(optimized),
         "-o", str(assembly)])
    text = assembly.read_text()
    rows = []
    for kernel in kernel_names(source):
        # LLVM prints each function's figures as comments after its code; a kernel's
        # are the first that follow its label.
        start = text.find(f"\n{kernel}:")
        block = text[start:] if start >= 0 else ""

        def field(pattern):
            match = re.search(pattern, block)
            return int(match.group(1)) if match else None

        rows.append({"kernel": kernel, "scratch": field(r"; ScratchSize: (\d+)"),
                     "registers": field(r"; NumVgprs: (\d+)"), "occupancy": field(r"; Occupancy: (\d+)"),
                     "code": field(r"; codeLenInByte = (\d+)"), "unit": "VGPRs", "occupancy_of": "waves/SIMD of 10"})
    return rows


def find_ptxas():
    return shutil.which("ptxas") or next(
        (str(p) for p in [Path("/usr/local/cuda/bin/ptxas")] if p.exists()), None)


def nvidia_report(source, source_file, depth, work):
    optimized = compile_to_ir(source_file, "nvptx64--nvidiacl", [], LIBCLC / "nvptx64--nvidiacl.bc", depth, work)
    ptx = work / "sm_80.ptx"
    run([tool("llc"), "-O3", "-mcpu=sm_80", str(optimized), "-o", str(ptx)])
    text = ptx.read_text()
    ptxas = find_ptxas()
    details = run([ptxas, "-arch=sm_80", "-v", str(ptx), "-o", os.devnull]).stderr if ptxas else ""
    rows = []
    for kernel in kernel_names(source):
        start = text.find(f".entry {kernel}(")
        body = text[start:text.find("\n}\n", start)] if start >= 0 else ""
        depot = re.search(r"__local_depot\d+\[(\d+)\]", body)
        row = {"kernel": kernel, "scratch": int(depot.group(1)) if depot else 0, "registers": None,
               "occupancy": None, "code": len(body.encode()), "unit": "registers", "occupancy_of": "warps/SM of 64"}
        info = re.search(rf"Function properties for {kernel}\n\s*(\d+) bytes stack frame.*\n.*Used (\d+) registers",
                         details)
        if info:
            row["scratch"], row["registers"] = int(info.group(1)), int(info.group(2))
            per_warp = -(-row["registers"] * 32 // 256) * 256  # registers are allocated 256 a warp
            row["occupancy"] = min(64, 65536 // per_warp) if per_warp else 64
        rows.append(row)
    return rows, ptxas


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("sources", nargs="+", help="the kernel's sources, in the order CMakeLists.txt lists them")
    parser.add_argument("--depth", type=int, default=4, help="the recursion depth the kernel is built for (default 4)")
    parser.add_argument("--check", action="store_true", help="exit 1 when a gfx906 kernel is over the budget")
    parser.add_argument("--max-scratch", type=int, default=DEFAULT_MAX_SCRATCH,
                        help=f"the budget of private scratch bytes a work-item (default {DEFAULT_MAX_SCRATCH})")
    parser.add_argument("--min-occupancy", type=int, default=DEFAULT_MIN_OCCUPANCY,
                        help=f"the lowest gfx906 occupancy, waves per SIMD (default {DEFAULT_MIN_OCCUPANCY})")
    args = parser.parse_args()
    source = program_source(args.sources)
    with tempfile.TemporaryDirectory(prefix="ray-kernel-resources-") as folder:
        work = Path(folder)
        source_file = work / "ray.cl"
        source_file.write_text(source)
        amd = amd_report(source, source_file, args.depth, work, inline_all=True)
        amd_calls = amd_report(source, source_file, args.depth, work, inline_all=False)
        nvidia, ptxas = nvidia_report(source, source_file, args.depth, work)

    def show(value):
        return "-" if value is None else str(value)

    print(f"Kernel resources at depth {args.depth} (RAY_MAX_FRAMES={args.depth + 1}), LLVM {LLVM_VERSION} + libclc")
    print("| target | kernel | private scratch B | registers | occupancy | code B |")
    print("|---|---|---:|---:|---:|---:|")
    for target, rows in (("gfx906 inlined", amd), ("gfx906 calls", amd_calls), ("sm_80 calls", nvidia)):
        for r in rows:
            print(f"| {target} | {r['kernel']} | {show(r['scratch'])} | {show(r['registers'])} {r['unit']} | "
                  f"{show(r['occupancy'])} {r['occupancy_of']} | {show(r['code'])} |")
    if not ptxas:
        print("sm_80: no ptxas on this machine, so no register count; private bytes are the PTX local depot")
    failures = [(build, r) for build, rows in (("inlined", amd), ("calls", amd_calls)) for r in rows
                if r["scratch"] is None or r["scratch"] > args.max_scratch
                or r["occupancy"] is None or r["occupancy"] < args.min_occupancy]
    for build, r in failures:
        print(f"over budget on gfx906 ({build}): {r['kernel']} needs {show(r['scratch'])} B of scratch (budget "
              f"{args.max_scratch}) at occupancy {show(r['occupancy'])} (budget >= {args.min_occupancy})")
    return 1 if args.check and failures else 0


if __name__ == "__main__":
    sys.exit(main())

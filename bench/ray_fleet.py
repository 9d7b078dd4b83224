#!/usr/bin/env python3
"""seamlit.ray against folder mode, in one run: files per second per CPU for `seamlit fix
DIR -o DIR` on 1 and 2 threads and for `python -m seamlit.ray fix` on a local Ray cluster
of 1 and 2 nodes of one CPU each, over a library of copies of the repository's models; and
`seamlit.fix_bytes`' per-file overhead against the command line on a small model.

    export CARGO_TARGET_DIR=...; cargo build -p seamlit -p seamlit-py   # or --release
    SEAMLIT_BIN=$CARGO_TARGET_DIR/debug/seamlit PYTHONPATH=<folder with the seamlit package> \\
        python3 bench/ray_fleet.py [--files 1000] [--work /tmp/fleet] [--repeat 3]

Folder mode's threads: RAYON_NUM_THREADS and taskset over that many cores. Ray's nodes have
num_cpus=1 each (each task one thread); the driver runs beside them. Prints a Markdown table.
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
MODELS = REPO / "assets" / "models"

#: One copy of the library: (source under assets/models, destination in the copy).
ONE_COPY = [
    ("fox/Fox.glb", "glb/Fox.glb"),
    ("NormalTangentTest.glb", "glb/NormalTangentTest.glb"),
    ("compressed/teapot_mo.glb", "glb/teapot_mo.glb"),
    ("lowpoly/kenney-platformer-cube.glb", "glb/cube.glb"),
    ("emissive_strength_test/EmissiveStrengthTest.glb", "glb/emissive.glb"),
    ("cornell_box/cornell_box.obj", "obj/cornell_box.obj"),
    ("cornell_box/cornell_box.mtl", "obj/cornell_box.mtl"),
    ("ufbx/blender_272_cube_7400_binary.fbx", "fbx/cube.fbx"),
    ("ufbx/maya_parented_cubes_7500_ascii.fbx", "fbx/parented.fbx"),
    ("ufbx/blender_293_half_skinned_7400_binary.fbx", "fbx/half_skinned.fbx"),
    ("usd/head_body.usdz", "usd/head_body.usdz"),
    ("usd/head_body.usda", "usd/head_body.usda"),
    ("usd/layered/shot.usda", "usd/layered/shot.usda"),
    ("usd/layered/prop.usda", "usd/layered/prop.usda"),
    ("usd/layered/base.usda", "usd/layered/base.usda"),
]
MODELS_PER_COPY = sum(1 for _, d in ONE_COPY if not d.endswith(".mtl"))


def library(root: Path, files: int) -> int:
    copies = -(-files // MODELS_PER_COPY)
    for i in range(copies):
        for source, target in ONE_COPY:
            path = root / f"copy{i:04d}" / target
            path.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(MODELS / source, path)
    return copies * MODELS_PER_COPY


def folder_mode(binary: str, src: Path, dst: Path, threads: int) -> float:
    cores = ",".join(str(c) for c in range(threads))
    env = dict(os.environ, RAYON_NUM_THREADS=str(threads))
    started = time.perf_counter()
    done = subprocess.run(["taskset", "-c", cores, binary, "fix", str(src), "-o", str(dst)], env=env, capture_output=True, text=True)
    seconds = time.perf_counter() - started
    if done.returncode != 0:
        sys.exit(f"folder mode failed: {done.stderr[-2000:]}")
    return seconds


def ray_mode(src: Path, dst: Path, nodes: int, repeat: int) -> tuple:
    """Runs ``seamlit.ray.fix`` ``repeat`` times on one cluster of ``nodes`` nodes, each into
    a fresh DST; returns the runs' seconds (the first with the workers' start and imports) and
    the cluster's start."""
    import ray
    from ray.cluster_utils import Cluster

    import seamlit.ray

    started = time.perf_counter()
    cluster = Cluster(initialize_head=True, head_node_args={"num_cpus": 1})
    for _ in range(nodes - 1):
        cluster.add_node(num_cpus=1)
    cluster.wait_for_nodes()
    ray.init(address=cluster.address, log_to_driver=False)
    up = time.perf_counter() - started
    runs = []
    try:
        for _ in range(repeat):
            shutil.rmtree(dst, ignore_errors=True)
            summary = seamlit.ray.fix(str(src), str(dst), pictures=0, progress=False)
            if summary.failed or summary.refused:
                sys.exit(f"ray run had failures: {summary.line()}")
            runs.append(summary.seconds)
    finally:
        ray.shutdown()
        cluster.shutdown()
    return runs, up


def same_tree(a: Path, b: Path) -> bool:
    left = sorted(p.relative_to(a) for p in a.rglob("*") if p.is_file() and "_seamlit" not in p.parts)
    right = sorted(p.relative_to(b) for p in b.rglob("*") if p.is_file())
    return left == right and all((a / p).read_bytes() == (b / p).read_bytes() for p in right)


def overhead(binary: str, work: Path, runs: int) -> tuple:
    import seamlit

    model = MODELS / "NormalTangentTest.glb"
    data = model.read_bytes()
    cli, native = [], []
    for _ in range(runs):
        started = time.perf_counter()
        subprocess.run([binary, "fix", str(model), "-o", str(work / "cli.glb")], check=True, capture_output=True)
        cli.append(time.perf_counter() - started)
        started = time.perf_counter()
        seamlit.fix_bytes(data, model.name)
        native.append(time.perf_counter() - started)
    return statistics.median(cli), statistics.median(native), model.stat().st_size


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--files", type=int, default=1000)
    parser.add_argument("--work", type=Path, default=Path("/tmp/seamlit-fleet"))
    parser.add_argument("--runs", type=int, default=21, help="runs of the overhead measure")
    parser.add_argument("--repeat", type=int, default=3, help="runs of each configuration (median)")
    args = parser.parse_args()
    binary = os.environ.get("SEAMLIT_BIN") or shutil.which("seamlit") or sys.exit("set SEAMLIT_BIN")
    shutil.rmtree(args.work, ignore_errors=True)
    src = args.work / "src"
    files = library(src, args.files)
    print(f"library: {files} model files ({MODELS_PER_COPY} models x {files // MODELS_PER_COPY} copies) in {src}")
    print(f"load average before: {os.getloadavg()}")
    rows = []
    for threads in (1, 2):
        runs = []
        for _ in range(args.repeat):
            shutil.rmtree(args.work / f"folder{threads}", ignore_errors=True)
            runs.append(folder_mode(binary, src, args.work / f"folder{threads}", threads))
        rows.append((f"`seamlit fix DIR -o DIR`, {threads} thread(s)", threads, runs, None))
        print(rows[-1], flush=True)
    for nodes in (1, 2):
        dst = args.work / f"ray{nodes}"
        runs, up = ray_mode(src, dst, nodes, args.repeat)
        assert same_tree(dst, args.work / "folder1"), "ray output differs from folder mode"
        rows.append((f"`seamlit.ray.fix`, {nodes} node(s) of 1 CPU", nodes, runs, up))
        print(rows[-1], flush=True)
    print(f"load average after: {os.getloadavg()}")
    print()
    print(f"Seconds: the median of {args.repeat} runs (Ray: on one cluster, the first run's in brackets: its")
    print("workers start and import the package).")
    print()
    print("| run | CPUs | wall (s) | files/s | files/s per CPU | cluster start (s) |")
    print("|---|---:|---:|---:|---:|---:|")
    median = lambda runs: statistics.median(runs)
    for name, cpus, runs, up in rows:
        rate = files / median(runs)
        wall = f"{median(runs):.2f}" + ("" if up is None else f" ({runs[0]:.2f})")
        print(f"| {name} | {cpus} | {wall} | {rate:.1f} | {rate / cpus:.1f} | {'' if up is None else f'{up:.1f}'} |")
    folder1 = files / median(rows[0][2])
    ray1, ray2 = files / median(rows[2][2]), files / median(rows[3][2])
    first1, first2 = files / rows[2][2][0], files / rows[3][2][0]
    print(f"\nRay 1 node against folder mode 1 thread, per CPU: {folder1 / ray1:.2f}x slower (first run {folder1 / first1:.2f}x)")
    print(f"Ray 2 nodes against 1 node: {ray2 / ray1:.2f}x (first runs {first2 / first1:.2f}x)")
    cli, native, size = overhead(binary, args.work, args.runs)
    print(f"\nper file, NormalTangentTest.glb ({size} bytes), median of {args.runs}: "
          f"command line {cli * 1000:.1f} ms (process start included), fix_bytes {native * 1000:.1f} ms")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""seamlit.ray against folder mode, in one run: files per second per CPU for `seamlit fix
DIR -o DIR` on 1 and 2 threads and for `python -m seamlit.ray fix` on a local Ray cluster
of 1 and 2 nodes of one CPU each, over a library of copies of the repository's models; and
`seamlit.fix_bytes`' per-file overhead against the command line on a small model.

    export CARGO_TARGET_DIR=...; cargo build -p seamlit -p seamlit-py   # or --release
    SEAMLIT_BIN=$CARGO_TARGET_DIR/debug/seamlit PYTHONPATH=<folder with the seamlit package> \\
        python3 bench/ray_fleet.py [--files 1000] [--work /tmp/fleet] [--repeat 3]

Folder mode's threads: RAYON_NUM_THREADS and taskset over that many cores. Ray's nodes have
num_cpus=1 each (each task one thread); the driver runs beside them. Each Ray run is
alternated with folder mode's on 1 and 2 threads (this shared machine's speed moves by a
third from one minute to the next), and each Ray figure is read against the folder runs
beside it. Prints a Markdown table.
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


#: SHA-256 of every file under the folders given, in one process: the hashes seamlit.ray's
#: report holds (each input with its companions, each output), which folder mode does not
#: make; one file after another (hashlib), or, with "together", as a Ray task makes them
#: (the extension module's Digests: messages of about one size side by side). Prints the
#: seconds.
HASH_ALL = """
import hashlib, sys, time
from pathlib import Path
together = sys.argv[1] == "together"
files = [p for root in sys.argv[2:] for p in sorted(Path(root).rglob('*')) if p.is_file() and '_seamlit' not in p.parts]
if together:
    from seamlit import _seamlit
    digests = _seamlit.Digests()
started = time.perf_counter()
for k, p in enumerate(files):
    if together:
        digests.add_file(k, str(p))
    else:
        hashlib.sha256(p.read_bytes()).hexdigest()
if together:
    digests.take()
print(time.perf_counter() - started)
"""


def audit_hashes(src: Path, dst: Path, runs: int, how: str) -> float:
    """The median seconds of hashing every input and output file as the report does, on one
    core (the share of a Ray task's time that folder mode has no counterpart for); ``how``:
    ``one`` after another or ``together``."""
    seconds = []
    for _ in range(runs):
        done = subprocess.run(["taskset", "-c", "0", sys.executable, "-c", HASH_ALL, how, str(src), str(dst)],
                              capture_output=True, text=True, check=True)
        seconds.append(float(done.stdout.strip()))
    return statistics.median(seconds)


class RayCluster:
    """A local Ray cluster of ``nodes`` nodes of one CPU each, the driver connected."""

    def __init__(self, nodes: int) -> None:
        import ray
        from ray.cluster_utils import Cluster

        started = time.perf_counter()
        self.cluster = Cluster(initialize_head=True, head_node_args={"num_cpus": 1})
        for _ in range(nodes - 1):
            self.cluster.add_node(num_cpus=1)
        self.cluster.wait_for_nodes()
        ray.init(address=self.cluster.address, log_to_driver=False)
        self.up = time.perf_counter() - started

    def fix(self, src: Path, dst: Path) -> float:
        """One ``seamlit.ray.fix`` into a fresh DST: its seconds."""
        import seamlit.ray

        shutil.rmtree(dst, ignore_errors=True)
        summary = seamlit.ray.fix(str(src), str(dst), pictures=0, progress=False)
        if summary.failed or summary.refused:
            sys.exit(f"ray run had failures: {summary.line()}")
        return summary.seconds

    def close(self) -> None:
        import ray

        ray.shutdown()
        self.cluster.shutdown()


def phase(binary: str, work: Path, src: Path, nodes: int, repeat: int) -> dict:
    """Ray on ``nodes`` nodes, each run alternated with folder mode on 1 and 2 threads (the
    machine's speed moves by a third from minute to minute: each Ray figure is read against
    the folder runs beside it). The cluster is up, idle, during the folder runs."""
    cluster = RayCluster(nodes)
    runs = {"folder1": [], "folder2": [], "ray": []}
    try:
        for _ in range(repeat):
            for threads in (1, 2):
                dst = work / f"folder{threads}"
                shutil.rmtree(dst, ignore_errors=True)
                runs[f"folder{threads}"].append(folder_mode(binary, src, dst, threads))
            runs["ray"].append(cluster.fix(src, work / f"ray{nodes}"))
    finally:
        cluster.close()
    assert same_tree(work / f"ray{nodes}", work / "folder1"), "ray output differs from folder mode"
    return {"runs": runs, "up": cluster.up}


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
    phases = {nodes: phase(binary, args.work, src, nodes, args.repeat) for nodes in (1, 2)}
    print(f"load average after: {os.getloadavg()}")
    median = statistics.median
    print()
    print(f"Seconds: the median of {args.repeat} runs, each Ray run alternated with folder mode's; the")
    print("first Ray run, in brackets, also starts the workers and imports the package.")
    print()
    print("| Ray nodes of 1 CPU | folder 1 thread (s) | folder 2 threads (s) | Ray (s) | Ray files/s per CPU | per CPU, folder 1 thread / Ray | cluster start (s) |")
    print("|---:|---:|---:|---:|---:|---:|---:|")
    slower = {}
    for nodes, result in phases.items():
        runs = result["runs"]
        folder1, ray = median(runs["folder1"]), median(runs["ray"])
        # Files per second per CPU: folder mode's on one thread over Ray's.
        slower[nodes] = (files / folder1) / (files / ray / nodes)
        first = (files / folder1) / (files / runs["ray"][0] / nodes)
        print(f"| {nodes} | {folder1:.2f} | {median(runs['folder2']):.2f} | {ray:.2f} ({runs['ray'][0]:.2f}) "
              f"| {files / ray / nodes:.1f} | {slower[nodes]:.2f}x ({first:.2f}x) | {result['up']:.1f} |")
    # Two nodes against one, each read against the folder runs beside it.
    scaling = 2 * slower[1] / slower[2]
    raw = median(phases[1]["runs"]["ray"]) / median(phases[2]["runs"]["ray"])
    print(f"\nRay 1 node against folder mode 1 thread, per CPU: {slower[1]:.2f}x slower")
    print(f"Ray 2 nodes against 1 node: {scaling:.2f}x (each against its folder runs; the raw ratio of medians {raw:.2f}x)")
    # What this machine gives a second thread: folder mode's own 2 threads against its 1.
    own = [median(p["runs"]["folder1"]) / median(p["runs"]["folder2"]) for p in phases.values()]
    print(f"Folder mode 2 threads against 1 thread, the same runs: {' and '.join(f'{x:.2f}x' for x in own)}")
    # The report's SHA-256 of every input and output: work a Ray task does that folder mode
    # has no counterpart for, against folder mode's time and as if folder mode did it too.
    one = audit_hashes(src, args.work / "folder1", args.repeat, "one")
    hashes = audit_hashes(src, args.work / "folder1", args.repeat, "together")
    print(f"The report's SHA-256 of every input and output file, one core: {one:.2f} s one after "
          f"another, {hashes:.2f} s together as a task makes them ({one / hashes:.1f}x), "
          f"{hashes / folder1:.0%} of folder mode's 1-thread time; Ray 1 node against folder mode "
          f"plus those hashes, per CPU: {slower[1] * folder1 / (folder1 + hashes):.2f}x")
    cli, native, size = overhead(binary, args.work, args.runs)
    print(f"\nper file, NormalTangentTest.glb ({size} bytes), median of {args.runs}: "
          f"command line {cli * 1000:.1f} ms (process start included), fix_bytes {native * 1000:.1f} ms")


if __name__ == "__main__":
    main()

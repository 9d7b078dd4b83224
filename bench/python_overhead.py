#!/usr/bin/env python3
"""The Python binding's overhead: `seamlit.fix` on NumPy arrays against the same fix from
Rust (crates/seamlit-py/examples/fix_time.rs), on one model, in one run.

    cargo build --release -p seamlit-py --example fix_time
    pip install ./crates/seamlit-py trimesh      # a release build of the package
    python3 bench/python_overhead.py MODEL.glb [RUNS]

The model is read into arrays with trimesh (not timed); both sides compute normals and
tangents from positions, triangles and UVs (`normals="recompute"`). Prints both timings
(min and median of RUNS) and the overhead of the median.
"""

import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import trimesh

import seamlit


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    path = sys.argv[1]
    runs = int(sys.argv[2]) if len(sys.argv) > 2 else 7
    scene = trimesh.load(path, force="scene", process=False)
    objects = []
    for node in scene.graph.nodes_geometry:
        transform, name = scene.graph[node]
        mesh = scene.geometry[name]
        o = {
            "positions": np.ascontiguousarray(mesh.vertices, np.float32),
            "triangles": np.ascontiguousarray(mesh.faces, np.uint32),
            "transform": np.asarray(transform, np.float32),
        }
        uv = getattr(mesh.visual, "uv", None)
        if uv is not None:
            o["uvs"] = np.ascontiguousarray(uv, np.float32)
        objects.append(o)
    vertices = sum(len(o["positions"]) for o in objects)
    triangles = sum(len(o["triangles"]) for o in objects)
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        seamlit.fix(objects, normals="recompute")
        times.append((time.perf_counter() - start) * 1e3)
    python = (min(times), statistics.median(times))
    example = Path(__file__).resolve().parents[1] / "target" / "release" / "examples" / "fix_time"
    line = subprocess.run([str(example), path, str(runs)], capture_output=True, text=True, check=True).stdout
    print(f"python: vertices {vertices} triangles {triangles} runs {runs} min {python[0]:.1f} median {python[1]:.1f}")
    print(f"rust:   {line.strip()}")
    rust_median = float(line.split("median")[1])
    print(f"overhead of the median: {100 * (python[1] / rust_median - 1):+.1f}%")


if __name__ == "__main__":
    main()

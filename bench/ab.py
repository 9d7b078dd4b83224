#!/usr/bin/env python3
"""Whole-process `seamlit fix` (the default options) of each FILE by two builds, alternated run
by run: the before and after of a change on real files of every kind (normal maps, authored
normals, skins), where bench/floor.sh times one large generated model.

    bench/ab.py OLD NEW FILE... [--runs N] [--threads T]

OLD and NEW are seamlit binaries (release builds: copy target/release/seamlit aside before the
change, and keep both in one folder: from /dev/shm a binary starts 10 to 15% slower on small
files than from disk, BENCHMARKS.md). Each run starts both builds on the file in turn (which goes first alternates), so a
machine that drifts drifts for both. Prints, per file, each build's median wall time and NEW /
OLD, and the geometric mean of the ratios. Outputs go to a temporary folder (their bytes are
compared by bench/io-identical.sh); a run that fails stops the script with its error line.
"""

import argparse
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("old")
    parser.add_argument("new")
    parser.add_argument("files", nargs="+")
    parser.add_argument("--runs", type=int, default=15, help="runs of each build per file")
    parser.add_argument("--threads", type=int, help="RAYON_NUM_THREADS (default: all cores)")
    args = parser.parse_args()
    for binary in (args.old, args.new):
        if not os.access(binary, os.X_OK):
            sys.exit(f"bench/ab.py: {binary} is not an executable")
    env = dict(os.environ)
    if args.threads:
        env["RAYON_NUM_THREADS"] = str(args.threads)
    load = open("/proc/loadavg").read().split()[:3]
    print(f"machine: {os.cpu_count()} cores; load {' '.join(load)}; {args.runs} runs each")
    print(f"{'file':<40} {'old':>10} {'new':>10} {'new/old':>8}")
    ratios = []
    with tempfile.TemporaryDirectory() as work:
        for path in args.files:
            name = os.path.basename(path)
            ext = name.rsplit(".", 1)[-1].lower()
            # seamlit writes every format it reads but FBX: its fix becomes a .glb.
            ext = "glb" if ext == "fbx" else ext
            times = {args.old: [], args.new: []}
            for run in range(args.runs + 1):
                order = (args.old, args.new) if run % 2 == 0 else (args.new, args.old)
                for k, binary in enumerate(order):
                    out = os.path.join(work, f"{k}.{ext}")
                    start = time.perf_counter()
                    done = subprocess.run([binary, "fix", path, "-o", out], env=env,
                                          stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
                    seconds = time.perf_counter() - start
                    if done.returncode != 0:
                        line = done.stderr.decode(errors="replace").strip().splitlines()[-1:]
                        sys.exit(f"bench/ab.py: {binary} fix {path}: {' '.join(line)}")
                    if run > 0:  # the first round warms the page cache
                        times[binary].append(seconds)
            old, new = (statistics.median(times[b]) * 1e3 for b in (args.old, args.new))
            ratios.append(new / old)
            print(f"{name:<40} {old:8.1f}ms {new:8.1f}ms {new / old:7.2f}x")
    geomean = math.exp(sum(math.log(r) for r in ratios) / len(ratios))
    print(f"{'geometric mean':<40} {'':>10} {'':>10} {geomean:7.2f}x")
    return 0


if __name__ == "__main__":
    sys.exit(main())

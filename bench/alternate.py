#!/usr/bin/env python3
"""Whole-process wall time of several shell commands, run in turn (one run of each, then the
next round), with the median of each and its ratio to the first command's median.

Alternating keeps a drifting machine from favouring whichever command ran first (BENCHMARKS.md:
this machine's speed moves by half within an hour). For one change's before and after on many
files, bench/ab.py (two builds, `seamlit fix` of each file into its own format); this is for
ratios across commands, such as one model's fix from two formats.

Example (the 1M teapot as `.glb` and `.usdc`, BENCHMARKS.md "A `.usdc` output without its
text"):

    bench/alternate.py --runs 11 "glb|seamlit fix t.glb -o o.glb" "usdc|seamlit fix t.usdc -o o.usdc"
"""
import argparse
import statistics
import subprocess
import sys
import time


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("cases", nargs="+", help="NAME|COMMAND (a shell command line)")
    parser.add_argument("--runs", type=int, default=9, help="runs of each command (default 9)")
    args = parser.parse_args()
    cases = []
    for case in args.cases:
        name, sep, command = case.partition("|")
        if not sep or not command.strip():
            print(f"bench/alternate.py: {case!r}: expected NAME|COMMAND", file=sys.stderr)
            return 2
        cases.append((name, command))
    times = {name: [] for name, _ in cases}
    for _ in range(args.runs):
        for name, command in cases:
            start = time.perf_counter()
            done = subprocess.run(command, shell=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
            elapsed = time.perf_counter() - start
            if done.returncode != 0:
                print(f"bench/alternate.py: {name}: exit {done.returncode}: {done.stderr.decode().strip()}",
                      file=sys.stderr)
                return 1
            times[name].append(elapsed)
    base = statistics.median(times[cases[0][0]])
    for name, _ in cases:
        median = statistics.median(times[name])
        print(f"{name:40s} {median * 1000:9.1f} ms  {median / base:5.2f}x  (min {min(times[name]) * 1000:.1f} ms)")
    return 0


if __name__ == "__main__":
    sys.exit(main())

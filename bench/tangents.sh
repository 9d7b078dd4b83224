#!/usr/bin/env bash
# Whole-process timings of `seamlit fix` and `seamlit inspect` on the demo teapot (32 objects,
# UVs, the brick normal map, no normals and no tangents: the default path is MikkTSpace) at
# about 64k, 256k, 1M and 4M triangles, against `--tangents seamlit`, on 1 and 2 threads;
# optionally against an older binary (the default before, the same input).
#
#   bench/tangents.sh [--old PATH] [--runs N] [--sizes "32 64 128 256"] [--threads "1 2"]
#
# Prints one line per case: the median wall time and peak memory of N runs (GNU time), the
# cases of one size alternated so that a noisy machine weighs on all alike. Needs release
# builds of `seamlit` and `seamlit-bench` (cargo build --release -p seamlit -p seamlit-bench).
set -euo pipefail
cd "$(dirname "$0")/.."

script=bench/tangents.sh
sizes="32 64 128 256"
threads="1 2"
source bench/timing.sh
parse_options "$@"
check_tools

echo "machine: $(nproc) cores, $(uname -m); load $(cut -d' ' -f1-3 /proc/loadavg)"
for n in $sizes; do
  input="$work/teapot-$n.glb"
  "$gen" teapot "$n" "$input" >/dev/null
  tris=$((2 * n * n * 32))
  for t in $threads; do
    cases=("fix default|$new fix $input -o $work/out.glb"
           "fix --tangents seamlit|$new fix $input -o $work/out.glb --tangents seamlit"
           "inspect default|$new inspect $input")
    [ -z "$old" ] || cases+=("old fix default|$old fix $input -o $work/out.glb")
    time_cases "$tris" "$t"
  done
done

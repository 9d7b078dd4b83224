#!/usr/bin/env bash
# Whole-process timings of `seamlit fix` on the same model as .glb and as OpenUSD (.usdc and
# .usda), issue 33's aim: a 1M-triangle .usdc fixed in at most 2x the time and memory of the
# .glb.
#
#   bench/usd.sh [--old PATH] [--runs N] [--sizes "64 128"] [--threads "1 2"]
#
# The model is the demo teapot written by `seamlit-bench teapot N` (32 objects, UVs, the brick
# normal map, no normals; 2 N^2 x 32 triangles), converted by bench/glb_to_usd.py with Pixar's
# USD (usd-core): one Mesh per object, points, triangles, `primvars:st`, no normals. The USD
# reader does not read UsdPreviewSurface normal maps, so every case runs `--tangents seamlit`
# (the .glb's default would be MikkTSpace): the same work on the geometry, the formats' reading
# and writing compared. Outputs: .glb for the .glb; the .usda override layer for USD.
# --old PATH adds the .usdc case run by an older binary (before and after a change).
# Prints the median wall time and peak memory (GNU time) of N runs, cases alternated.
# Needs release builds: cargo build --release -p seamlit -p seamlit-bench.
set -euo pipefail
cd "$(dirname "$0")/.."

script=bench/usd.sh
sizes="64 128"
threads="1 2"
source bench/timing.sh
parse_options "$@"
check_tools
python3 -c "import pxr" 2>/dev/null || { echo "bench/usd.sh: needs Pixar's USD: pip install usd-core" >&2; exit 2; }

echo "machine: $(nproc) cores, $(uname -m); load $(cut -d' ' -f1-3 /proc/loadavg)"
for n in $sizes; do
  "$gen" teapot "$n" "$work/t.glb" >/dev/null
  python3 bench/glb_to_usd.py "$work/t.glb" "$work/t.usdc" >/dev/null
  python3 bench/glb_to_usd.py "$work/t.glb" "$work/t.usda" >/dev/null
  tris=$((2 * n * n * 32))
  echo "input: $tris triangles; .glb $(du -k "$work/t.glb" | cut -f1) KiB, .usdc $(du -k "$work/t.usdc" | cut -f1) KiB, .usda $(du -k "$work/t.usda" | cut -f1) KiB"
  for t in $threads; do
    cases=("fix .glb -o .glb|$new fix $work/t.glb -o $work/out.glb --tangents seamlit"
           "fix .usdc -o .usda|$new fix $work/t.usdc -o $work/out.usda --tangents seamlit"
           "fix .usda -o .usda|$new fix $work/t.usda -o $work/out2.usda --tangents seamlit"
           "inspect .glb|$new inspect $work/t.glb"
           "inspect .usdc|$new inspect $work/t.usdc")
    [ -z "$old" ] || cases+=("old fix .usdc -o .usda|$old fix $work/t.usdc -o $work/out3.usda --tangents seamlit")
    time_cases "$tris" "$t"
  done
done

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

old=""
runs=3
sizes="64 128"
threads="1 2"
while [ $# -gt 0 ]; do
  case "$1" in
    --old) old="$2"; shift 2 ;;
    --runs) runs="$2"; shift 2 ;;
    --sizes) sizes="$2"; shift 2 ;;
    --threads) threads="$2"; shift 2 ;;
    *) echo "usage: bench/usd.sh [--old PATH] [--runs N] [--sizes LIST] [--threads LIST]" >&2; exit 2 ;;
  esac
done

new=target/release/seamlit
gen=target/release/seamlit-bench
for b in "$new" "$gen"; do
  [ -x "$b" ] || { echo "bench/usd.sh: $b is missing: cargo build --release -p seamlit -p seamlit-bench" >&2; exit 2; }
done
[ -z "$old" ] || [ -x "$old" ] || { echo "bench/usd.sh: --old $old is not an executable" >&2; exit 2; }
[ -x /usr/bin/time ] || { echo "bench/usd.sh: needs GNU time (apt-get install time)" >&2; exit 2; }
python3 -c "import pxr" 2>/dev/null || { echo "bench/usd.sh: needs Pixar's USD: pip install usd-core" >&2; exit 2; }

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# One run: prints "seconds kilobytes".
once() {
  /usr/bin/time -f "%e %M" -o "$work/time" "$@" >/dev/null 2>"$work/err" ||
    { echo "failed: $* ($(tail -1 "$work/err"))" >&2; exit 1; }
  cat "$work/time"
}

median() { sort -n | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }

echo "machine: $(nproc) cores, $(uname -m); load $(cut -d' ' -f1-3 /proc/loadavg)"
for n in $sizes; do
  "$gen" teapot "$n" "$work/t.glb" >/dev/null
  python3 bench/glb_to_usd.py "$work/t.glb" "$work/t.usdc" >/dev/null
  python3 bench/glb_to_usd.py "$work/t.glb" "$work/t.usda" >/dev/null
  tris=$((2 * n * n * 32))
  echo "input: $tris triangles; .glb $(du -k "$work/t.glb" | cut -f1) KiB, .usdc $(du -k "$work/t.usdc" | cut -f1) KiB, .usda $(du -k "$work/t.usda" | cut -f1) KiB"
  for t in $threads; do
    declare -A secs=() mem=()
    cases=("fix .glb -o .glb|$new fix $work/t.glb -o $work/out.glb --tangents seamlit"
           "fix .usdc -o .usda|$new fix $work/t.usdc -o $work/out.usda --tangents seamlit"
           "fix .usda -o .usda|$new fix $work/t.usda -o $work/out2.usda --tangents seamlit"
           "inspect .glb|$new inspect $work/t.glb"
           "inspect .usdc|$new inspect $work/t.usdc")
    [ -z "$old" ] || cases+=("old fix .usdc -o .usda|$old fix $work/t.usdc -o $work/out3.usda --tangents seamlit")
    for r in $(seq "$runs"); do
      for c in "${cases[@]}"; do
        name=${c%%|*}; cmd=${c#*|}
        read -r s k < <(RAYON_NUM_THREADS=$t once $cmd)
        secs[$name]+="$s "; mem[$name]+="$k "
      done
    done
    for c in "${cases[@]}"; do
      name=${c%%|*}
      s=$(echo "${secs[$name]}" | tr ' ' '\n' | grep . | median)
      k=$(echo "${mem[$name]}" | tr ' ' '\n' | grep . | median)
      printf '%9d triangles  %s thread(s)  %-20s %7.2f s  %5d MiB\n' "$tris" "$t" "$name" "$s" $((k / 1024))
    done
    unset secs mem
  done
done

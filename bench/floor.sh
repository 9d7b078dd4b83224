#!/usr/bin/env bash
# The default `seamlit fix` against the floor of reading and writing the same file while
# computing nothing (issue 44): whole-process wall time and peak memory of `seamlit fix` on
# the demo teapot (32 objects, UVs, the brick normal map, no normals and no tangents: the
# default path is MikkTSpace) and of seamlit-io's `load_save` example on the same file,
# alternated, and their ratios.
#
#   bench/floor.sh [--old PATH] [--runs N] [--sizes "128"] [--threads "2"]
#
# --old PATH adds the same fix run by an older binary (before and after a change), and its
# ratios to the floor. Keep it on the same filesystem as target/: a binary's own pages count
# in its peak memory, differently from tmpfs (/dev/shm) than from disk (2 MiB here).
# Sizes are the teapot's tessellation (128: 1,048,576 triangles). Needs release builds:
# cargo build --release -p seamlit -p seamlit-bench && cargo build --release -p seamlit-io --example load_save
set -euo pipefail
cd "$(dirname "$0")/.."

script=bench/floor.sh
sizes="128"
threads="2"
source bench/timing.sh
runs=7
parse_options "$@"
check_tools
floor=target/release/examples/load_save
[ -x "$floor" ] || {
  echo "$script: $floor is missing: cargo build --release -p seamlit-io --example load_save" >&2
  exit 2
}

echo "machine: $(nproc) cores, $(uname -m); load $(cut -d' ' -f1-3 /proc/loadavg); $runs runs each"
for n in $sizes; do
  input="$work/teapot-$n.glb"
  "$gen" teapot "$n" "$input" >/dev/null
  tris=$((2 * n * n * 32))
  for t in $threads; do
    cases=("fix default|$new fix $input -o $work/out.glb"
           "load and save|$floor $input $work/floor.glb")
    [ -z "$old" ] || cases+=("old fix default|$old fix $input -o $work/out-old.glb")
    lines=$(time_cases "$tris" "$t")
    echo "$lines"
    # "... fix default   0.38 s  108 MiB" over "... load and save   0.08 s  54 MiB".
    echo "$lines" | awk -v tris="$tris" -v t="$t" '
      { for (i = 1; i < NF; i++) { if ($(i + 1) == "s") s = $i; if ($(i + 1) == "MiB") m = $i } }
      $5 == "fix" { fs = s; fm = m }
      $5 == "load" { ls = s; lm = m }
      $5 == "old" { os = s; om = m }
      END {
        if (ls > 0 && lm > 0) {
          printf "%9d triangles  %s thread(s)  fix / floor: %.2fx wall, %.2fx peak memory\n", tris, t, fs / ls, fm / lm
          if (os > 0) printf "%9d triangles  %s thread(s)  old fix / floor: %.2fx wall, %.2fx peak memory\n", tris, t, os / ls, om / lm
        }
      }'
  done
done

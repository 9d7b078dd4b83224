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

old=""
runs=3
sizes="32 64 128 256"
threads="1 2"
while [ $# -gt 0 ]; do
  case "$1" in
    --old) old="$2"; shift 2 ;;
    --runs) runs="$2"; shift 2 ;;
    --sizes) sizes="$2"; shift 2 ;;
    --threads) threads="$2"; shift 2 ;;
    *) echo "usage: bench/tangents.sh [--old PATH] [--runs N] [--sizes LIST] [--threads LIST]" >&2; exit 2 ;;
  esac
done

new=target/release/seamlit
gen=target/release/seamlit-bench
for b in "$new" "$gen"; do
  [ -x "$b" ] || { echo "bench/tangents.sh: $b is missing: cargo build --release -p seamlit -p seamlit-bench" >&2; exit 2; }
done
[ -z "$old" ] || [ -x "$old" ] || { echo "bench/tangents.sh: --old $old is not an executable" >&2; exit 2; }
[ -x /usr/bin/time ] || { echo "bench/tangents.sh: needs GNU time (apt-get install time)" >&2; exit 2; }

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
  input="$work/teapot-$n.glb"
  "$gen" teapot "$n" "$input" >/dev/null
  tris=$((2 * n * n * 32))
  for t in $threads; do
    declare -A secs=() mem=()
    cases=("fix default|$new fix $input -o $work/out.glb"
           "fix --tangents seamlit|$new fix $input -o $work/out.glb --tangents seamlit"
           "inspect default|$new inspect $input")
    [ -z "$old" ] || cases+=("old fix default|$old fix $input -o $work/out.glb")
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
      printf '%9d triangles  %s thread(s)  %-24s %7.2f s  %5d MiB\n' "$tris" "$t" "$name" "$s" $((k / 1024))
    done
    unset secs mem
  done
done

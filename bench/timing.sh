# Sourced by bench/tangents.sh and bench/usd.sh: their options, the tools they need, and the
# timing of alternated cases (GNU time, medians). Set `script` before sourcing.
#
#   parse_options "$@"     --old PATH, --runs N, --sizes LIST, --threads LIST
#   check_tools            the release binaries, --old, GNU time; sets new, gen and work
#   time_cases TRIS T      runs the array `cases` ("name|command") `runs` times, alternated, on
#                          T threads, and prints each case's median time and memory

old=""
runs=3
parse_options() {
  while [ $# -gt 0 ]; do
    case "$1" in
      --old) old="$2"; shift 2 ;;
      --runs) runs="$2"; shift 2 ;;
      --sizes) sizes="$2"; shift 2 ;;
      --threads) threads="$2"; shift 2 ;;
      *) echo "usage: $script [--old PATH] [--runs N] [--sizes LIST] [--threads LIST]" >&2; exit 2 ;;
    esac
  done
}

check_tools() {
  new=target/release/seamlit
  gen=target/release/seamlit-bench
  for b in "$new" "$gen"; do
    [ -x "$b" ] || { echo "$script: $b is missing: cargo build --release -p seamlit -p seamlit-bench" >&2; exit 2; }
  done
  [ -z "$old" ] || [ -x "$old" ] || { echo "$script: --old $old is not an executable" >&2; exit 2; }
  [ -x /usr/bin/time ] || { echo "$script: needs GNU time (apt-get install time)" >&2; exit 2; }
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
}

# One run: prints "seconds kilobytes".
once() {
  /usr/bin/time -f "%e %M" -o "$work/time" "$@" >/dev/null 2>"$work/err" ||
    { echo "failed: $* ($(tail -1 "$work/err"))" >&2; exit 1; }
  cat "$work/time"
}

median() { sort -n | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }

time_cases() {
  local tris=$1 t=$2 c name cmd s k r
  declare -A secs=() mem=()
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
}

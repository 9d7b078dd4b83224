#!/usr/bin/env bash
# Runs one fuzz target: fuzz/run.sh TARGET [SECONDS] [extra libFuzzer flags...]
# The corpus grows in fuzz/corpus/TARGET (not checked in), seeded from fuzz/seeds/TARGET
# (checked in); crashes, hangs and OOMs land in fuzz/artifacts/TARGET.
# Built without a sanitizer (all seamlit crates forbid unsafe code; a panic, a stack overflow,
# a hang or an allocation past -rss_limit_mb is what we look for), with debug assertions
# (integer overflow panics).
set -euo pipefail
cd "$(dirname "$0")"
target=$1
seconds=${2:-600}
shift $(( $# >= 2 ? 2 : 1 ))
mkdir -p "corpus/$target" "artifacts/$target"
# seamlit-scene (and with it wgpu) is built for the `scene` target only.
features=()
if [ "$target" = scene ]; then features=(--features scene); fi
exec cargo +${FUZZ_TOOLCHAIN:-nightly} fuzz run --sanitizer none --debug-assertions "${features[@]}" "$target" \
  "corpus/$target" "seeds/$target" -- \
  -max_total_time="$seconds" -rss_limit_mb=2048 -malloc_limit_mb=2048 -timeout=10 -max_len=16384 \
  -print_final_stats=1 "$@"

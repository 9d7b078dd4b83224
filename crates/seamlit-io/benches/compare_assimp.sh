#!/usr/bin/env bash
# Times seamlit-io and `assimp info` (Debian package assimp-utils) loading the same
# 1M-triangle OBJ and GLB, as whole processes: wall time and CPU time (user + sys).
# Usage: crates/seamlit-io/benches/compare_assimp.sh [DIR]   (files go to DIR, default /tmp/sio-bench)
set -euo pipefail
cd "$(dirname "$0")/../../.."
dir="${1:-/tmp/sio-bench}"
cargo build --release -q -p seamlit-io --example load_info
bin=target/release/examples/load_info
[ -f "$dir/teapot-1m.obj" ] && [ -f "$dir/teapot-1m.glb" ] || "$bin" --generate "$dir"
command -v assimp >/dev/null || { echo "assimp not found: apt-get install assimp-utils" >&2; exit 2; }
echo "commit: $(git rev-parse --short HEAD 2>/dev/null || echo unknown)$(git diff --quiet -- crates 2>/dev/null || echo ' (with uncommitted changes)')"
echo "machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores, $(free -g | awk '/Mem:/{print $2}') GiB"
echo "load average: $(cut -d' ' -f1-3 /proc/loadavg)"
for file in "$dir/teapot-1m.obj" "$dir/teapot-1m.glb"; do
  for run in 1 2 3; do
    /usr/bin/time -f "seamlit-io        $(basename "$file") run $run: %e s wall, %U s user, %S s sys, %M KB max RSS" "$bin" "$file" >/dev/null
    /usr/bin/time -f "assimp info -r    $(basename "$file") run $run: %e s wall, %U s user, %S s sys, %M KB max RSS" assimp info "$file" -r -s >/dev/null
    /usr/bin/time -f "assimp info       $(basename "$file") run $run: %e s wall, %U s user, %S s sys, %M KB max RSS" assimp info "$file" -s >/dev/null
  done
done
echo "load average: $(cut -d' ' -f1-3 /proc/loadavg)"

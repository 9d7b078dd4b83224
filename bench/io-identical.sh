#!/usr/bin/env bash
# Runs `seamlit fix` on every model file under assets/ (.obj, .gltf, .glb, .vrm, .fbx, .usda,
# .usdc, .usdz, .usd; subfolders and assets/validator-corpus included) and on the fuzz
# regression inputs of crates/seamlit-io/tests/regressions (which fail, each with its own
# error) to .gltf, .glb and .obj, for glTF inputs once more to .glb with --keep-compression,
# for VRM inputs to .vrm and for USD inputs to .usda, .usdc and .usdz, and writes a sha256
# manifest of everything written: the
# output files, and for each run its exit code and stderr. Two manifests of two builds diff
# empty when the builds write the same bytes and fail the same way (issue 24: a restructure
# of seamlit-io must change no output).
#
# Usage: bench/io-identical.sh MANIFEST [BINARY] [WORK]
#   BINARY defaults to target/debug/seamlit, WORK (cleared first) to /tmp/io-identical-work.
#   Use the same WORK for both runs: error lines and warnings name the output paths.
# Example:
#   cargo build -p seamlit && bench/io-identical.sh /tmp/io-baseline/manifest.txt
#   ...change the code...
#   cargo build -p seamlit && bench/io-identical.sh /tmp/io-after.txt
#   diff /tmp/io-baseline/manifest.txt /tmp/io-after.txt && echo identical
set -uo pipefail

manifest=${1:?usage: bench/io-identical.sh MANIFEST [BINARY] [WORK]}
root=$(cd "$(dirname "$0")/.." && pwd)
binary=${2:-$root/target/debug/seamlit}
work=${3:-/tmp/io-identical-work}
case $manifest in /*) ;; *) manifest=$PWD/$manifest ;; esac
case $binary in /*) ;; *) binary=$PWD/$binary ;; esac

rm -rf "$work"
mkdir -p "$work" "$(dirname "$manifest")"
cd "$root" || exit 1

run() { # run NAME INPUT OUTPUT [FLAGS...]
  local name=$1 input=$2 output=$3
  shift 3
  local dir=$work/$name
  mkdir -p "$dir"
  "$binary" fix "$input" -o "$dir/$output" "$@" >"$dir/stdout.txt" 2>"$dir/stderr.txt"
  echo $? >"$dir/exit-code.txt"
}

count=0
while IFS= read -r input; do
  name=${input//\//__}
  run "$name/gltf" "$input" out.gltf
  run "$name/glb" "$input" out.glb
  run "$name/obj" "$input" out.obj
  case ${input,,} in
    *.gltf | *.glb) run "$name/keep" "$input" out.glb --keep-compression ;;
    *.vrm) run "$name/vrm" "$input" out.vrm ;;
    *.usda | *.usdc | *.usdz | *.usd)
      run "$name/usda" "$input" out.usda
      run "$name/usdc" "$input" out.usdc
      run "$name/usdz" "$input" out.usdz
      ;;
  esac
  count=$((count + 1))
done < <(find assets crates/seamlit-io/tests/regressions -type f \
  \( -iname '*.obj' -o -iname '*.gltf' -o -iname '*.glb' -o -iname '*.vrm' -o -iname '*.fbx' \
  -o -iname '*.usda' -o -iname '*.usdc' -o -iname '*.usdz' -o -iname '*.usd' \) | LC_ALL=C sort)

(cd "$work" && find . -type f | LC_ALL=C sort | xargs -d '\n' sha256sum) >"$manifest"
failed=$(grep -l -v '^0$' "$work"/*/*/exit-code.txt | wc -l)
echo "$count inputs, $(wc -l <"$manifest") files in $manifest, $failed runs failed"

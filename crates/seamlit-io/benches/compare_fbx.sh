#!/usr/bin/env bash
# Times loading the same 1M-triangle model as FBX and as GLB, as whole processes: seamlit-io
# (the load_info example), `assimp info` (Debian assimp-utils; -r = raw, no post-processing)
# and Blender's own FBX and glTF importers (the bpy module; Python with bpy imported and
# nothing loaded is timed too, to subtract). Wall time, CPU (user + sys), peak RSS.
# Inputs: the load bench's teapot (load_info --generate) imported by Blender and exported as
# FBX and as GLB from one scene (fbx_inputs.py), so both files hold the same model.
# Usage: crates/seamlit-io/benches/compare_fbx.sh [DIR] [RUNS]   (files go to DIR, default /tmp/sio-fbx-bench)
set -euo pipefail
cd "$(dirname "$0")/../../.."
dir="${1:-/tmp/sio-fbx-bench}"
runs="${2:-3}"
python="${PYTHON:-python3}"
cargo build --release -q -p seamlit-io --example load_info
bin=target/release/examples/load_info
mkdir -p "$dir"
[ -f "$dir/teapot-1m.glb" ] || "$bin" --generate "$dir" >/dev/null
[ -f "$dir/model.fbx" ] && [ -f "$dir/model.glb" ] ||
  "$python" crates/seamlit-io/benches/fbx_inputs.py "$dir/teapot-1m.glb" "$dir" >/dev/null 2>&1 ||
  { echo "Blender (bpy) could not write the inputs: pip install bpy==5.0.1" >&2; exit 2; }
command -v assimp >/dev/null || { echo "assimp not found: apt-get install assimp-utils" >&2; exit 2; }
echo "commit: $(git rev-parse --short HEAD 2>/dev/null || echo unknown)$(git diff --quiet -- crates 2>/dev/null || echo ' (with uncommitted changes)')"
echo "machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores, $(free -g | awk '/Mem:/{print $2}') GiB"
echo "files: $(du -h "$dir/model.fbx" | cut -f1) FBX, $(du -h "$dir/model.glb" | cut -f1) GLB"
echo "load average: $(cut -d' ' -f1-3 /proc/loadavg)"
# One timed run: timed LABEL COMMAND...; the command's own output is dropped.
timed() {
  /usr/bin/time -o "$dir/time" -f "%e s wall, %U s user, %S s sys, %M KB max RSS" "${@:2}" >/dev/null 2>&1 ||
    { echo "$1 failed" >&2; exit 1; }
  printf '%-34s run %s: %s\n' "$1" "$run" "$(cat "$dir/time")"
}
for run in $(seq "$runs"); do
  for file in "$dir/model.fbx" "$dir/model.glb"; do
    name=$(basename "$file")
    importer=$([ "${name##*.}" = fbx ] && echo fbx || echo gltf)
    timed "seamlit-io $name" "$bin" "$file"
    timed "assimp info -r $name" assimp info "$file" -r -s
    timed "Blender import $name" "$python" -c "import bpy; bpy.ops.wm.read_factory_settings(use_empty=True); bpy.ops.import_scene.$importer(filepath='$file')"
  done
  timed "Blender start-up, nothing read" "$python" -c "import bpy; bpy.ops.wm.read_factory_settings(use_empty=True)"
done
echo "load average: $(cut -d' ' -f1-3 /proc/loadavg)"

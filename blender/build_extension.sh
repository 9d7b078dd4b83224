#!/usr/bin/env bash
# Builds the Blender extension: target/blender/seamlit_seams-VERSION.zip, the add-on in
# blender/seamlit_seams with the `seamlit` wheel inside it and named in its manifest, ready
# for Blender's Edit > Preferences > Get Extensions > Install from Disk.
#
# The wheel is built with maturin for the stable ABI of Python 3.11 and later (abi3): one
# wheel for the Python of Blender 4.2 to 5.0 (3.11) and for newer Blenders' newer Pythons.
# It is for the platform this runs on; build on each platform you ship to.
#
# Usage: blender/build_extension.sh [--dev]
#   --dev   a debug build (fast to compile, slow to run; for tests)
# Environment: PYTHON, the Python that runs maturin (default python3; `pip install maturin`).
# Needs: cargo, a Python 3 with maturin.
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
profile=release
case "${1:-}" in
  --dev) profile=dev ;;
  "") ;;
  *) echo "usage: blender/build_extension.sh [--dev]" >&2; exit 2 ;;
esac
python=${PYTHON:-python3}
source_dir=blender/seamlit_seams
out=target/blender
version=$(sed -n 's/^version = "\(.*\)"$/\1/p' "$source_dir/blender_manifest.toml" | head -n 1)
[ -n "$version" ] || { echo "no version in $source_dir/blender_manifest.toml" >&2; exit 1; }

rm -rf "$out/wheel" "$out/stage"
mkdir -p "$out/wheel" "$out/stage/wheels"
"$python" -m maturin build --quiet --profile "$profile" -m crates/seamlit-py/Cargo.toml \
  -i "$python" --features pyo3/abi3-py311 -o "$out/wheel"
wheel=$(ls "$out"/wheel/seamlit-*.whl)
[ "$(wc -l <<<"$wheel")" = 1 ] || { echo "expected one wheel, found: $wheel" >&2; exit 1; }
name=$(basename "$wheel")

# The platform Blender calls the wheel's (its manifest's `platforms`).
case "$name" in
  *manylinux*x86_64.whl | *linux_x86_64.whl) platform=linux-x64 ;;
  *manylinux*aarch64.whl | *linux_aarch64.whl) platform=linux-arm64 ;;
  *macosx*arm64.whl) platform=macos-arm64 ;;
  *macosx*x86_64.whl) platform=macos-x64 ;;
  *win_amd64.whl) platform=windows-x64 ;;
  *win_arm64.whl) platform=windows-arm64 ;;
  *) echo "a wheel for a platform Blender does not name: $name" >&2; exit 1 ;;
esac

cp "$wheel" "$out/stage/wheels/"
for file in "$source_dir"/*; do
  case "$(basename "$file")" in
    __pycache__ | wheels) ;;
    blender_manifest.toml) ;;
    *) cp -R "$file" "$out/stage/" ;;
  esac
done
# The manifest as written, with the wheel and its platform named.
{
  grep -v -E '^(wheels|platforms) *=' "$source_dir/blender_manifest.toml"
  echo
  echo "# Added by blender/build_extension.sh."
  echo "platforms = [\"$platform\"]"
  echo "wheels = [\"./wheels/$name\"]"
} >"$out/stage/blender_manifest.toml"

zip="$out/seamlit_seams-$version.zip"
rm -f "$zip"
"$python" - "$out/stage" "$zip" <<'PY'
import pathlib, sys, zipfile
stage, zip_path = pathlib.Path(sys.argv[1]), sys.argv[2]
with zipfile.ZipFile(zip_path, "w", zipfile.ZIP_DEFLATED) as z:
    for path in sorted(stage.rglob("*")):
        if path.is_file() and "__pycache__" not in path.parts:
            z.write(path, path.relative_to(stage).as_posix())
PY
echo "$zip"

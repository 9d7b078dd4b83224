#!/usr/bin/env bash
# Builds the seamlit web page into target/web/ (a folder any static file server can serve):
#   web/build.sh          optimised for size (profile `web`), what is published and measured
#   web/build.sh --dev    the dev profile, quicker to build, for the browser tests
# Needs the wasm32-unknown-unknown target, clang (meshopt's C++ for wasm32) and the
# wasm-bindgen CLI at exactly the version of the wasm-bindgen crate in Cargo.lock; it installs
# what is missing (rustup, apt-get, cargo install).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
profile=web
[ "${1:-}" = "--dev" ] && profile=dev

rustup target list --installed | grep -qx wasm32-unknown-unknown ||
  rustup target add wasm32-unknown-unknown
if ! command -v clang >/dev/null 2>&1; then
  if [ "$(id -u)" = 0 ]; then sudo=""; else sudo="sudo"; fi
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq clang >/dev/null
fi
version=$(awk '/^name = "wasm-bindgen"$/ { getline; gsub(/[^0-9.]/, ""); print; exit }' Cargo.lock)
if [ "$(wasm-bindgen --version 2>/dev/null | awk '{print $2}')" != "$version" ]; then
  echo "web: installing wasm-bindgen-cli $version"
  # Only the `wasm-bindgen` program, without TLS (that is for the test runner's downloads):
  # a quicker cold build. Not --locked: its lock file names a webpki-roots release that
  # crates.io no longer serves.
  cargo install -q wasm-bindgen-cli --version "$version" --no-default-features --bin wasm-bindgen
fi

# The C flags of a wasm32 build (web/wasm-env.sh).
. web/wasm-env.sh

target_dir=${CARGO_TARGET_DIR:-$root/target}
cargo build -q --target wasm32-unknown-unknown -p seamlit-web --profile "$profile"
out_profile=$profile
[ "$profile" = dev ] && out_profile=debug
out=$root/target/web
rm -rf "$out"
mkdir -p "$out"
wasm-bindgen --target web --no-typescript --out-dir "$out/pkg" \
  "$target_dir/wasm32-unknown-unknown/$out_profile/seamlit_web.wasm"
cp web/index.html web/main.js web/style.css "$out/"
echo "$out"

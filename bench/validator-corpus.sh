#!/usr/bin/env bash
# Regenerates assets/validator-corpus/: every model file of the Khronos glTF Validator's own
# test suite that has a report (X.gltf.report.json or X.glb.report.json beside it), valid
# (issues.numErrors == 0) or not, with that report, the side files (.bin, images) of their
# folders, the repository's LICENSE and a SOURCES.md that says so. The valid ones must load
# (tests/validator_corpus.rs); no file, valid or not, may end in a panic.
#
# Usage: bench/validator-corpus.sh [GIT_DIR] [COMMIT]
#   GIT_DIR defaults to /work/.mirror/KhronosGroup+glTF-Validator/repo (a bare clone of
#   https://github.com/KhronosGroup/glTF-Validator), COMMIT to 434283b.
# Needs git and jq.
set -euo pipefail

git_dir=${1:-/work/.mirror/KhronosGroup+glTF-Validator/repo}
commit=${2:-434283b}
root=$(cd "$(dirname "$0")/.." && pwd)
out=$root/assets/validator-corpus
full=$(git -C "$git_dir" rev-parse "$commit^{commit}")

rm -rf "$out"
mkdir -p "$out"

show() { git -C "$git_dir" show "$full:$1"; }

files=$(git -C "$git_dir" ls-tree -r --name-only "$full" -- test)
valid=0
total=0
folders=()
while IFS= read -r report; do
  model=${report%.report.json}
  total=$((total + 1))
  errors=$(show "$report" | jq '.issues.numErrors')
  if [ "$errors" = 0 ]; then
    valid=$((valid + 1))
  fi
  mkdir -p "$out/$(dirname "$model")"
  show "$model" >"$out/$model"
  show "$report" >"$out/$report"
  folders+=("$(dirname "$model")")
done < <(grep -E '\.(gltf|glb)\.report\.json$' <<<"$files")

# Side files: every buffer and image file in a folder that holds a model.
for folder in $(printf '%s\n' "${folders[@]}" | sort -u); do
  grep -E "^$folder/[^/]+\.(bin|png|jpg|jpeg|webp|ktx2)$" <<<"$files" | while IFS= read -r side; do
    show "$side" >"$out/$side"
  done || true
done

show LICENSE >"$out/LICENSE"
cat >"$out/SOURCES.md" <<SOURCES
# glTF Validator corpus

Files made by other people, kept in the repository so that a clone runs its tests alone:
\`crates/seamlit-io/tests/validator_corpus.rs\` checks that seamlit accepts every glTF the
Khronos glTF Validator reports valid (issue 11), and
\`no_file_of_the_corpus_panics\` there that no file, valid or invalid, ends in a panic
(issue 32). \`bench/validator-corpus.sh\` regenerates this folder from a clone of the
repository below.

| files | what they are | what the tests use them for | source | licence |
|---|---|---|---|---|
| \`test/**\` ($total models, their reports and side files) | the validator's own test files: every \`X.gltf\`/\`X.glb\` with an \`X.gltf.report.json\`/\`X.glb.report.json\` beside it ($valid of the $total report \`issues.numErrors == 0\`), that report, and every \`.bin\`, \`.png\`, \`.jpg\`, \`.webp\`, \`.ktx2\` file in a folder holding one of them; paths as in the repository | every valid file must load (but a short list of named refusals) and its pass-through output must be valid; no file, valid or not, may end in a panic | https://github.com/KhronosGroup/glTF-Validator, folder \`test/\`, commit \`$full\` | Apache-2.0, \`LICENSE\` here (the repository's own) |
SOURCES
echo "$total reported files ($valid valid) -> $out ($(du -sh --apparent-size "$out" | cut -f1))"

#!/usr/bin/env bash
# bench/corpus.sh: seamlit over other projects' OBJ and glTF test files, beside the readers
# people use (issue 27). Not run by CI: the files are not in this repository.
#
# For each .obj, .gltf and .glb file of the corpora: `seamlit inspect FILE` (loaded, or the
# one error line), `assimp info FILE` (Assimp's command line, apt-get install assimp-utils),
# trimesh.load (Python), and for glTF the Khronos validator's error count (tests/validate.cjs,
# .ci/node). Prints one row per file (TSV) to OUT/files.tsv and a summary per corpus and
# outcome to stdout (the table in BENCHMARKS.md).
#
# Usage: bench/corpus.sh [OUT]   (default bench/out/corpus)
# Corpora, from bare clones (the mirrors below, or GIT DIRs in the environment):
#   ASSIMP_GIT  assimp/assimp: test/models/{OBJ,glTF,glTF2}, test/models-nonbsd/OBJ
#   TOBJ_GIT    Twinklebear/tobj: obj/
# Needs: target/debug/seamlit or target/release/seamlit (SEAMLIT=path), git, node, python3
# with trimesh; assimp is optional (its column is "-" without it).
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
OUT=${1:-$ROOT/bench/out/corpus}
ASSIMP_GIT=${ASSIMP_GIT:-/work/.mirror/assimp+assimp/repo}
TOBJ_GIT=${TOBJ_GIT:-/work/.mirror/Twinklebear+tobj/repo}
SEAMLIT=${SEAMLIT:-$( (ls "$ROOT"/target/release/seamlit "$ROOT"/target/debug/seamlit 2>/dev/null || true) | head -n 1)}
[ -x "$SEAMLIT" ] || { echo "no seamlit binary: cargo build -p seamlit" >&2; exit 1; }

rm -rf "$OUT"
mkdir -p "$OUT/files"
extract() { # NAME GIT_DIR PATH...
  local name=$1 git=$2
  shift 2
  if [ ! -d "$git" ]; then
    echo "corpus $name: $git is missing; skipped" >&2
    return
  fi
  mkdir -p "$OUT/files/$name"
  # File by file: a snapshot may lack its largest blobs (those are left out, and counted).
  local missing=0 mode type blob path
  while IFS=$' \t' read -r mode type blob path; do
    mkdir -p "$OUT/files/$name/$(dirname "$path")"
    git -C "$git" cat-file blob "$blob" >"$OUT/files/$name/$path" 2>/dev/null ||
      { rm -f "$OUT/files/$name/$path"; missing=$((missing + 1)); }
  done < <(git -C "$git" ls-tree -r HEAD -- "$@")
  echo "corpus $name: $(git -C "$git" rev-parse --short HEAD), $missing file(s) absent from the snapshot" >&2
}
extract assimp "$ASSIMP_GIT" test/models/OBJ test/models/glTF test/models/glTF2 test/models-nonbsd/OBJ
extract tobj "$TOBJ_GIT" obj

mapfile -t files < <(cd "$OUT/files" && find . -type f \( -iname '*.obj' -o -iname '*.gltf' -o -iname '*.glb' \) | sed 's|^\./||' | sort)

# The validator on every glTF at once (one node start-up).
gltfs=()
for f in "${files[@]}"; do
  case "${f,,}" in *.gltf | *.glb) gltfs+=("$OUT/files/$f") ;; esac
done
declare -A validator
if [ ${#gltfs[@]} -gt 0 ]; then
  while IFS=$'\t' read -r file errors; do
    validator[$file]=$errors
  done < <(node "$ROOT/crates/seamlit-io/tests/validate.cjs" "${gltfs[@]}" |
    python3 -c 'import json,sys
for line in sys.stdin:
    r = json.loads(line); print(r["file"] + "\t" + str(r["errors"]))')
fi

printf 'file\tseamlit\tseamlit_error\tassimp\ttrimesh\tvalidator_errors\n' >"$OUT/files.tsv"
for f in "${files[@]}"; do
  path="$OUT/files/$f"
  if err=$(timeout 60 "$SEAMLIT" inspect "$path" 2>&1 >/dev/null); then
    s=loaded; e=""
  else
    s="refused"; e=$(grep -m1 '^error: ' <<<"$err" | sed "s|$OUT/files/||g; s|\t| |g" || true)
  fi
  if command -v assimp >/dev/null; then
    if timeout 60 assimp info "$path" >/dev/null 2>&1; then a=loaded; else a=refused; fi
  else
    a=-
  fi
  if timeout 60 python3 -c 'import sys, trimesh; trimesh.load(sys.argv[1])' "$path" >/dev/null 2>&1; then
    t=loaded
  else
    t=refused
  fi
  v=${validator[$path]:--}
  printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$f" "$s" "$e" "$a" "$t" "$v" >>"$OUT/files.tsv"
done

python3 - "$OUT/files.tsv" <<'PY'
import csv, sys, collections
rows = list(csv.DictReader(open(sys.argv[1]), delimiter="\t"))
print("| corpus | files | seamlit loads | refused, no other reader loads it | refused, another reader loads it |")
print("|---|---|---|---|---|")
by = collections.defaultdict(list)
for r in rows:
    by[r["file"].split("/")[0] + " " + r["file"].rsplit(".", 1)[-1].lower()].append(r)
for key in sorted(by):
    rs = by[key]
    loaded = sum(r["seamlit"] == "loaded" for r in rs)
    others = lambda r: r["assimp"] == "loaded" or r["trimesh"] == "loaded" or r["validator_errors"] == "0"
    alone = sum(r["seamlit"] != "loaded" and not others(r) for r in rs)
    print(f"| {key} | {len(rs)} | {loaded} | {alone} | {len(rs) - loaded - alone} |")
print()
print("Refused files, why, and the other readers (assimp, trimesh, validator errors):")
print()
for r in rows:
    if r["seamlit"] != "loaded":
        print(f"- `{r['file']}`: {r['seamlit_error'][7:]} (assimp {r['assimp']}, trimesh {r['trimesh']}, validator {r['validator_errors']})")
PY

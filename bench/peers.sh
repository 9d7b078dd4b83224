#!/usr/bin/env bash
# bench/peers.sh: `seamlit fix` against the tools users have today, on the same files.
#
# Peers: Assimp's command line (assimp export IN OUT -jiv -gsn -cts), glTF-Transform's
# command line (weld, then tangents), the paper's reference algorithm (O(V x F), where it
# finishes within REF_TIMEOUT seconds), and `seamlit fix`. For each model and peer: whole-process
# wall time and peak resident memory (/usr/bin/time -f '%e %M'), RUNS runs with the peers taking
# turns inside each run, the median, and the ratio to seamlit's median of this invocation.
# Then `seamlit inspect --json` on every peer's output (seam quality) and a side-by-side render
# of the teapot as each peer wrote it.
#
# Usage: bench/peers.sh [--quick] [--runs N] [--out DIR]
#   --quick   fewer and smaller models, 3 runs (a few minutes)
#   --runs N  runs per model and peer (default 5; models above 500k triangles get 3)
#   --out DIR where inputs, outputs, logs and results.md go (default bench/out)
#
# Installs nothing. Needs: target/release/seamlit and target/release/seamlit-bench
# (cargo build --release -p seamlit -p seamlit-bench), /usr/bin/time and jq. Peers it skips
# with a message when missing: assimp (apt-get install assimp-utils), glTF-Transform
# (npm ci --prefix bench, which installs the pinned @gltf-transform/cli into bench/node_modules).
# Environment: SEAMLIT, SEAMLIT_BENCH, ASSIMP, GLTF_TRANSFORM (paths of the tools), MODELS (the
# small models, default assets/models), LARGE (the large models, default ../shared/models/large
# beside the checkout; their rows are skipped with a message when absent), REF_TIMEOUT (240 s), REF_MAX_TRIANGLES (110000), ONLY (model names to
# keep, e.g. ONLY=teapot-128).
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
QUICK=0
RUNS=""
OUT="$ROOT/bench/out"
while [[ $# -gt 0 ]]; do
    case "$1" in
        --quick) QUICK=1 ;;
        --runs) RUNS=${2:?--runs needs a number}; shift ;;
        --out) OUT=${2:?--out needs a folder}; shift ;;
        -h|--help) sed -n '2,22p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
        *) echo "peers.sh: unknown argument $1 (see --help)" >&2; exit 2 ;;
    esac
    shift
done
if [[ -z "$RUNS" ]]; then RUNS=$([[ $QUICK == 1 ]] && echo 3 || echo 5); fi
[[ "$RUNS" =~ ^[1-9][0-9]*$ ]] || { echo "peers.sh: --runs must be a positive number" >&2; exit 2; }

SEAMLIT=${SEAMLIT:-$ROOT/target/release/seamlit}
BENCH=${SEAMLIT_BENCH:-$ROOT/target/release/seamlit-bench}
GLTF_TRANSFORM=${GLTF_TRANSFORM:-$ROOT/bench/node_modules/.bin/gltf-transform}
ASSIMP=${ASSIMP:-$(command -v assimp || true)}
MODELS=${MODELS:-$ROOT/assets/models}
LARGE=${LARGE:-$ROOT/../shared/models/large}
REF_TIMEOUT=${REF_TIMEOUT:-240}         # seconds; the reference is O(V x F)
REF_MAX_TRIANGLES=${REF_MAX_TRIANGLES:-110000}
BIG=500000                              # triangles above which a model gets at most 3 runs

# ---- what is here -----------------------------------------------------------------------
fail() { echo "peers.sh: $*" >&2; exit 2; }
[[ -x "$SEAMLIT" && -x "$BENCH" ]] ||
    fail "missing $SEAMLIT or $BENCH; build them with: cargo build --release -p seamlit -p seamlit-bench"
[[ -x /usr/bin/time ]] || fail "/usr/bin/time is missing; install it with: sudo apt-get install time"
command -v jq >/dev/null || fail "jq is missing; install it with: sudo apt-get install jq"
[[ -d "$MODELS" ]] || fail "no models at $MODELS (set MODELS=...)"

PEERS=(seamlit)
if [[ -n "$ASSIMP" && -x "$ASSIMP" ]]; then
    PEERS+=(assimp)
else
    echo "skipping Assimp: not found; install it with: sudo apt-get install assimp-utils" >&2
fi
if [[ -x "$GLTF_TRANSFORM" ]] && command -v node >/dev/null; then
    PEERS+=(gltf-transform)
else
    echo "skipping glTF-Transform: not found; install it with: npm ci --prefix bench" \
        "(needs node and npm; installs @gltf-transform/cli into bench/node_modules)" >&2
fi
PEERS+=(reference)

mkdir -p "$OUT"/{inputs,outputs,times,reports}
LOG="$OUT/log.txt"
: >"$LOG"
say() { echo "$*" | tee -a "$LOG" >&2; }

# ---- inputs: every tool reads the same GLB (positions, UVs, objects; no normals) ---------
# name|source: "teapot:N" is the demo teapot at N x N quads per patch (32 objects).
if [[ $QUICK == 1 ]]; then
    LIST=("teapot-16|teapot:16" "teapot-64|teapot:64"
        "cornell_box|$MODELS/cornell_box/cornell_box.obj" "groups|$MODELS/groups.obj"
        "NormalTangentTest|$MODELS/NormalTangentTest.glb")
else
    LIST=("teapot-16|teapot:16" "teapot-64|teapot:64" "teapot-128|teapot:128"
        "cornell_box|$MODELS/cornell_box/cornell_box.obj" "groups|$MODELS/groups.obj"
        "NormalTangentTest|$MODELS/NormalTangentTest.glb"
        "spot|$MODELS/spot/spot_triangulated.obj")
    if [[ -d "$LARGE" ]]; then
        LIST+=("stanford-bunny|$LARGE/stanford-bunny.obj" "nefertiti|$LARGE/nefertiti.obj")
    else
        echo "skipping stanford-bunny and nefertiti: no large models at $LARGE (set LARGE=...)" >&2
    fi
fi

# ONLY="name ..." keeps just those models (to rerun one row).
if [[ -n ${ONLY:-} ]]; then
    KEEP=()
    for entry in "${LIST[@]}"; do
        [[ " $ONLY " == *" ${entry%%|*} "* ]] && KEEP+=("$entry")
    done
    LIST=("${KEEP[@]}")
fi

NAMES=()
declare -A TRIS OBJS
for entry in "${LIST[@]}"; do
    name=${entry%%|*}
    src=${entry#*|}
    in="$OUT/inputs/$name.glb"
    if [[ $src == teapot:* ]]; then
        "$BENCH" teapot "${src#teapot:}" "$in" >>"$LOG"
    else
        "$BENCH" input "$src" "$in" >>"$LOG"
    fi
    # glTF-Transform has no smooth-normal generator and its `tangents` needs NORMAL: it gets
    # the normals an exporter writes, smooth within each object (seamlit --mode object).
    "$SEAMLIT" fix "$in" -o "$OUT/inputs/$name.object-normals.glb" --mode object \
        --tangents none >>"$LOG"
    "$SEAMLIT" inspect --json "$in" >"$OUT/reports/$name.input.json"
    TRIS[$name]=$(jq '.as_loaded.triangles' "$OUT/reports/$name.input.json")
    OBJS[$name]=$(jq '.as_loaded.objects' "$OUT/reports/$name.input.json")
    NAMES+=("$name")
    say "input $name: ${OBJS[$name]} objects, ${TRIS[$name]} triangles"
done

# ---- timing ------------------------------------------------------------------------------
# timed FILE CMD...: runs CMD under /usr/bin/time and appends "seconds kilobytes" to FILE.
timed() {
    local file=$1; shift
    echo "+ $*" >>"$LOG"
    if /usr/bin/time -f '%e %M' -o "$file.one" "$@" >>"$LOG" 2>&1; then
        tail -n 1 "$file.one" >>"$file"
    else
        echo "  failed: $(tr '\n' ' ' <"$file.one")" >>"$LOG"
        return 1
    fi
}

# run_peer PEER NAME RUN: one run of PEER on model NAME; appends "seconds kilobytes" (summed
# over the peer's processes, peak = the largest) to times/NAME.PEER, or "fail"/"skip".
run_peer() {
    local peer=$1 name=$2 in="$OUT/inputs/$2.glb" out="$OUT/outputs/$2.$1.glb"
    local steps="$OUT/times/$name.$peer.steps"
    : >"$steps"
    case $peer in
        seamlit) timed "$steps" "$SEAMLIT" fix "$in" -o "$out" ;;
        assimp) timed "$steps" "$ASSIMP" export "$in" "$out" -fglb2 -jiv -gsn -cts ;;
        gltf-transform)
            timed "$steps" "$GLTF_TRANSFORM" weld "$OUT/inputs/$name.object-normals.glb" \
                "$OUT/outputs/$name.welded.glb" &&
                timed "$steps" "$GLTF_TRANSFORM" tangents "$OUT/outputs/$name.welded.glb" "$out" ;;
        reference) timed "$steps" timeout "$REF_TIMEOUT" "$BENCH" reference "$in" "$out" ;;
    esac || { echo fail >>"$OUT/times/$name.$peer"; return 0; }
    awk '{s += $1; if ($2 > m) m = $2} END {printf "%.2f %d\n", s, m}' "$steps" \
        >>"$OUT/times/$name.$peer"
}

# median of the first column (or of the second with COL=2) of the numeric lines of a file.
median() {
    awk -v c="${COL:-1}" '$1 != "fail" {print $c}' "$1" | sort -g |
        awk '{v[NR] = $1} END {if (NR == 0) print "-"; else if (NR % 2) print v[(NR + 1) / 2];
             else printf "%.2f\n", (v[NR / 2] + v[NR / 2 + 1]) / 2}'
}

for name in "${NAMES[@]}"; do
    runs=$RUNS
    if (( TRIS[$name] > BIG && runs > 3 )); then runs=3; fi
    for peer in "${PEERS[@]}"; do rm -f "$OUT/times/$name.$peer"; done
    for ((r = 1; r <= runs; r++)); do
        for peer in "${PEERS[@]}"; do
            if [[ $peer == reference ]]; then
                # O(V x F): too slow past REF_MAX_TRIANGLES, and one run is enough past 20k.
                if (( TRIS[$name] > REF_MAX_TRIANGLES )); then
                    [[ $r == 1 ]] && echo skip >"$OUT/times/$name.reference"
                    continue
                fi
                if (( TRIS[$name] > 20000 && r > 1 )); then continue; fi
            fi
            run_peer "$peer" "$name" "$r"
        done
    done
    say "timed $name ($runs runs)"
done

# ---- seam quality of each output ---------------------------------------------------------
for name in "${NAMES[@]}"; do
    for peer in "${PEERS[@]}"; do
        out="$OUT/outputs/$name.$peer.glb"
        json="$OUT/reports/$name.$peer.json"
        rm -f "$json"
        if [[ $peer == assimp ]]; then
            # Assimp 5.2's glTF 2 exporter drops the tangents it computed (-cts); its JSON dump
            # keeps them. Same input, same steps, untimed; seamlit-bench converts the dump.
            out="$OUT/outputs/$name.assimp-json.glb"
            "$ASSIMP" export "$OUT/inputs/$name.glb" "$OUT/outputs/$name.assjson" -fassjson \
                -jiv -gsn -cts >>"$LOG" 2>&1 &&
                "$BENCH" assjson "$OUT/outputs/$name.assjson" "$out" >>"$LOG" 2>&1 || rm -f "$out"
            rm -f "$OUT/outputs/$name.assjson"
        fi
        if [[ -f "$out" ]] && ! grep -qx 'fail\|skip' "$OUT/times/$name.$peer"; then
            "$SEAMLIT" inspect --json "$out" >"$json" 2>>"$LOG" || rm -f "$json"
        fi
    done
done

# ---- the tables --------------------------------------------------------------------------
fmt_angle() { jq -r "$1 | if . == null then \"-\" else (. * 100 | round / 100 | tostring) end" "$2"; }
label() {
    case $1 in
        seamlit) echo "seamlit fix" ;;
        assimp) echo "Assimp -jiv -gsn -cts" ;;  # quality: from its JSON dump, see above
        gltf-transform) echo "glTF-Transform weld + tangents" ;;
        reference) echo "paper's reference" ;;
    esac
}
RESULTS="$OUT/results.md"
{
    echo "| model | objects | triangles | tool | wall s (median) | peak MiB (median) | time / seamlit | memory / seamlit | runs |"
    echo "|---|---:|---:|---|---:|---:|---:|---:|---:|"
    for name in "${NAMES[@]}"; do
        base_s=$(median "$OUT/times/$name.seamlit")
        base_k=$(COL=2 median "$OUT/times/$name.seamlit")
        for peer in "${PEERS[@]}"; do
            file="$OUT/times/$name.$peer"
            if grep -qx skip "$file"; then
                echo "| $name | ${OBJS[$name]} | ${TRIS[$name]} | $(label "$peer") | not run (> $REF_MAX_TRIANGLES triangles) | | | | 0 |"
                continue
            fi
            n=$(grep -cvx fail "$file" || true)
            if [[ $n == 0 ]]; then
                echo "| $name | ${OBJS[$name]} | ${TRIS[$name]} | $(label "$peer") | failed (see log.txt) | | | | 0 |"
                continue
            fi
            s=$(median "$file")
            k=$(COL=2 median "$file")
            echo "| $name | ${OBJS[$name]} | ${TRIS[$name]} | $(label "$peer") | $s | $(awk -v k="$k" 'BEGIN {printf "%.0f", k / 1024}') | $(awk -v a="$s" -v b="$base_s" 'BEGIN {if (b > 0 && a > 0) printf "%.1fx", a / b; else printf "-"}') | $(awk -v a="$k" -v b="$base_k" 'BEGIN {if (b > 0 && a > 0) printf "%.1fx", a / b; else printf "-"}') | $n |"
        done
    done
    echo
    echo "| model | tool | max normal angle ° | mean normal angle ° | normal breaks > 1° | max tangent angle ° | max abs(n·t) | hard edges | min hard-edge angle ° |"
    echo "|---|---|---:|---:|---:|---:|---:|---:|---:|"
    for name in "${NAMES[@]}"; do
        for peer in "${PEERS[@]}"; do
            json="$OUT/reports/$name.$peer.json"
            [[ -f "$json" ]] || continue
            echo "| $name | $(label "$peer") | $(fmt_angle .as_loaded.cross_object.max_normal_angle_deg "$json") | $(fmt_angle .as_loaded.cross_object.mean_normal_angle_deg "$json") | $(jq .as_loaded.cross_object.normal_breaks "$json") | $(fmt_angle .as_loaded.cross_object.max_tangent_angle_deg "$json") | $(jq -r '.as_loaded.max_abs_dot_nt | if . == null then "-" else (. * 1e4 | round / 1e4 | tostring) end' "$json") | $(jq .as_loaded.cross_object.hard_edges "$json") | $(fmt_angle .as_loaded.cross_object.min_hard_edge_normal_angle_deg "$json") |"
        done
    done
} >"$RESULTS"

# ---- pictures: the teapot as each peer wrote it ------------------------------------------
PICS=()
for peer in assimp gltf-transform reference seamlit; do
    f="$OUT/outputs/teapot-16.$peer.glb"
    [[ $peer == assimp ]] && f="$OUT/outputs/teapot-16.assimp-json.glb"
    if [[ -f "$OUT/reports/teapot-16.$peer.json" ]]; then PICS+=("$f"); fi
done
if [[ ${#PICS[@]} -gt 0 ]]; then
    "$BENCH" render --demo --views lit,plain --size 300x225 --eye 2.0,4.3,7.0 --target 0,1.2,0 \
        -o "$OUT/teapot-peers.png" \
        "${PICS[@]}" >>"$LOG" 2>&1 && echo "columns of $OUT/teapot-peers.png: ${PICS[*]##*/}" >>"$RESULTS" ||
        say "render failed (no GPU or software rasteriser?): see $LOG"
fi

{
    echo
    echo "Machine: $(nproc) cores, $(awk -F': ' '/model name/ {print $2; exit}' /proc/cpuinfo)," \
        "$(free -g | awk '/Mem:/ {print $2}') GiB; load average at the end: $(cut -d' ' -f1-3 /proc/loadavg)"
    echo "Versions: $("$SEAMLIT" --version); $("$ASSIMP" version 2>/dev/null | grep -i -m1 'version' || echo 'assimp ?');" \
        "gltf-transform $("$GLTF_TRANSFORM" --version 2>/dev/null | tail -n 1 || echo '?')"
    echo "Runs: $RUNS (3 above $BIG triangles; the reference once above 20k triangles, not above $REF_MAX_TRIANGLES)"
} >>"$RESULTS"
cat "$RESULTS"

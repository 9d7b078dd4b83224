#!/usr/bin/env bash
# seamlit against the Khronos glTF Sample Viewer: the same models, camera, light and tone
# mapping in both, the mean FLIP error per model and the pictures side by side.
#
#   bench/sample-viewer/compare.sh [--environment] [--size WxH] [--out DIR]
#       [--animation N --times T1,T2,...] [NAME=FILE.glb ...]
#
# Models: those models.mjs builds (spheres: metallic x roughness; materials: emissive,
# textures, occlusion, alpha mask and blend), the Khronos samples in assets/models
# (NormalTangentTest, Fox), and each NAME=FILE.glb given. Each gets one glTF camera and one
# KHR_lights_punctual directional light (3 lux); seamlit renders through the same camera
# (as a scene file's [[camera]]), both with Khronos PBR Neutral tone mapping, exposure 1.
#
# Without --environment: punctual light only (the Sample Viewer's IBL off and no default
# lights; seamlit's --ambient 0). With --environment: both also light with the same
# equirectangular sky.hdr that models.mjs writes (seamlit: --environment PATH.hdr).
#
# With --animation N: only the models given, each posed by its animation N at each of the
# --times (seconds) in both (seamlit: --animation N --time T), pictures NAME@T.png.
#
# Writes DIR/viewer/NAME.png, DIR/seamlit/NAME.png, DIR/side-by-side/NAME.png (Sample Viewer |
# seamlit | FLIP error map) and DIR/flip.md (the table); DIR defaults to out/sample-viewer.
# Installs nothing: says what is missing and how to install it. See bench/sample-viewer/README.md.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
size=640x480
out=$root/out/sample-viewer
environment=0
models=("NormalTangentTest=$root/assets/models/NormalTangentTest.glb" "Fox=$root/assets/models/fox/Fox.glb")
given=()
animation=""
times=""
while [ $# -gt 0 ]; do
    case $1 in
        --environment) environment=1 ;;
        --animation) animation=$2; shift ;;
        --times) times=$2; shift ;;
        --size) size=$2; shift ;;
        --out) out=$2; shift ;;
        -h|--help) sed -n '2,23p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
        *=*) models+=("$1"); given+=("$1") ;;
        *) echo "compare.sh: unknown argument $1 (see --help)" >&2; exit 2 ;;
    esac
    shift
done
if [ -n "$animation" ]; then
    [ -n "$times" ] && [ ${#given[@]} -gt 0 ] ||
        { echo "compare.sh: --animation needs --times and NAME=FILE.glb models" >&2; exit 2; }
    models=("${given[@]}")
fi
width=${size%x*}
height=${size#*x}
# seamlit's background (linear 0.02, 0.02, 0.025, as sRGB bytes): the Sample Viewer clears to it.
background=(39 39 44)

missing=0
need() { # what, install command
    echo "compare.sh: $1 is missing; install it with: $2" >&2
    missing=1
}
command -v node > /dev/null || need node "apt-get install -y nodejs npm"
chromium=${CHROMIUM:-$(command -v chromium || true)}
[ -n "$chromium" ] && [ -x "$chromium" ] || need chromium "apt-get install -y chromium"
[ -d "$here/node_modules/@khronosgroup/gltf-viewer" ] && [ -d "$here/node_modules/puppeteer-core" ] ||
    need "the npm packages @khronosgroup/gltf-viewer and puppeteer-core" "npm ci --prefix bench/sample-viewer"
pick() { # binary name: the release build, else the debug one
    for profile in release debug; do
        [ -x "$root/target/$profile/$1" ] && { echo "$root/target/$profile/$1"; return; }
    done
}
seamlit=${SEAMLIT:-$(pick seamlit)}
bench=${SEAMLIT_BENCH:-$(pick seamlit-bench)}
[ -n "$seamlit" ] || need "target/release/seamlit" "cargo build --release -p seamlit"
[ -n "$bench" ] || need "target/release/seamlit-bench (FLIP)" "cargo build --release -p seamlit-bench"
[ $missing = 0 ] || exit 1

mkdir -p "$out/models" "$out/viewer" "$out/seamlit" "$out/side-by-side"
ASPECT="$width/$height" node "$here/models.mjs" "$out/models" "${models[@]}"
names=(spheres materials clearcoat sheen specular anisotropy transforms emissive variants transmission iridescence dispersion
    transmission_texture thickness_texture iridescence_texture iridescence_thickness_texture anisotropy_texture
    clearcoat_roughness_texture specular_texture)
[ -n "$animation" ] && names=()
for m in "${models[@]}"; do names+=("${m%%=*}"); done
# Each picture: NAME (unposed) or NAME@T (animation $animation at T seconds); and for a
# model with KHR_materials_variants, NAME%V for each variant V (picture NAME.V.png).
shots=()
for name in "${names[@]}"; do
    if [ -n "$animation" ]; then
        for t in ${times//,/ }; do shots+=("$name@$t"); done
    else
        shots+=("$name")
        while IFS= read -r v; do
            [ -n "$v" ] && shots+=("$name%$v")
        done < <(node -e "for (const v of JSON.parse(require('fs').readFileSync(process.argv[1])).variants ?? []) console.log(v)" "$out/models/$name.camera.json")
    fi
done
# A shot's model, pose flags and picture name.
shot_name() { local n=${1%@*}; echo "${n%%%*}"; }
shot_variant() { case $1 in *%*) echo "${1#*%}" ;; esac; }
shot_file() { echo "${1/\%/.}"; }
sky=$out/models/sky.hdr

echo "Sample Viewer: ${names[*]} at ${width}x${height}"
{
    echo "["
    sep=""
    for shot in "${shots[@]}"; do
        name=$(shot_name "$shot")
        pose=""
        case $shot in *@*) pose=",\"animation\":$animation,\"time\":${shot#*@}" ;; esac
        variant=$(shot_variant "$shot")
        [ -n "$variant" ] && pose="$pose,\"variant\":$(node -e 'console.log(JSON.stringify(process.argv[1]))' "$variant")"
        camera=$(node -e "console.log(JSON.parse(require('fs').readFileSync(process.argv[1])).index)" "$out/models/$name.camera.json")
        printf '%s{"model":"%s","camera":%s,"width":%s,"height":%s,"clearColor":[%s,%s,%s],"environment":"%s","useIBL":%s,"environmentIntensity":1,"environmentRotation":90%s,"out":"%s"}\n' \
            "$sep" "$out/models/$name.glb" "$camera" "$width" "$height" "${background[@]}" "$sky" \
            "$([ $environment = 1 ] && echo true || echo false)" "$pose" "$out/viewer/$(shot_file "$shot").png"
        sep=","
    done
    echo "]"
} > "$out/viewer/jobs.json"
CHROMIUM=$chromium node "$here/render.mjs" "$out/viewer/jobs.json"

echo "seamlit: $seamlit"
# The Sample Viewer draws no shadows: seamlit's are switched off to compare the shading.
lighting=(--lighting pbr --tone-mapping neutral --exposure 1 --shadows off)
if [ $environment = 1 ]; then
    # The Sample Viewer's environment rotation 90 puts the panorama's middle at +Z, as
    # seamlit's --environment-rotation 0 does (its V is seamlit's 90 - V).
    lighting+=(--ambient 0 --environment "$sky" --environment-intensity 1 --environment-rotation 0
        --background "$(awk "BEGIN { printf \"%.4f,%.4f,%.4f\", ${background[0]}/255, ${background[1]}/255, ${background[2]}/255 }")")
else
    lighting+=(--ambient 0 --environment none)
fi
for name in "${names[@]}"; do
    node -e "
        const c = JSON.parse(require('fs').readFileSync(process.argv[1]));
        const v = (a) => '[' + a.join(', ') + ']';
        console.log('[[model]]\npath = ' + JSON.stringify(process.argv[2]) + '\n\n[[camera]]\nname = \"compare\"\n' +
            'position = ' + v(c.position) + '\ntarget = ' + v(c.target) + '\nfov_deg = ' + c.fov_deg +
            '\nnear = ' + c.near + '\nfar = ' + c.far);
    " "$out/models/$name.camera.json" "$name.glb" > "$out/models/$name.toml"
done
for shot in "${shots[@]}"; do
    name=$(shot_name "$shot")
    pose=()
    case $shot in *@*) pose=(--animation "$animation" --time "${shot#*@}") ;; esac
    variant=$(shot_variant "$shot")
    [ -n "$variant" ] && pose+=(--variant "$variant")
    "$seamlit" render "$out/models/$name.toml" -o "$out/seamlit/$(shot_file "$shot").png" --size "$size" \
        --camera compare "${lighting[@]}" "${pose[@]}" > /dev/null
done

mode=$([ $environment = 1 ] && echo "punctual light + sky.hdr" || echo "punctual light only")
{
    echo "| model ($mode, ${width}x${height}) | mean FLIP |"
    echo "|---|---:|"
    for shot in "${shots[@]}"; do
        file=$(shot_file "$shot")
        flip=$("$bench" flip "$out/viewer/$file.png" "$out/seamlit/$file.png" --side-by-side "$out/side-by-side/$file.png")
        echo "| $file | $flip |"
    done
} | tee "$out/flip.md"
echo "pictures: $out/side-by-side/ (Sample Viewer | seamlit | FLIP error)"

//! Giving back at load what the pass-through writer never reads changes nothing it writes.

use std::path::{Path, PathBuf};

use seamlit_asset::files::Destination;
use seamlit_asset::{Asset, LoadOptions, SaveOptions};
use seamlit_mesh::FixOptions;

use super::{load, load_whole, parse};
use crate::source::GltfSource;

/// Every glTF and GLB file under `assets/` but the validator's corpus (which the io manifest,
/// `bench/io-identical.sh`, covers).
fn files() -> Vec<PathBuf> {
    fn walk(dir: &Path, found: &mut Vec<PathBuf>) {
        let mut entries: Vec<PathBuf> =
            std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
        entries.sort();
        for path in entries {
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            if path.is_dir() && name != "validator-corpus" {
                walk(&path, found);
            } else if name.ends_with(".glb") || name.ends_with(".gltf") {
                found.push(path);
            }
        }
    }
    let mut found = Vec::new();
    walk(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets"), &mut found);
    found
}

/// The bytes buffer 0 of a loaded asset holds.
fn held(asset: &Asset) -> usize {
    asset.document::<GltfSource>().map_or(0, |s| s.0.buffers.stored_bytes(0).len())
}

/// What `asset` saves as `name`, in memory: every file, in order.
fn saved(asset: &Asset, name: &str) -> Vec<(PathBuf, Vec<u8>)> {
    let mut to = Destination::memory();
    crate::save_to(asset, Path::new(name), &SaveOptions::default(), &mut to).unwrap();
    to.into_memory()
}

/// `asset` fixed with the default options (split vertices, new normals, tangents and indices).
fn fixed(mut asset: Asset) -> Asset {
    seamlit_mesh::fix_in_place(&mut asset.model, &FixOptions::default()).unwrap();
    asset
}

/// Every file of the assets, loaded with and without giving back, fixed and saved as `.glb`
/// and `.gltf`: the same bytes. Most files give something back.
#[test]
fn outputs_are_the_same_with_the_unread_bytes_given_back() {
    let (mut files_seen, mut given_back) = (0, 0);
    for file in files() {
        let options = LoadOptions::FIX;
        let (whole, lean) = match (load_whole(&file, &options), load(&file, &options)) {
            (Ok(whole), Ok(lean)) => (whole, lean),
            (whole, lean) => {
                assert_eq!(whole.is_ok(), lean.is_ok(), "{}", file.display());
                continue;
            }
        };
        files_seen += 1;
        if held(&lean) < held(&whole) {
            given_back += 1;
        }
        let (whole, lean) = (fixed(whole), fixed(lean));
        for name in ["out.glb", "out.gltf"] {
            assert!(saved(&whole, name) == saved(&lean, name), "{} as {name}", file.display());
        }
    }
    assert!(files_seen >= 40, "{files_seen} files");
    assert!(given_back >= 30, "{given_back} of {files_seen} files gave bytes back");
}

/// A GLB of one quad whose POSITION, NORMAL, TANGENT, TEXCOORD_0 and indices each have a
/// buffer view of their own, the positions' with `padding` bytes before and after them that
/// no accessor reads.
fn quad_glb(padding: [usize; 2]) -> Vec<u8> {
    let floats = |values: &[f32]| values.iter().flat_map(|v| v.to_le_bytes()).collect::<Vec<u8>>();
    let positions = floats(&[0., 0., 0., 1., 0., 0., 1., 1., 0., 0., 1., 0.]);
    let views: [Vec<u8>; 5] = [
        [vec![0xAB; padding[0]], positions, vec![0xCD; padding[1]]].concat(),
        floats(&[0., 0., 1.].repeat(4)),
        floats(&[1., 0., 0., 1.].repeat(4)),
        floats(&[0., 1., 1., 1., 1., 0., 0., 0.]),
        [0u16, 1, 2, 0, 2, 3].iter().flat_map(|i| i.to_le_bytes()).collect(),
    ];
    let mut bin = Vec::new();
    let mut view_json = Vec::new();
    for view in &views {
        view_json.push(
            serde_json::json!({ "buffer": 0, "byteOffset": bin.len(), "byteLength": view.len() }),
        );
        bin.extend_from_slice(view);
        bin.resize(bin.len().next_multiple_of(4), 0);
    }
    let accessor = |view: usize, kind: &str, component: u32, count: usize| serde_json::json!({ "bufferView": view, "componentType": component, "count": count, "type": kind });
    let mut position = accessor(0, "VEC3", 5126, 4);
    if padding[0] > 0 {
        position["byteOffset"] = serde_json::json!(padding[0]);
    }
    position["min"] = serde_json::json!([0., 0., 0.]);
    position["max"] = serde_json::json!([1., 1., 0.]);
    let json = serde_json::json!({
        "asset": { "version": "2.0" },
        "scene": 0, "scenes": [{ "nodes": [0] }], "nodes": [{ "mesh": 0 }],
        "meshes": [{ "primitives": [{
            "attributes": { "POSITION": 0, "NORMAL": 1, "TANGENT": 2, "TEXCOORD_0": 3 },
            "indices": 4,
        }] }],
        "accessors": [position, accessor(1, "VEC3", 5126, 4), accessor(2, "VEC4", 5126, 4),
            accessor(3, "VEC2", 5126, 4), accessor(4, "SCALAR", 5123, 6)],
        "bufferViews": view_json,
        "buffers": [{ "byteLength": bin.len() }],
    });
    seamlit_testkit::glb(&json, &bin)
}

/// `quad_glb` loaded from a file.
fn load_quad(keep_all: bool, padding: [usize; 2]) -> Asset {
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("seamlit-give-back-{}-{call}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("quad.glb");
    std::fs::write(&file, quad_glb(padding)).unwrap();
    let options = LoadOptions::FIX;
    let asset = if keep_all { load_whole(&file, &options) } else { load(&file, &options) };
    std::fs::remove_dir_all(&dir).unwrap();
    asset.unwrap()
}

/// Positions or UVs changed after a load that gave their bytes back (their views are
/// written from the model) are not written among the input's other data by the
/// pass-through: the generic writer writes the model, and the save says why.
#[test]
fn changed_positions_or_uvs_are_written_by_the_generic_writer() {
    for (what, change) in [
        ("positions", (|a: &mut Asset| a.model.objects[0].positions[2].z = 0.5) as fn(&mut Asset)),
        ("texture coordinates", |a: &mut Asset| {
            a.model.objects[0].uvs.as_mut().unwrap()[1].x = 0.25;
        }),
    ] {
        let mut asset = load_quad(false, [0, 0]);
        change(&mut asset);
        let mut to = Destination::memory();
        let warnings =
            crate::save_to(&asset, Path::new("out.glb"), &SaveOptions::default(), &mut to).unwrap();
        let generic =
            warnings.iter().any(|w| w.contains("generic glTF writer") && w.contains(what));
        assert!(generic, "{what}: {warnings:?}");
        let back = parse(&to.into_memory()[0].1, Path::new("out.glb"), &LoadOptions::FIX).unwrap();
        assert_eq!(back.model.objects[0].positions, asset.model.objects[0].positions);
        assert_eq!(back.model.objects[0].uvs, asset.model.objects[0].uvs);
    }
    // Unchanged, or loaded whole: the pass-through, which writes the input's positions.
    for asset in [load_quad(false, [0, 0]), load_quad(true, [0, 0])] {
        let mut to = Destination::memory();
        let warnings =
            crate::save_to(&asset, Path::new("out.glb"), &SaveOptions::default(), &mut to).unwrap();
        assert!(warnings.iter().all(|w| !w.contains("generic")), "{warnings:?}");
    }
}

/// Where the output keeps a view whose bytes were given back, unused (the model lost its
/// tangents, so the new views take fewer places than the old ones held), its bytes are zeros, and
/// the file reads back as the model it was written from.
#[test]
fn a_view_left_unused_is_written_as_zeros() {
    let options = LoadOptions::FIX;
    let without_tangents = |mut asset: Asset| {
        asset.model.objects.iter_mut().for_each(|o| o.tangents = None);
        asset
    };
    let lean = without_tangents(load_quad(false, [0, 0]));
    let whole = without_tangents(load_quad(true, [0, 0]));
    assert_eq!(held(&lean), 0, "every view given back");
    assert!(held(&whole) > 0);
    let (lean_out, whole_out) = (&saved(&lean, "out.glb")[0].1, &saved(&whole, "out.glb")[0].1);
    assert_eq!(lean_out.len(), whole_out.len());
    let differing: Vec<usize> =
        (0..lean_out.len()).filter(|&i| lean_out[i] != whole_out[i]).collect();
    // Three views freed (normals, tangents, indices), two new (normals, indices): pruning gives
    // the first two places away and keeps the old indices' view, unused; of its bytes
    // (0, 1, 2, 0, 2, 3 as u16) four are not zero.
    assert_eq!(differing.len(), 4, "bytes that differ");
    assert!(differing.iter().all(|&i| lean_out[i] == 0), "only zeros where bytes were given back");
    let back = parse(lean_out, Path::new("out.glb"), &options).unwrap();
    assert_eq!(back.model.objects.len(), lean.model.objects.len());
    for (read, written) in back.model.objects.iter().zip(&lean.model.objects) {
        assert_eq!(read.positions, written.positions);
        assert_eq!(read.normals, written.normals);
        assert_eq!(read.uvs, written.uvs);
        assert_eq!(read.triangles, written.triangles);
        assert_eq!(read.tangents, None);
    }
}

/// A view that the positions do not fill (bytes before or after them that no accessor reads)
/// is kept as read: its bytes are written as they were.
#[test]
fn a_view_the_positions_do_not_fill_is_kept() {
    for padding in [[4, 0], [0, 4], [8, 12]] {
        let (lean, whole) = (load_quad(false, padding), load_quad(true, padding));
        assert_eq!(held(&lean), 48 + padding[0] + padding[1], "{padding:?}: the positions' view");
        assert!(saved(&lean, "out.glb") == saved(&whole, "out.glb"), "{padding:?}");
    }
}

/// A buffer that would give back less than a quarter of itself keeps all of it (giving back
/// moves the bytes kept): NormalTangentTest.glb, two embedded PNGs beside a little geometry.
/// The teapot GLB of the same test folder gives back its geometry.
#[test]
fn a_buffer_mostly_kept_is_kept_whole() {
    let models = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/models");
    let file = models.join("NormalTangentTest.glb");
    let (lean, whole) =
        (load(&file, &LoadOptions::FIX).unwrap(), load_whole(&file, &LoadOptions::FIX).unwrap());
    assert_eq!(held(&lean), held(&whole));
    let file = models.join("compressed/teapot_noq.glb");
    let (lean, whole) =
        (load(&file, &LoadOptions::FIX).unwrap(), load_whole(&file, &LoadOptions::FIX).unwrap());
    assert!(held(&lean) * 4 < held(&whole), "{} of {}", held(&lean), held(&whole));
}

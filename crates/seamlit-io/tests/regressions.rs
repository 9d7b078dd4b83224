//! Every file under tests/regressions/ (hostile inputs made by hand, and inputs the fuzz
//! targets in fuzz/ found) loads without a panic, either successfully or with an error of one
//! line that names the file (or, for a side file such as an `.mtl`, the file's folder named
//! after the model). Listed inputs also state what the error must say. Side files live in
//! subfolders, which are not loaded themselves.

use std::path::{Path, PathBuf};

use seamlit_io::LoadOptions;

const DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/regressions");

/// What the error of a hand-made input must contain (`None`: it must load).
const EXPECTED: &[(&str, Option<&str>)] = &[
    ("glb_chunk_length_lies.glb", Some("glb_chunk_length_lies.glb")),
    ("glb_header_length_lies.glb", Some("glb_header_length_lies.glb")),
    ("glb_truncated_header.glb", Some("glb_truncated_header.glb")),
    ("gltf_accessor_count_4e9.gltf", Some("accessor 0")),
    ("gltf_accessor_offset_near_u64_max.gltf", Some("accessor 0")),
    // Issue 32: the gltf crate unwrapped a channel's target node and path unchecked. The
    // channel that cannot be played is skipped with a warning; the model loads.
    ("gltf_animation_channel_node_missing.gltf", None),
    ("gltf_animation_channel_pointer_path_with_node.gltf", None),
    // Found by tests/mutated_gltf.rs (issue 32): the gltf crate unwrapped the type of an
    // animation's accessor, which the leniency for unused accessors had let through.
    ("gltf_animation_input_type_invalid.gltf", Some("accessors[0].type")),
    ("gltf_buffer_length_u64_max.gltf", Some("buffer 0")),
    ("gltf_buffer_uri_escapes.gltf", Some("leaves the model's folder")),
    ("gltf_huge_stride.gltf", Some("bufferViews[0]")),
    // Found by the `gltf` fuzz target: gltf's Image::source unwrapped a missing uri.
    ("gltf_image_without_uri.gltf", Some("images[0]: an image needs a uri or a bufferView")),
    ("gltf_image_view_without_mime_type.gltf", Some("images[0]: an image in a bufferView needs")),
    // Found by the `gltf` fuzz target: gltf's reader computed `count - 1` for count 0.
    ("gltf_index_accessor_count_0.gltf", Some("accessor 2: indices has count 0")),
    // Issue 32: the gltf crate's `read_morph_targets` read a target's NORMAL accessor, which
    // seamlit does not read or check (count 0: `count - 1`).
    ("gltf_morph_target_normal_count_0.gltf", None),
    ("gltf_node_cycle.gltf", Some("nodes[0]")),
    ("gltf_node_is_its_own_child.gltf", Some("nodes[0]")),
    // Found by the `gltf` fuzz target: gltf-json's validation indexed the accessors unchecked.
    ("gltf_position_accessor_missing.gltf", Some("meshes[0].primitives[0].attributes.POSITION")),
    ("gltf_scene_lists_a_node_twice.gltf", Some("nodes[0]")),
    ("gltf_scene_node_out_of_range.gltf", Some("scenes[0]")),
    ("gltf_sparse_without_view_declares_1e8_positions.gltf", Some("without a buffer view")),
    // An oversized texture is not decoded: a warning, and the model loads.
    ("gltf_texture_declares_100000x100000.gltf", None),
    ("gltf_view_offset_near_u64_max.gltf", Some("bufferViews[0]")),
    // Found by tests/mutated_gltf.rs (issue 32): a byteStride below the element's size made
    // the gltf crate's reader assert.
    ("gltf_view_stride_below_element.gltf", Some("bufferViews[0] has byteStride 4, less than")),
    ("newell_patch_count_u64_max.bpt", Some("newell_patch_count_u64_max.bpt:1:")),
    ("newell_point_count_huge.bpt", Some("newell_point_count_huge.bpt:3:")),
    ("obj_face_index_huge.obj", Some("obj_face_index_huge.obj:4:")),
    ("obj_face_index_negative_huge.obj", Some("obj_face_index_negative_huge.obj:4:")),
    // Found by the `obj` fuzz target: tobj panicked on a colour of two numbers. Since issue
    // 27 such a statement is a warning (its material keeps the default), never an error.
    ("obj_mtl_colour_with_two_numbers.obj", None),
    ("obj_mtllib_escapes.obj", Some("leaves the model's folder")),
    ("obj_only_statements_no_values.obj", Some("obj_only_statements_no_values.obj:1:")),
    // Found by the `usd` fuzz target: a corrupted usda whose xformOpOrder token runs on to the
    // end of the file; looking the op up by that name sent openusd into a loop.
    // Found by the `usd` fuzz target (issue 33, run 5): metadata arrays nested 48 deep; each
    // level of openusd's parser escaped the one inside it again (2^48 bytes, for ever).
    ("usd_metadata_arrays_nested_48_deep.usda", Some("an array of arrays is not a metadata value")),
    // Found by the `usd` fuzz target: openusd's text parser recurses a level a bracket, and
    // 20,000 nested prims overflowed the stack (3,000 took over a minute). Refused above 256.
    ("usd_prims_nested_300_deep.usda", Some("nested 300 levels deep")),
    // Found by the `usd` fuzz target: a .usdc count past the end of the file, which unpatched
    // openusd 0.6 allocated (848 TB) and aborted on; refused by vendor/openusd's bounds.
    ("usd_usdc_count_past_the_file.usdc", Some("Unable to read vec")),
    // Found by the `usd` fuzz target (issue 33, run 4): a corrupted .usdc whose child-name
    // list holds a name that is not an identifier; openusd's traversal walked for ever. The
    // fork skips such children; the stage loads.
    ("usd_usdc_prim_child_not_a_name.usdc", None),
    // Found by reading after a device fuzz run's unsaved SIGSEGV (fuzz/README.md): a .usdc
    // of prims nested 2,000 deep, 659 bytes, kept composition busy for over a minute (1,000:
    // 7 s; the time grows with the cube of the depth). The fork refuses paths past 256 levels.
    ("usd_usdc_prims_nested_300_deep.usdc", Some("nested deeper than 256 levels")),
    ("usd_xform_op_name_runs_to_the_end.usda", Some("not a property name")),
];

fn inputs() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(DIR)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    files
}

fn name(path: &Path) -> String {
    path.file_name().unwrap().to_string_lossy().into_owned()
}

#[test]
fn every_regression_input_loads_or_fails_cleanly() {
    let options = LoadOptions::DEFAULT;
    let mut problems = Vec::new();
    for path in inputs() {
        let file = name(&path);
        let result = std::panic::catch_unwind(|| seamlit_io::load(&path, &options));
        let expected = EXPECTED.iter().find(|(f, _)| *f == file).map(|(_, e)| *e);
        match (result, expected) {
            (Err(_), _) => problems.push(format!("{file}: panicked")),
            (Ok(Ok(_)), None | Some(None)) => {}
            (Ok(Ok(_)), Some(Some(want))) => {
                problems.push(format!("{file}: loaded, expected an error with {want:?}"));
            }
            (Ok(Err(err)), expected) => {
                let message = err.to_string();
                eprintln!("{message}");
                let stem = path.file_stem().unwrap().to_string_lossy();
                if message.contains('\n') || !message.contains(&*stem) {
                    problems.push(format!("{file}: not one line naming the file: {message:?}"));
                }
                match expected {
                    Some(None) => problems.push(format!("{file}: expected to load: {message}")),
                    Some(Some(want)) if !message.contains(want) => {
                        problems.push(format!("{file}: expected {want:?} in {message:?}"));
                    }
                    _ => {}
                }
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn every_hand_made_input_is_present() {
    let files: Vec<String> = inputs().iter().map(|p| name(p)).collect();
    for (file, _) in EXPECTED {
        assert!(files.iter().any(|f| f == file), "{file} is missing from {DIR}");
    }
}

#[test]
fn an_oversized_texture_is_not_decoded_and_gets_a_warning() {
    let path = Path::new(DIR).join("gltf_texture_declares_100000x100000.gltf");
    let asset = seamlit_io::load(&path, &LoadOptions::DEFAULT).unwrap();
    assert_eq!(asset.textures.len(), 1);
    assert!(asset.textures[0].image.is_none());
    assert!(
        asset.warnings.iter().any(|w| w.contains("cannot be decoded") && w.contains("100000")),
        "{:?}",
        asset.warnings
    );
}

/// Issue 32: of two channels, the one whose target node does not exist, or whose path is
/// KHR_animation_pointer's `"pointer"` on a node, is skipped and named in a warning; the
/// other plays.
#[test]
fn a_channel_that_cannot_be_played_is_skipped_and_named() {
    for (file, why) in [
        ("gltf_animation_channel_node_missing.gltf", "channel 1: its target node 7 does not exist"),
        (
            "gltf_animation_channel_pointer_path_with_node.gltf",
            "channel 1: its target path is not translation, rotation, scale or weights",
        ),
    ] {
        let asset = seamlit_io::load(&Path::new(DIR).join(file), &LoadOptions::DEFAULT).unwrap();
        assert_eq!(asset.animations[0].channels.len(), 1, "{file}");
        assert!(
            asset.warnings.iter().any(|w| w.contains("animations[0]") && w.contains(why)),
            "{file}: {:?}",
            asset.warnings
        );
    }
}

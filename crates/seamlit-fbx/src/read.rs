//! `fbx::load`: the file (within the size limit) streamed to ufbx (or its bytes given), opened
//! with glTF's conventions (`scene.rs`), then its nodes, meshes and materials converted.

mod animation;
mod material;
mod mesh;
mod nodes;
mod scene;
mod skin;
// The one module of seamlit with `unsafe`: ufbx's thread pool is a C interface.
#[allow(unsafe_code)]
mod threads;

use std::path::Path;

use seamlit_mesh::{Model, VAxis};

use seamlit_asset::Asset;
use seamlit_asset::LoadOptions;
use seamlit_asset::error::IoError;
use seamlit_asset::files::Files;

/// Reads an FBX file (binary or ASCII) and the textures it embeds or names. A file without
/// a triangle loads as an empty model here; `seamlit_io::load` refuses it.
///
/// What comes in, in glTF's conventions (+Y up, metres, right-handed, counter-clockwise
/// front faces): the node tree with its names ([`Asset::nodes`], ufbx's root left out), one
/// object per mesh part per material (named after its node) with positions, the file's
/// normals, two UV sets (`uvs`, `uvs1`), the first colour set, and tangents where the file
/// has tangents and bitangents for the first UV set; each object's transform is its node's
/// geometry-to-world matrix (pivots and geometry transforms resolved by ufbx). Materials are
/// ufbx's metallic-roughness reading of the file's (base colour, normal map, roughness,
/// metallic, emission, opacity), textures embedded or by a path inside the model's folder.
/// UVs run up ([`VAxis::Up`]), as FBX's do.
///
/// # Errors
///
/// [`IoError::Io`] / [`IoError::TooLarge`] for the file itself; [`IoError::Fbx`] for a file
/// ufbx refuses or finds truncated, or a mesh with values that are not finite;
/// [`IoError::TooManyElements`] past `options.max_elements` or
/// `options.max_model_triangles`; the texture errors of [`seamlit_asset::LoadOptions::strict`].
pub fn load(path: &Path, options: &LoadOptions) -> Result<Asset, IoError> {
    seamlit_asset::files::check_size(path, options)?;
    // A file on disk is streamed to ufbx, which keeps what it needs of it (the compressed
    // arrays until they are inflated): the whole file is never held beside the scene (the 26
    // MB Blender FBX of BENCHMARKS.md: 27 MiB less at the process's peak). A stream
    // ufbx refuses is read again whole, for the error's words: cut short, a stream can end in
    // its "Failed to load" where the same bytes in memory give "Truncated file".
    if options.files == Files::Disk {
        let file = std::fs::File::open(path).map_err(|e| IoError::io(path, e))?;
        if file.metadata().is_ok_and(|m| m.is_file())
            && let Ok(scene) = scene::open(scene::Input::File(file), path)
        {
            return convert(&scene, path, options);
        }
    }
    let bytes = seamlit_asset::files::read_bytes(path, options)?;
    parse(&bytes, path, options)
}

/// Reads FBX bytes as [`load`] reads a file; `path` names the file in errors, and its folder
/// is where textures that are not embedded are looked for.
///
/// # Errors
///
/// As [`load`], but for the errors of reading the file itself.
pub fn parse(bytes: &[u8], path: &Path, options: &LoadOptions) -> Result<Asset, IoError> {
    let scene = scene::open(scene::Input::Bytes(bytes), path)?;
    convert(&scene, path, options)
}

/// The asset of a scene ufbx opened from `path`.
fn convert(scene: &ufbx::SceneRoot, path: &Path, options: &LoadOptions) -> Result<Asset, IoError> {
    let mut warnings = Vec::new();
    let mut tree = nodes::tree(scene);
    let (materials, textures) = material::convert(scene, path, &mut warnings);
    let (objects, skins) = mesh::objects(scene, &mut tree, path, options)?;
    let node_of = |n: &ufbx::Node| tree.index.get(n.element.typed_id as usize).copied().flatten();
    let animations = animation::animations(scene, node_of, path, &mut warnings);
    let mut asset = Asset {
        model: Model { objects, v_axis: VAxis::Up },
        materials,
        textures,
        nodes: tree.nodes,
        skins,
        animations,
        source: Some(path.to_path_buf()),
        ..Asset::default()
    };
    warnings.extend(seamlit_asset::texture::decode_all(&mut asset.textures, path, options)?);
    asset.warnings = warnings;
    Ok(asset)
}

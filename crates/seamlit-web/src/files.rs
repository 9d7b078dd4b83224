//! The page's files: a model and its side files as the user dropped them (a `.gltf` with its
//! `.bin` and images, an OBJ with its MTL and textures), read from memory; and the fixed
//! model as the one file the page offers to download: what `seamlit fix MODEL -o OUT` writes
//! (GLB for glTF and GLB, VRM for VRM, the OBJ with its material libraries and textures, a
//! USDZ package for a USDZ), several files as one zip of them under the names the command line
//! gives them.
//!
//! Plain Rust, tested on the host against the command line's library calls.

use std::io::Write as _;
use std::path::{Path, PathBuf};

use seamlit_io::files::{Destination, Files, MemoryFiles};
use seamlit_io::{Asset, LoadOptions, SaveOptions};

/// The extensions of model files the page reads, in the order it picks the model among
/// files dropped together.
pub const MODEL_EXTENSIONS: [&str; 5] = ["glb", "vrm", "gltf", "obj", "usdz"];

/// A stage of loose layers: the page packs USD only from a package.
const LOOSE_STAGE: &str = "the page reads USD stages packed as .usdz; a stage of loose layers \
                           needs the command line (`seamlit fix`)";

/// Extensions of models the page names but does not read, with why.
const NOT_READ: [(&str, &str); 4] = [
    (
        "fbx",
        "FBX needs the command line (`seamlit fix`): its reader is a C library the page does \
         not build",
    ),
    ("usda", LOOSE_STAGE),
    ("usdc", LOOSE_STAGE),
    ("usd", LOOSE_STAGE),
];

/// The lower-case extension of `name`.
fn extension(name: &str) -> String {
    Path::new(name)
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default()
}

/// The model among files dropped together (`names`, paths relative to what was dropped):
/// the first by [`MODEL_EXTENSIONS`]' order, then the shallowest path, then by name; else a
/// file the page names but does not read; else the first.
#[must_use]
pub fn pick_model(names: &[String]) -> Option<&str> {
    let depth = |n: &&String| n.matches(['/', '\\']).count();
    let rank = |n: &&String| MODEL_EXTENSIONS.iter().position(|e| *e == extension(n));
    let best = names
        .iter()
        .filter(|n| rank(n).is_some())
        .min_by(|a, b| (rank(a), depth(a), a.as_str()).cmp(&(rank(b), depth(b), b.as_str())));
    let named = || names.iter().find(|n| NOT_READ.iter().any(|(e, _)| *e == extension(n)));
    best.or_else(named).or_else(|| names.first()).map(String::as_str)
}

/// Reads the model `model` (one of `files`' paths; its side files among them), textures
/// decoded for drawing.
///
/// # Errors
///
/// One line naming the file and the reason: a format the page does not read, a file the
/// reader refuses (a missing buffer names the file it looked for), a model without
/// triangles.
pub fn read(model: &str, files: Vec<(String, Vec<u8>)>) -> Result<Asset, String> {
    let refuse = |why: &str| format!("{model}: {why}");
    let format = extension(model);
    if let Some((_, why)) = NOT_READ.iter().find(|(e, _)| *e == format) {
        return Err(refuse(why));
    }
    if !MODEL_EXTENSIONS.contains(&format.as_str()) {
        return Err(refuse("not a model file seamlit reads (GLB, VRM, glTF, OBJ, USDZ)"));
    }
    let files = MemoryFiles::new(files.into_iter().map(|(n, b)| (PathBuf::from(n), b)));
    let path = Path::new(model);
    let bytes = files.get(path).ok_or_else(|| refuse("not among the files given"))?.clone();
    let options = LoadOptions { files: Files::Memory(files), ..LoadOptions::default() };
    let asset = match format.as_str() {
        "obj" => seamlit_io::obj::parse(&bytes, path, &options),
        // Read from the set, as the command line reads it from disk.
        "usdz" => seamlit_io::usd::load(path, &options),
        _ => seamlit_io::gltf::parse(&bytes, path, &options),
    }
    .map_err(|e| e.to_string())?;
    if asset.model.triangle_count() == 0 {
        return Err(refuse("the file holds no triangles"));
    }
    Ok(asset)
}

/// The fixed model as the page offers it: one file, its name and bytes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Download {
    /// `STEM.glb`, `STEM.vrm`, `STEM.usdz`, or `STEM.zip` for several files.
    pub name: String,
    /// The file's bytes.
    pub bytes: Vec<u8>,
    /// Where the command line writes the file (`STEM.glb`, `STEM.vrm`, `STEM.obj`, `STEM.usdz`): the
    /// report names it.
    pub output: PathBuf,
}

/// Writes `fixed`, the model read from `model`, into memory as `seamlit fix MODEL -o
/// STEM.EXT` writes it (EXT: `glb` for glTF and GLB, `vrm` for VRM, `obj` for OBJ, `usdz`
/// for USDZ), the files as one [`Download`]; returns the writer's warnings too.
///
/// # Errors
///
/// The writer's error, one line.
pub fn write(model: &str, fixed: &Asset) -> Result<(Download, Vec<String>), String> {
    let path = Path::new(model);
    let stem = path.file_stem().map_or_else(|| "model".into(), |s| s.to_string_lossy());
    let format = extension(model);
    let out_extension = match format.as_str() {
        "obj" | "usdz" => format.as_str(),
        _ => seamlit_io::folder::output_extension(path, "glb"),
    };
    let output = PathBuf::from(format!("{stem}.{out_extension}"));
    let mut memory = Destination::memory();
    let options = SaveOptions::default();
    let warnings = match out_extension {
        "obj" => seamlit_io::obj::save_to(fixed, &output, &options, &mut memory),
        "usdz" => seamlit_io::usd::save_package_to(fixed, &output, &mut memory),
        _ => seamlit_io::gltf::save_to(fixed, &output, &options, &mut memory),
    }
    .map_err(|e| e.to_string())?;
    let mut written = memory.into_memory();
    let download = if written.len() == 1 {
        let (name, bytes) = written.remove(0);
        Download { name: name.display().to_string(), bytes, output }
    } else {
        let bytes = zip(&written).map_err(|e| format!("{model}: packing the download: {e}"))?;
        Download { name: format!("{stem}.zip"), bytes, output }
    };
    Ok((download, warnings))
}

/// A zip of `files` (stored, not compressed: model files compress poorly next to the time it
/// takes in a page), in the order written, names with `/`, no timestamps (the zip format's
/// earliest), so that the same files give the same bytes.
fn zip(files: &[(PathBuf, Vec<u8>)]) -> zip::result::ZipResult<Vec<u8>> {
    let mut archive = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let options = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Stored)
        .last_modified_time(zip::DateTime::default());
    for (name, bytes) in files {
        let name: Vec<String> =
            name.components().map(|c| c.as_os_str().to_string_lossy().into_owned()).collect();
        archive.start_file(name.join("/"), options)?;
        archive.write_all(bytes)?;
    }
    Ok(archive.finish()?.into_inner())
}

#[cfg(test)]
mod tests {
    use super::pick_model;

    fn names(list: &[&str]) -> Vec<String> {
        list.iter().map(|s| (*s).to_owned()).collect()
    }

    #[test]
    fn the_model_is_picked_among_its_side_files() {
        assert_eq!(pick_model(&names(&["a.bin", "tex/b.png", "kit/A.gltf"])), Some("kit/A.gltf"));
        assert_eq!(pick_model(&names(&["box.mtl", "box.obj", "t.png"])), Some("box.obj"));
        assert_eq!(pick_model(&names(&["sub/b.glb", "a.glb"])), Some("a.glb"));
        assert_eq!(pick_model(&names(&["x.gltf", "y.glb"])), Some("y.glb"));
        assert_eq!(pick_model(&names(&["m.fbx", "t.png"])), Some("m.fbx"));
        assert_eq!(pick_model(&names(&["a.usda", "b.usdz"])), Some("b.usdz"));
        assert_eq!(pick_model(&names(&["notes.txt"])), Some("notes.txt"));
        assert_eq!(pick_model(&[]), None);
    }
}

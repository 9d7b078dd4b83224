//! The `.usdz` output: one self-contained package, as the USDZ specification and Apple's
//! tools expect. Its first file, the package's root layer, is the override layer `write.rs`
//! makes (the fixed normals over the input); after it come the input's files, in the folder
//! layout they have on disk, so that every relative asset path still resolves inside the
//! package:
//!
//! - from a `.usdz` input, every file of the input package, under the same names (the
//!   override layer sublayers the input's root layer, its first file);
//! - from a `.usda`/`.usdc` input, the root layer and every file it uses, found by walking
//!   each layer's fields as Pixar's `UsdUtilsComputeAllDependencies` does: sublayers,
//!   references and payloads (in every variant, selected or not: a package keeps the variant
//!   sets working), and every asset-valued attribute or metadata (textures, clips), layers
//!   among them walked in turn. The names are the files' paths below the deepest folder that
//!   holds them all.
//!
//! Entries are stored uncompressed with their data 64-byte aligned (openusd's
//! `usdz::ArchiveWriter`), the package is assembled in memory and written to a temporary file
//! beside the output, then renamed.

use std::collections::{BTreeSet, HashSet, VecDeque};
use std::io::{Cursor, Read};
use std::path::{Component, Path, PathBuf};

use openusd::{sdf, usda, usdc, usdz};

use crate::source::UsdSource;
use seamlit_asset::Asset;
use seamlit_asset::error::IoError;
use seamlit_asset::error::usd::UsdOutput;
use seamlit_asset::files::{Destination, Files};

/// The input's files to put in the package, in order: `(name in the package, bytes)`; the
/// first is the input's root layer.
type Entries = Vec<(String, Vec<u8>)>;

/// The most bytes the files of a package may hold together (the default size limit of a
/// model file, `LoadOptions::max_file_bytes`).
const MAX_PACKAGE_BYTES: u64 = 4 << 30;

/// Writes `asset` (loaded from a USD stage) as a `.usdz` package at `path`. Returns the
/// warnings: meshes whose normals are not written, files the input names that are not in
/// the package, and why.
///
/// # Errors
///
/// Those of [`super::write::save`]; [`IoError::UsdOutput`] with [`UsdOutput::Package`] when
/// a file of the input cannot be read or put in a package.
pub(crate) fn save(
    asset: &Asset,
    path: &Path,
    to: &mut Destination,
) -> Result<Vec<String>, IoError> {
    let layer = super::write::prepare(asset, path)?;
    let mut warnings = layer.warnings.clone();
    let refuse = |reason: String| IoError::UsdOutput {
        path: path.to_path_buf(),
        kind: UsdOutput::Package { reason },
    };
    let input = &layer.input;
    let is_package =
        input.extension().is_some_and(|e| e.to_string_lossy().eq_ignore_ascii_case("usdz"));
    let source = asset.document::<UsdSource>();
    let files = source.map_or(&Files::Disk, |s| &s.files);
    let entries = super::read::guarded(input, || match files {
        Files::Disk if is_package => {
            let file = std::fs::File::open(input).map_err(|e| refuse(e.to_string()))?;
            package_entries(file).map_err(refuse)
        }
        Files::Disk => {
            let roots = source.map_or(&[][..], |s| &s.asset_roots[..]);
            dependencies(input, roots, &mut warnings).map_err(refuse)
        }
        Files::Memory(_) if is_package => {
            let bytes = files.read(input).map_err(|e| refuse(e.to_string()))?;
            package_entries(Cursor::new(bytes)).map_err(refuse)
        }
        Files::Memory(_) => Err(refuse(
            "a stage read from memory is packed only from a .usdz (its layers are not walked)"
                .to_owned(),
        )),
    })?;
    let root = &entries.first().ok_or_else(|| refuse("the input is empty".to_owned()))?.0;
    let name = layer_name(path, &entries);
    let text = layer.text(&format!("./{root}"));
    let mut archive = usdz::ArchiveWriter::new(Cursor::new(Vec::new()));
    archive.add_layer(&name, text.as_bytes()).map_err(|e| refuse(format!("{e:#}")))?;
    for (entry, bytes) in &entries {
        archive.add_layer(entry, bytes).map_err(|e| refuse(format!("{e:#}")))?;
    }
    let bytes = archive.finish().map_err(|e| refuse(format!("{e:#}")))?.into_inner();
    to.write(path, &bytes)?;
    Ok(warnings)
}

/// The override layer's name in the package: the output's stem, `.usda`, made unique among
/// the input's files.
fn layer_name(output: &Path, entries: &Entries) -> String {
    let stem = output.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let stem = seamlit_asset::files::safe_name(&stem);
    let taken: HashSet<String> = entries.iter().map(|(n, _)| n.to_ascii_lowercase()).collect();
    (0..)
        .map(|k| if k == 0 { format!("{stem}.usda") } else { format!("{stem}_{k}.usda") })
        .find(|n| !taken.contains(&n.to_ascii_lowercase()))
        .unwrap_or_default()
}

/// Every file of the package `input` (a file or bytes), in its order (its root layer first).
fn package_entries(input: impl Read + std::io::Seek) -> Result<Entries, String> {
    let mut zip = zip::ZipArchive::new(input).map_err(|e| format!("not a package: {e}"))?;
    let mut entries = Vec::new();
    let mut total = 0u64;
    for i in 0..zip.len() {
        let mut entry = zip.by_index(i).map_err(|e| format!("file {i} of the package: {e}"))?;
        if entry.is_dir() {
            continue;
        }
        let name = entry.name().to_owned();
        total = total.saturating_add(entry.size());
        if total > MAX_PACKAGE_BYTES {
            return Err(format!("its files hold more than {MAX_PACKAGE_BYTES} bytes"));
        }
        let mut bytes = Vec::new();
        (&mut entry)
            .take(MAX_PACKAGE_BYTES)
            .read_to_end(&mut bytes)
            .map_err(|e| format!("{name} in the package: {e}"))?;
        entries.push((name, bytes));
    }
    Ok(entries)
}

/// The root layer at `input` and every file it uses, named by their paths below the
/// deepest folder that holds them all. Files outside the root layer's folder and
/// `asset_roots` (the folders the stage was read from, `--asset-root`) are left out with a
/// warning, as the reader leaves them unread.
fn dependencies(
    input: &Path,
    asset_roots: &[PathBuf],
    warnings: &mut Vec<String>,
) -> Result<Entries, String> {
    let root = input.canonicalize().map_err(|e| e.to_string())?;
    let folders = super::read::allowed_folders(&root, asset_roots);
    let mut files = vec![root.clone()];
    let mut seen: HashSet<PathBuf> = HashSet::from([root.clone()]);
    let mut queue = VecDeque::from([root]);
    while let Some(file) = queue.pop_front() {
        let Some(data) = layer_data(&file)? else { continue };
        let folder = file.parent().unwrap_or(Path::new("/")).to_path_buf();
        for asset in asset_paths(data.as_ref()) {
            // A file inside a package (`textures.usdz[red.png]`): the package goes in.
            let asset = asset.split('[').next().unwrap_or_default();
            if asset.is_empty() {
                continue;
            }
            let absolute = Path::new(asset).is_absolute();
            if asset.contains("://") || asset.starts_with('`') || asset.contains('<') || absolute {
                warnings.push(format!(
                    "{}: asset path @{asset}@ is not a relative file path: not put in the package",
                    file.display()
                ));
                continue;
            }
            if !packaged_kind(asset) {
                warnings.push(format!(
                    "{}: @{asset}@ is not a kind of file a package holds (layers, images, audio): not put in the package",
                    file.display()
                ));
                continue;
            }
            match folder.join(asset).canonicalize() {
                Ok(found) if !folders.iter().any(|f| found.starts_with(f)) => {
                    warnings.push(format!(
                        "{}: @{asset}@ lies outside the stage's folder (--asset-root DIR allows another folder): not put in the package",
                        file.display()
                    ));
                }
                Ok(found) if found.is_file() => {
                    if seen.insert(found.clone()) {
                        files.push(found.clone());
                        queue.push_back(found);
                    }
                }
                _ => warnings.push(format!(
                    "{}: @{asset}@ is not a file: not put in the package",
                    file.display()
                )),
            }
        }
    }
    let base = common_folder(&files);
    let mut total = 0u64;
    let mut entries = Vec::new();
    for file in &files {
        let bytes = std::fs::read(file).map_err(|e| format!("{}: {e}", file.display()))?;
        total = total.saturating_add(bytes.len() as u64);
        if total > MAX_PACKAGE_BYTES {
            return Err(format!("its files hold more than {MAX_PACKAGE_BYTES} bytes"));
        }
        let name = file
            .strip_prefix(&base)
            .unwrap_or(file)
            .components()
            .map(|c| c.as_os_str().to_string_lossy().into_owned())
            .collect::<Vec<_>>()
            .join("/");
        entries.push((name, bytes));
    }
    Ok(entries)
}

/// Whether `asset` names a kind of file the USDZ specification lets a package hold: layers,
/// packages, images and audio. Anything else a layer names (any file on the disk, wherever it
/// is) stays out of the package.
fn packaged_kind(asset: &str) -> bool {
    let extension = Path::new(asset).extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
    matches!(
        extension.as_deref(),
        Some(
            "usda"
                | "usdc"
                | "usd"
                | "usdz"
                | "png"
                | "jpg"
                | "jpeg"
                | "exr"
                | "avif"
                | "m4a"
                | "mp3"
                | "wav"
        )
    )
}

/// The layer at `file`, or `None` for a file that is not a text or binary layer (a texture,
/// a package).
fn layer_data(file: &Path) -> Result<Option<Box<dyn sdf::AbstractData>>, String> {
    let mut head = [0u8; 8];
    let n = std::fs::File::open(file).and_then(|mut f| f.read(&mut head)).unwrap_or(0);
    let error = |e: anyhow::Error| format!("{}: {e:#}", file.display());
    if head[..n].starts_with(b"PXR-USDC") {
        return usdc::read_file(file).map(Some).map_err(error);
    }
    if head[..n].starts_with(b"#usda") {
        super::read::check_text_nesting(file).map_err(|e| e.to_string())?;
        let data = usda::read_file(file).map_err(error)?;
        return Ok(Some(Box::new(data)));
    }
    Ok(None)
}

/// Every asset path a layer names: sublayers, references, payloads, asset values (in
/// defaults, time samples and dictionaries), in every spec, variants included.
fn asset_paths(data: &dyn sdf::AbstractData) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for spec in data.spec_paths() {
        for field in data.list_fields(&spec).unwrap_or_default() {
            if let Ok(Some(value)) = data.try_field(&spec, &field) {
                if let ("subLayers", sdf::Value::StringVec(layers)) =
                    (field.as_str(), value.as_ref())
                {
                    out.extend(layers.iter().cloned());
                }
                collect(value.as_ref(), &mut out);
            }
        }
    }
    out
}

fn collect(value: &sdf::Value, out: &mut BTreeSet<String>) {
    fn items<T: Default + Clone + PartialEq>(list: &sdf::ListOp<T>) -> impl Iterator<Item = &T> {
        [
            &list.explicit_items,
            &list.added_items,
            &list.prepended_items,
            &list.appended_items,
            &list.ordered_items,
        ]
        .into_iter()
        .flatten()
    }
    match value {
        sdf::Value::AssetPath(a) => {
            out.insert(a.authored_path.clone());
        }
        sdf::Value::AssetPathVec(list) => {
            out.extend(list.iter().map(|a| a.authored_path.clone()));
        }
        sdf::Value::ReferenceListOp(list) => {
            out.extend(items(list).map(|r| r.asset_path.clone()));
        }
        sdf::Value::PayloadListOp(list) => {
            out.extend(items(list).map(|p| p.asset_path.clone()));
        }
        sdf::Value::Payload(p) => {
            out.insert(p.asset_path.clone());
        }
        sdf::Value::Dictionary(d) => d.values().for_each(|v| collect(v, out)),
        sdf::Value::TimeSamples(samples) => samples.iter().for_each(|(_, v)| collect(v, out)),
        _ => {}
    }
}

/// The deepest folder holding every file of `files` (absolute paths).
fn common_folder(files: &[PathBuf]) -> PathBuf {
    let mut common: Vec<Component<'_>> = match files.first().and_then(|f| f.parent()) {
        Some(folder) => folder.components().collect(),
        None => return PathBuf::from("/"),
    };
    for file in files {
        let parent: Vec<Component<'_>> =
            file.parent().map(|p| p.components().collect()).unwrap_or_default();
        let same = common.iter().zip(&parent).take_while(|(a, b)| a == b).count();
        common.truncate(same);
    }
    common.iter().collect()
}

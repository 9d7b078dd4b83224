//! The stage opened by openusd, composed (every payload loaded), and what goes wrong there as
//! [`UsdKind`]s: a layer openusd cannot read, composition errors (a missing payload is a
//! warning, as USD itself treats it; every other one an error), and, as a last resort, a
//! panic inside openusd.

use std::panic::AssertUnwindSafe;
use std::path::Path;
use std::sync::{Arc, Mutex};

use glam::DMat4;
use openusd::{pcp, sdf, usd};

use super::memory::InMemory;
use super::nesting::{MAX_TEXT_NESTING, text_nesting};
use super::resolver::{Confined, Outside};
use seamlit_asset::LoadOptions;
use seamlit_asset::error::IoError;
use seamlit_asset::error::usd::UsdKind;
use seamlit_asset::files::Files;

/// A stage opened, with the layers its resolver refused (outside the stage's folders).
pub(super) struct Opened {
    pub stage: usd::Stage,
    refused: Arc<Mutex<Vec<Outside>>>,
}

/// Opens `path` as the root layer of a stage, through [`Confined`]: layers come only from the
/// root layer's folder and `options.asset_roots`, each within the size and nesting limits; or,
/// for files in memory ([`LoadOptions::files`]), through [`InMemory`] within the same limits.
/// openusd reads the root layer and its sublayers now and the targets of references and
/// payloads as prims are composed.
///
/// # Errors
///
/// [`IoError::Usd`] with [`UsdKind::Layer`] when the root layer or a sublayer cannot be read,
/// [`UsdKind::Outside`] when a sublayer lies outside the stage's folders.
pub(super) fn open(path: &Path, options: &LoadOptions) -> Result<Opened, IoError> {
    let Some(root) = path.to_str() else {
        return Err(layer_error(path, "the path is not UTF-8, which openusd needs".to_owned()));
    };
    // The root layer too is opened through the resolver, which checks its nesting.
    let refused = Arc::new(Mutex::new(Vec::new()));
    let opened = match &options.files {
        Files::Disk => {
            let roots = &options.asset_roots;
            let resolver = Confined::new(path, roots, options.max_file_bytes, Arc::clone(&refused));
            usd::Stage::builder().resolver(resolver).open(root)
        }
        Files::Memory(files) => {
            let resolver = InMemory::new(files.clone(), options.max_file_bytes);
            usd::Stage::builder().resolver(resolver).open(root)
        }
    };
    let opened =
        Opened { stage: opened.map_err(|e| layer_error(path, format!("{e:#}")))?, refused };
    // A sublayer refused is not an error openusd reports: the stage would compose without it.
    opened.check_refused(path)?;
    Ok(opened)
}

impl Opened {
    /// [`UsdKind::Outside`] for the first layer refused (by asset path), if any, with
    /// openusd's composition error about it (which names the prim of the arc) where there is
    /// one. Where several arcs name the layer, the first of their errors in text order:
    /// openusd lists them in an order that changes from run to run.
    fn check_refused(&self, path: &Path) -> Result<(), IoError> {
        let first = self
            .refused
            .lock()
            .ok()
            .and_then(|r| r.iter().min_by(|a, b| a.asset.cmp(&b.asset)).cloned());
        let Some(outside) = first else { return Ok(()) };
        let named = format!("@{}@", outside.asset);
        let arc = self.stage.composition_errors().into_iter().map(|e| e.to_string());
        let layer = arc.filter(|m| m.contains(&named)).min().unwrap_or_else(|| {
            format!("layer @{}@ ({})", outside.asset, outside.resolved.display())
        });
        let folder = path.parent().map(|p| p.display().to_string()).unwrap_or_default();
        let folder = if folder.is_empty() { ".".to_owned() } else { folder };
        let kind = UsdKind::Outside { layer, folder };
        Err(IoError::Usd { path: path.to_path_buf(), kind })
    }
}

/// Refuses a root layer in text form (`#usda`) nested deeper than [`MAX_TEXT_NESTING`]
/// before openusd parses it. Layers it references are parsed by openusd unchecked.
pub(crate) fn check_text_nesting(path: &Path) -> Result<(), IoError> {
    // Unreadable: openusd says why.
    let Ok(bytes) = std::fs::read(path) else { return Ok(()) };
    if !bytes.starts_with(b"#usda") {
        return Ok(());
    }
    let depth = text_nesting(&bytes);
    if depth > MAX_TEXT_NESTING {
        let message = format!(
            "brackets nested {depth} levels deep, more than the {MAX_TEXT_NESTING} seamlit reads"
        );
        return Err(layer_error(path, message));
    }
    Ok(())
}

/// A [`UsdKind::Layer`] error about the root layer.
fn layer_error(path: &Path, message: String) -> IoError {
    let kind = UsdKind::Layer { layer: path.display().to_string(), message };
    IoError::Usd { path: path.to_path_buf(), kind }
}

/// An openusd error met while reading `prim`, as [`UsdKind::Prim`].
pub(super) fn prim_error(path: &Path, prim: &sdf::Path, error: &anyhow::Error) -> IoError {
    let kind = UsdKind::Prim { prim: prim.as_str().to_owned(), message: format!("{error:#}") };
    IoError::Usd { path: path.to_path_buf(), kind }
}

/// Runs `work`, turning a panic inside it (openusd's, on bytes it does not expect) into
/// [`UsdKind::Panicked`]. A last resort: the tests feed cut and corrupted files to make sure
/// none gets here.
pub(crate) fn guarded<T>(
    path: &Path,
    work: impl FnOnce() -> Result<T, IoError>,
) -> Result<T, IoError> {
    // Nothing `work` touches outlives it: the stage it opens is dropped with the panic.
    std::panic::catch_unwind(AssertUnwindSafe(work)).unwrap_or_else(|payload| {
        let message = payload
            .downcast_ref::<&str>()
            .map(|s| (*s).to_owned())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "a panic".to_owned());
        // One line, whatever the panic said (an assertion's message has three).
        let message = message.split_whitespace().collect::<Vec<_>>().join(" ");
        Err(IoError::Usd { path: path.to_path_buf(), kind: UsdKind::Panicked { message } })
    })
}

/// The stage's composition errors so far: a payload whose layer is missing or unreadable is
/// a warning (the stage composes without it, as USD's own tools do); any other error fails.
///
/// # Errors
///
/// [`IoError::Usd`] with [`UsdKind::Composition`] for the first error that is not about a
/// payload.
pub(super) fn composition(
    opened: &Opened,
    path: &Path,
    warnings: &mut Vec<String>,
) -> Result<(), IoError> {
    for error in opened.stage.composition_errors() {
        let payload = matches!(
            &error,
            pcp::Error::UnresolvedLayer { arc: pcp::ArcType::Payload, .. }
                | pcp::Error::MalformedLayer { arc: pcp::ArcType::Payload, .. }
        );
        // A layer in a format openusd has no reader for (MaterialX's `.mtlx`, which Pixar's
        // USD reads through a plugin): Pixar's USD without that plugin warns and composes the
        // rest, and so does seamlit.
        let unread = match &error {
            pcp::Error::MalformedLayer { asset_path, .. } => unread_format(asset_path),
            _ => None,
        };
        let message = error.to_string();
        // A layer refused for where it lies is an error, a payload too.
        opened.check_refused(path)?;
        if let Some(extension) = unread {
            let line = format!(
                "{}: {message}: openusd reads no .{extension} layers; the stage composes without it",
                path.display()
            );
            if !warnings.contains(&line) {
                warnings.push(line);
            }
        } else if payload {
            let line = format!("{}: {message}: the stage composes without it", path.display());
            if !warnings.contains(&line) {
                warnings.push(line);
            }
        } else {
            let kind = UsdKind::Composition { message };
            return Err(IoError::Usd { path: path.to_path_buf(), kind });
        }
    }
    opened.check_refused(path)
}

/// The extension of `asset_path` (lower case) where it names a layer format openusd has no
/// reader for; `None` for its own formats (`.usda`, `.usdc`, `.usd`, `.usdz`, and a path inside
/// a package) and for a path without an extension.
fn unread_format(asset_path: &str) -> Option<String> {
    let file = asset_path.split('[').next().unwrap_or(asset_path);
    let extension = Path::new(file).extension()?.to_string_lossy().to_ascii_lowercase();
    (!matches!(extension.as_str(), "usda" | "usdc" | "usd" | "usdz")).then_some(extension)
}

/// The stage's `upAxis` as the rotation that turns it into +Y up: a quarter turn about X for
/// Z up (`(x, y, z)` to `(x, z, -y)`, what glTF exporters do), the identity for Y.
pub(super) fn up_axis(stage: &usd::Stage) -> Result<DMat4, anyhow::Error> {
    let up = stage.stage_metadata("upAxis")?.and_then(|v| match v {
        sdf::Value::Token(t) => Some(t.as_str().to_owned()),
        sdf::Value::String(s) => Some(s),
        _ => None,
    });
    Ok(match up.as_deref() {
        Some("Z") => DMat4::from_rotation_x(-std::f64::consts::FRAC_PI_2),
        _ => DMat4::IDENTITY,
    })
}

/// The stage metadata a layer over the stage repeats, as `(key, usda value)`, where the root
/// layer authors them: the scalars below, and `customLayerData` where it holds only
/// strings, tokens, numbers, booleans and dictionaries of them.
pub(super) fn metadata(stage: &usd::Stage) -> Result<Vec<(String, String)>, anyhow::Error> {
    const KEYS: [&str; 8] = [
        "defaultPrim",
        "upAxis",
        "metersPerUnit",
        "kilogramsPerUnit",
        "startTimeCode",
        "endTimeCode",
        "timeCodesPerSecond",
        "framesPerSecond",
    ];
    let mut out = Vec::new();
    for key in KEYS {
        let text = match stage.stage_metadata(key)? {
            Some(sdf::Value::Token(t)) => quoted(t.as_str()),
            Some(sdf::Value::String(s)) => quoted(&s),
            Some(sdf::Value::Double(d)) if d.is_finite() => format!("{d:?}"),
            Some(sdf::Value::Float(f)) if f.is_finite() => format!("{f:?}"),
            Some(sdf::Value::Int(i)) => i.to_string(),
            _ => continue,
        };
        out.push((key.to_owned(), text));
    }
    if let Some(sdf::Value::Dictionary(data)) = stage.stage_metadata("customLayerData")?
        && let Some(text) = dictionary(&data, 1)
    {
        out.push(("customLayerData".to_owned(), text));
    }
    Ok(out)
}

/// A usda dictionary of strings, tokens, numbers, booleans and dictionaries (keys quoted,
/// sorted); `None` where a value is of another type (the writer then leaves it out).
fn dictionary(
    data: &std::collections::HashMap<String, sdf::Value>,
    depth: usize,
) -> Option<String> {
    let mut keys: Vec<&String> = data.keys().collect();
    keys.sort();
    let pad = "    ".repeat(depth + 1);
    let mut out = String::from("{\n");
    for key in keys {
        let (kind, text) = match &data[key] {
            sdf::Value::String(s) => ("string", quoted(s)),
            sdf::Value::Token(t) => ("token", quoted(t.as_str())),
            sdf::Value::Bool(b) => ("bool", b.to_string()),
            sdf::Value::Int(i) => ("int", i.to_string()),
            sdf::Value::Int64(i) => ("int64", i.to_string()),
            sdf::Value::Double(d) if d.is_finite() => ("double", format!("{d:?}")),
            sdf::Value::Float(f) if f.is_finite() => ("float", format!("{f:?}")),
            sdf::Value::Dictionary(d) => ("dictionary", dictionary(d, depth + 1)?),
            _ => return None,
        };
        out.push_str(&format!("{pad}{kind} {} = {text}\n", quoted(key)));
    }
    out.push_str(&"    ".repeat(depth));
    out.push('}');
    Some(out)
}

/// A usda string literal.
fn quoted(text: &str) -> String {
    let mut out = String::from("\"");
    for c in text.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

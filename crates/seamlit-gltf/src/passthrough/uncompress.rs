//! The pass-through's output stores geometry uncompressed unless the save keeps meshopt
//! compression: [`uncompress_views`] gives the views the input stored meshopt-compressed
//! their decoded bytes (decoded at load, `decode/meshopt.rs`), and [`strip_draco`] removes
//! KHR_draco_mesh_compression from the primitives (decoded at load, `decode/draco.rs`), whose
//! compressed views pruning then drops.

use std::path::Path;

use serde_json::{Value, json};

use crate::decode::draco::{DRACO, draco_primitives};
use crate::decode::meshopt::{MESHOPT, is_fallback, meshopt};
use crate::json::usize_member;
use crate::loaded::LoadedBuffers;

/// For the pass-through writer: every view of `json` (the output document) that carries
/// EXT_meshopt_compression is given its decoded bytes (`source_buffers`, decoded at load)
/// as new data in buffer 0, by `append` (which returns their offset there), and loses the
/// extension; fallback buffers no view uses any more are removed when they are the last
/// buffers, or else given their bytes as a `data:` URI; the extension is removed from
/// `extensionsUsed` and `extensionsRequired` when nothing uses it any more. Returns one
/// sentence for the save report, or `None` when nothing was compressed.
pub(crate) fn uncompress_views(
    json: &mut Value,
    source_buffers: &LoadedBuffers,
    path: &Path,
    mut append: impl FnMut(Vec<u8>) -> usize,
) -> Option<String> {
    let view_count = json["bufferViews"].as_array().map_or(0, Vec::len);
    let mut moved = 0;
    let mut names = std::collections::BTreeSet::new();
    for index in 0..view_count {
        let view = &json["bufferViews"][index];
        let Some((name, _)) = meshopt(view) else { continue };
        names.insert(name);
        let offset = usize_member(view, "byteOffset").unwrap_or(0);
        let length = usize_member(view, "byteLength").unwrap_or(0);
        // Decoded and checked at load: the bytes are there.
        let bytes = usize_member(view, "buffer")
            .and_then(|b| source_buffers.get(b, offset..offset + length))
            .map(<[u8]>::to_vec)
            .unwrap_or_default();
        let at = append(bytes);
        let view = &mut json["bufferViews"][index];
        view["buffer"] = json!(0);
        view["byteOffset"] = json!(at);
        remove_extension(view);
        moved += 1;
    }
    if moved == 0 {
        return None;
    }
    drop_unused_fallbacks(json, source_buffers);
    let still_used = json["buffers"]
        .as_array()
        .into_iter()
        .flatten()
        .chain(json["bufferViews"].as_array().into_iter().flatten())
        .any(|item| meshopt(item).is_some());
    if !still_used {
        for list in ["extensionsUsed", "extensionsRequired"] {
            if let Some(names) = json[list].as_array_mut() {
                names.retain(|name| !MESHOPT.iter().any(|m| name == m));
                if names.is_empty()
                    && let Some(root) = json.as_object_mut()
                {
                    root.remove(list);
                }
            }
        }
    }
    Some(format!(
        "{}: {moved} buffer views compressed with {} were decompressed; the output stores them uncompressed",
        path.display(),
        names.into_iter().collect::<Vec<_>>().join(" and ")
    ))
}

/// Fallback buffers (no data of their own) that no buffer view uses any more: the last ones
/// are removed (no index changes); one followed by a buffer that stays is given its bytes
/// as a `data:` URI, so that every buffer of the output has data. Every fallback buffer
/// left loses the extension.
fn drop_unused_fallbacks(json: &mut Value, source_buffers: &LoadedBuffers) {
    let used: std::collections::BTreeSet<usize> = json["bufferViews"]
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(|view| usize_member(view, "buffer"))
        .collect();
    let Some(buffers) = json["buffers"].as_array_mut() else { return };
    let unused_fallback =
        |index: usize, buffer: &Value| index > 0 && !used.contains(&index) && is_fallback(buffer);
    while buffers.len() > 1 && unused_fallback(buffers.len() - 1, &buffers[buffers.len() - 1]) {
        buffers.pop();
    }
    for (index, buffer) in buffers.iter_mut().enumerate() {
        if !is_fallback(buffer) {
            continue;
        }
        // Buffer 0 is written by the pass-through itself (BIN chunk or `NAME.bin`).
        if index > 0 && buffer.get("uri").is_none() {
            let length = source_buffers.len(index);
            let bytes = source_buffers.get(index, 0..length).unwrap_or_default();
            buffer["uri"] =
                json!(format!("data:application/octet-stream;base64,{}", base64::encode(bytes)));
        }
        remove_extension(buffer);
    }
}

/// Removes EXT_meshopt_compression from an object's `extensions` (and `extensions` when it
/// is left empty).
fn remove_extension(item: &mut Value) {
    let Some(object) = item.as_object_mut() else { return };
    let empty = object
        .get_mut("extensions")
        .and_then(Value::as_object_mut)
        .map(|extensions| {
            MESHOPT.iter().for_each(|name| {
                extensions.remove(*name);
            });
            extensions.is_empty()
        })
        .unwrap_or(false);
    if empty {
        object.remove("extensions");
    }
}

/// Removes KHR_draco_mesh_compression from every primitive of `json` (the output document;
/// the primitives' accessors hold the data `decode/draco.rs` decoded at load) and from
/// `extensionsUsed` and `extensionsRequired`. Returns one sentence for the save
/// report, or `None` when no primitive carried it.
pub(crate) fn strip_draco(json: &mut Value, path: &Path) -> Option<String> {
    let places = draco_primitives(json);
    if places.is_empty() {
        return None;
    }
    for &(m, p) in &places {
        let primitive = &mut json["meshes"][m]["primitives"][p];
        let Some(extensions) = primitive["extensions"].as_object_mut() else { continue };
        extensions.remove(DRACO);
        if extensions.is_empty()
            && let Some(primitive) = primitive.as_object_mut()
        {
            primitive.remove("extensions");
        }
    }
    for list in ["extensionsUsed", "extensionsRequired"] {
        let Some(names) = json[list].as_array_mut() else { continue };
        names.retain(|name| name != DRACO);
        if names.is_empty()
            && let Some(root) = json.as_object_mut()
        {
            root.remove(list);
        }
    }
    Some(format!(
        "{}: {} primitives compressed with {DRACO} were decompressed; the output stores them uncompressed",
        path.display(),
        places.len()
    ))
}

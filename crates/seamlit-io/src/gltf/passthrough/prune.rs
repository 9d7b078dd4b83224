//! Pruning for the glTF pass-through: the accessors and buffer views that only the input's
//! NORMAL, TANGENT, indices (and, for split primitives, the other attributes) used give
//! their places to the new ones, and their bytes leave buffer 0.
//!
//! The rules (design: `docs/gltf-pass-through.md`, "Indices, accessors and buffers"):
//!
//! - **Only what the pass made unused goes.** An accessor or buffer view is dropped when the
//!   input document used it and the output no longer does. Whatever the input itself left
//!   unused stays, bytes and all.
//! - **Nothing the output still uses is renumbered.** A dropped entry's index is reused by a
//!   new entry (the new ones were appended, so only new indices change); skins, animations,
//!   instancing attributes and images keep the indices they had.
//! - **Only documents whose every reference is known are pruned.** An extension this module
//!   does not know may hold an accessor or buffer view index; where one is present, nothing
//!   is dropped (the output keeps the input's data, as before pruning existed).
//! - Buffer 0 keeps the bytes of every buffer view it still holds, each at the same offset
//!   modulo 4 (so every accessor stays aligned to its component size), in input order.

use std::ops::Range;

use serde_json::{Value, json};

use crate::gltf_pass::index;

/// Extensions whose references to accessors and buffer views [`accessor_sites`] and
/// [`view_sites`] know, or which hold none (materials, textures by index, lights...).
fn known(extension: &str) -> bool {
    extension.starts_with("KHR_materials_")
        || matches!(
            extension,
            "KHR_texture_transform"
                | "KHR_texture_basisu"
                | "EXT_texture_webp"
                | "EXT_texture_avif"
                | "MSFT_texture_dds"
                | "KHR_lights_punctual"
                | "KHR_mesh_quantization"
                | "KHR_animation_pointer"
                | "KHR_node_visibility"
                | "KHR_xmp_json_ld"
                | "EXT_mesh_gpu_instancing"
                | "KHR_draco_mesh_compression"
        )
}

/// Every extension named anywhere in the document: in `extensionsUsed` and as a key of any
/// `extensions` object.
fn extensions(document: &Value) -> Vec<String> {
    fn walk(value: &Value, names: &mut Vec<String>) {
        match value {
            Value::Object(map) => {
                for (key, member) in map {
                    if let (true, Some(extensions)) = (key == "extensions", member.as_object()) {
                        names.extend(extensions.keys().cloned());
                    }
                    walk(member, names);
                }
            }
            Value::Array(items) => items.iter().for_each(|item| walk(item, names)),
            _ => {}
        }
    }
    let mut names: Vec<String> = document["extensionsUsed"]
        .as_array()
        .map(|used| used.iter().filter_map(Value::as_str).map(str::to_owned).collect())
        .unwrap_or_default();
    walk(document, &mut names);
    names.sort();
    names.dedup();
    names
}

/// The extensions of `document` that keep it from being pruned (those [`known`] does not
/// list); empty when it may be pruned.
pub(crate) fn unknown_extensions(document: &Value) -> Vec<String> {
    extensions(document).into_iter().filter(|name| !known(name)).collect()
}

/// A JSON pointer token for an object key (`~` and `/` escaped).
fn token(key: &str) -> String {
    key.replace('~', "~0").replace('/', "~1")
}

/// The JSON pointers of every place the document names an accessor by index.
fn accessor_sites(document: &Value) -> Vec<String> {
    let mut sites = Vec::new();
    let mut members = |object: &Value, at: String| {
        if let Some(map) = object.as_object() {
            sites.extend(map.keys().map(|k| format!("{at}/{}", token(k))));
        }
    };
    for (m, mesh) in array(document, "meshes").iter().enumerate() {
        for (p, primitive) in array(mesh, "primitives").iter().enumerate() {
            let at = format!("/meshes/{m}/primitives/{p}");
            members(&primitive["attributes"], format!("{at}/attributes"));
            for (t, target) in array(primitive, "targets").iter().enumerate() {
                members(target, format!("{at}/targets/{t}"));
            }
        }
    }
    for (n, node) in array(document, "nodes").iter().enumerate() {
        let instancing = &node["extensions"]["EXT_mesh_gpu_instancing"]["attributes"];
        members(instancing, format!("/nodes/{n}/extensions/EXT_mesh_gpu_instancing/attributes"));
    }
    for (m, mesh) in array(document, "meshes").iter().enumerate() {
        for (p, primitive) in array(mesh, "primitives").iter().enumerate() {
            if primitive.get("indices").is_some() {
                sites.push(format!("/meshes/{m}/primitives/{p}/indices"));
            }
        }
    }
    for (s, skin) in array(document, "skins").iter().enumerate() {
        if skin.get("inverseBindMatrices").is_some() {
            sites.push(format!("/skins/{s}/inverseBindMatrices"));
        }
    }
    for (a, animation) in array(document, "animations").iter().enumerate() {
        for (s, _) in array(animation, "samplers").iter().enumerate() {
            sites.push(format!("/animations/{a}/samplers/{s}/input"));
            sites.push(format!("/animations/{a}/samplers/{s}/output"));
        }
    }
    sites
}

/// The JSON pointers of every place the document names a buffer view by index.
fn view_sites(document: &Value) -> Vec<String> {
    let mut sites = Vec::new();
    for (a, accessor) in array(document, "accessors").iter().enumerate() {
        if accessor.get("bufferView").is_some() {
            sites.push(format!("/accessors/{a}/bufferView"));
        }
        if accessor.get("sparse").is_some() {
            sites.push(format!("/accessors/{a}/sparse/indices/bufferView"));
            sites.push(format!("/accessors/{a}/sparse/values/bufferView"));
        }
    }
    for (i, image) in array(document, "images").iter().enumerate() {
        if image.get("bufferView").is_some() {
            sites.push(format!("/images/{i}/bufferView"));
        }
    }
    for (m, mesh) in array(document, "meshes").iter().enumerate() {
        for (p, primitive) in array(mesh, "primitives").iter().enumerate() {
            if primitive["extensions"]["KHR_draco_mesh_compression"].get("bufferView").is_some() {
                sites.push(format!(
                    "/meshes/{m}/primitives/{p}/extensions/KHR_draco_mesh_compression/bufferView"
                ));
            }
        }
    }
    sites
}

/// How many places of `document` name buffer view `view` (in a document whose every
/// reference [`unknown_extensions`] vouches for).
#[cfg(feature = "draco")]
pub(crate) fn view_uses(document: &Value, view: usize) -> usize {
    view_sites(document)
        .iter()
        .filter(|site| document.pointer(site).and_then(index) == Some(view))
        .count()
}

/// The array member `key` of `value`, or none.
fn array<'v>(value: &'v Value, key: &str) -> &'v [Value] {
    value.get(key).and_then(Value::as_array).map_or(&[], Vec::as_slice)
}

/// Which of `count` entries the `sites` of `document` name.
fn used(document: &Value, sites: &[String], count: usize) -> Vec<bool> {
    let mut used = vec![false; count];
    for site in sites {
        let i = document.pointer(site).and_then(index);
        if let Some(u) = i.and_then(|i| used.get_mut(i)) {
            *u = true;
        }
    }
    used
}

/// Moves the entries of the array `key` appended after the input's `input_count` into the
/// places of the input entries that `before` used and `after` does not, then closes the gap
/// the moved ones left at the end; rewrites every site. Returns the places reused.
fn reuse(
    document: &mut Value,
    key: &str,
    input_count: usize,
    before: &[bool],
    sites: impl Fn(&Value) -> Vec<String>,
) -> Vec<usize> {
    let total = array(document, key).len();
    let after = used(document, &sites(document), total);
    let freed: Vec<usize> = (0..input_count.min(total))
        .filter(|&i| before.get(i) == Some(&true) && !after[i])
        .collect();
    let added: Vec<usize> = (input_count..total).collect();
    let moves = freed.len().min(added.len());
    if moves == 0 {
        return Vec::new();
    }
    // New index of every appended entry: the first `moves` go to freed places, the rest
    // close up behind the input's entries.
    let mut to = vec![usize::MAX; total];
    for (k, &from) in added.iter().enumerate() {
        to[from] = if k < moves { freed[k] } else { input_count + k - moves };
    }
    let entries = document[key].as_array_mut().expect("counted above");
    for (k, &from) in added.iter().enumerate().take(moves) {
        entries.swap(freed[k], from);
    }
    let tail: Vec<Value> = entries.drain(input_count..).collect();
    entries.extend(tail.into_iter().skip(moves));
    for site in sites(document) {
        let Some(reference) = document.pointer_mut(&site) else { continue };
        let moved = index(reference).filter(|&i| i >= input_count);
        if let Some(&new) = moved.and_then(|i| to.get(i)) {
            *reference = json!(new);
        }
    }
    freed.into_iter().take(moves).collect()
}

/// Where buffer 0's kept input bytes go.
#[derive(Debug, Default)]
pub(crate) struct Kept {
    /// Input byte ranges kept, in order, each with its new start.
    pub ranges: Vec<(Range<usize>, usize)>,
    /// The kept bytes' extent in the output buffer (padding included), before the new data.
    pub length: usize,
}

/// Prunes `output` (the pass-through's document, new accessors and buffer views appended to
/// `input`'s): see the module docs. `appended_at` is where the new data starts in buffer 0.
/// Returns how buffer 0's input bytes move, `None` when nothing was dropped (or the document
/// may not be pruned): then buffer 0 keeps the input's bytes as they were.
pub(crate) fn prune(input: &Value, output: &mut Value, appended_at: usize) -> Option<Kept> {
    if !unknown_extensions(input).is_empty() {
        return None;
    }
    let accessors = array(input, "accessors").len();
    let before = used(input, &accessor_sites(input), accessors);
    let freed = reuse(output, "accessors", accessors, &before, accessor_sites);
    if freed.is_empty() {
        return None;
    }
    let views = array(input, "bufferViews").len();
    let before = used(input, &view_sites(input), views);
    let replaced = reuse(output, "bufferViews", views, &before, view_sites);
    let kept = compact(output, views, &replaced, appended_at);
    Some(kept)
}

/// Packs buffer 0's input bytes that the input's remaining buffer views hold (`input_views`
/// of them, less the `replaced` places now holding new views) and moves the new views
/// (data appended at `appended_at`) down behind them.
fn compact(
    document: &mut Value,
    input_views: usize,
    replaced: &[usize],
    appended_at: usize,
) -> Kept {
    let range = |view: &Value| {
        let start = index(&view["byteOffset"]).unwrap_or(0);
        let length = index(&view["byteLength"]).unwrap_or(0);
        start..start.saturating_add(length)
    };
    let in_buffer_0 = |view: &Value| index(&view["buffer"]) == Some(0);
    let views = array(document, "bufferViews");
    let old: Vec<usize> = (0..input_views.min(views.len()))
        .filter(|i| !replaced.contains(i) && in_buffer_0(&views[*i]))
        .collect();
    // The kept input ranges, merged where they overlap or touch.
    let mut spans: Vec<Range<usize>> = old.iter().map(|&i| range(&views[i])).collect();
    spans.sort_by_key(|r| (r.start, r.end));
    let mut merged: Vec<Range<usize>> = Vec::new();
    for span in spans {
        match merged.last_mut() {
            Some(last) if span.start <= last.end => last.end = last.end.max(span.end),
            _ => merged.push(span),
        }
    }
    let mut kept = Kept::default();
    for span in merged {
        // The same offset modulo 4 as in the input: accessors stay aligned.
        let start = kept.length + (span.start + 4 - kept.length % 4) % 4;
        kept.length = start + span.len();
        kept.ranges.push((span, start));
    }
    kept.length = kept.length.next_multiple_of(4);
    let moved = |offset: usize, ranges: &[(Range<usize>, usize)]| {
        ranges
            .iter()
            .find(|(r, _)| r.start <= offset && offset <= r.end)
            .map_or(0, |(r, start)| start + (offset - r.start))
    };
    let entries = document["bufferViews"].as_array_mut().expect("counted above");
    for (i, view) in entries.iter_mut().enumerate() {
        if !in_buffer_0(view) {
            continue;
        }
        let offset = index(&view["byteOffset"]).unwrap_or(0);
        let new = if i < input_views && !replaced.contains(&i) {
            // A zero-length view keeps a place at its range's start.
            moved(offset, &kept.ranges)
        } else {
            offset - appended_at + kept.length
        };
        view["byteOffset"] = json!(new);
    }
    kept
}

//! Where glTF 2.0 allows what gltf 1.4.1 refuses, and how the reader follows the
//! specification there with the least parsing of its own.
//!
//! The document keeps being checked by gltf-json's own validation ([`validate`]); only the
//! errors that contradict the specification are dropped, each for a stated reason:
//!
//! - an accessor without `bufferView` is all zeros ("When `bufferView` is undefined, the
//!   accessor MUST be initialized with zeros", glTF 2.0, 5.1 Accessor); gltf-json requires
//!   a `bufferView` unless `sparse` is present;
//! - a primitive without `POSITION` is allowed (its rendering is skipped, glTF 2.0,
//!   3.7.2.1); the reader skips it with a warning;
//! - an accessor `type` outside the listed ones is allowed by the schema (`anyOf` with
//!   `string`); gltf-json refuses it. It is kept only for accessors seamlit never reads: no
//!   mesh primitive, skin (`inverseBindMatrices`) or animation sampler uses them (the gltf
//!   crate panics on the type of one it reads).
//!
//! A document gltf-json refuses to parse is parsed again as [`lenient`] patches it: a scene
//! without `nodes`, whole numbers written as floats. Before that typed parse,
//! [`drop_channels_without_node`] removes, from the copy gltf-json
//! parses only, the animation channels whose target has no `node` (allowed: "When
//! undefined, the animated object MAY be defined by an extension", as
//! `KHR_animation_pointer` does); seamlit does not read animations, and the pass-through
//! writes the document as written.
//!
//! A file without scenes "SHOULD be treated as a library of individual entities such as
//! materials or meshes" (glTF 2.0, 3.5.1): seamlit places the nodes that are no node's child
//! as if one scene listed them ([`root_nodes`]), as Blender's importer does, so that `fix`
//! has their meshes to fix. Meshes that no node instances stay unplaced.
//!
//! A buffer without `uri` that is not a GLB's BIN chunk has data that "MAY be provided by
//! an extension or other means"; seamlit has none for it. It loads as an empty buffer, and
//! a primitive that reads from one is skipped with a warning ([`without_data`]), as one
//! without `POSITION` is; the pass-through writes it back as it was.

use gltf::json::validation::{Checked, Error as Problem, Validate};

/// gltf-json's validation of `root`, without the errors the specification contradicts (see
/// the module documentation).
///
/// # Errors
///
/// The remaining problems, each at its JSON path, in gltf-json's order.
pub(crate) fn validate(root: &gltf::json::Root) -> Result<(), Vec<(gltf::json::Path, Problem)>> {
    let mut errors = Vec::new();
    root.validate(root, gltf::json::Path::new, &mut |path, error| {
        let path = path();
        if !allowed(root, path.as_str(), &error) {
            errors.push((path, error));
        }
    });
    if errors.is_empty() { Ok(()) } else { Err(errors) }
}

/// Whether the specification allows what gltf-json reports as `error` at `path`.
fn allowed(root: &gltf::json::Root, path: &str, error: &Problem) -> bool {
    // "When positions are not specified, client implementations SHOULD skip primitive's
    // rendering" (glTF 2.0, 3.7.2.1): the reader skips it with a warning.
    if path.starts_with("meshes[") && path.ends_with(r#".attributes["POSITION"]"#) {
        return matches!(error, Problem::Missing);
    }
    let Some((index, field)) = path
        .strip_prefix("accessors[")
        .and_then(|rest| rest.split_once("]."))
        .and_then(|(i, field)| Some((i.parse::<usize>().ok()?, field)))
    else {
        return false;
    };
    let Some(accessor) = root.accessors.get(index) else { return false };
    match (field, error) {
        ("bufferView", Problem::Missing) => accessor.buffer_view.is_none(),
        ("type", Problem::Invalid) => {
            matches!(accessor.type_, Checked::Invalid) && !read_by_seamlit(root, index)
        }
        _ => false,
    }
}

/// Whether accessor `index` is one the reader reads: an attribute, the indices or a
/// morph-target attribute of a mesh primitive, a skin's `inverseBindMatrices`, or an
/// animation sampler's `input` or `output`.
fn read_by_seamlit(root: &gltf::json::Root, index: usize) -> bool {
    let skins = root.skins.iter().filter_map(|s| s.inverse_bind_matrices);
    let samplers =
        root.animations.iter().flat_map(|a| &a.samplers).flat_map(|s| [s.input, s.output]);
    if skins.chain(samplers).any(|a| a.value() == index) {
        return true;
    }
    root.meshes.iter().flat_map(|m| &m.primitives).any(|p| {
        p.indices.is_some_and(|i| i.value() == index)
            || p.attributes.values().any(|a| a.value() == index)
            || p.targets.iter().flatten().any(|t| {
                [&t.positions, &t.normals, &t.tangents]
                    .into_iter()
                    .flatten()
                    .any(|a| a.value() == index)
            })
    })
}

/// Removes, from a copy of the document meant for gltf-json only, every animation channel
/// whose `target` has no `node`; `true` when one was removed.
pub(crate) fn drop_channels_without_node(document: &mut serde_json::Value) -> bool {
    let mut changed = false;
    let animations = document.get_mut("animations").and_then(serde_json::Value::as_array_mut);
    for animation in animations.into_iter().flatten() {
        if let Some(channels) =
            animation.get_mut("channels").and_then(serde_json::Value::as_array_mut)
        {
            let before = channels.len();
            channels.retain(|c| c.get("target").is_none_or(|t| t.get("node").is_some()));
            changed |= channels.len() != before;
        }
    }
    changed
}

/// Why `primitive` cannot be read: an accessor it reads (attribute, indices, morph-target
/// attribute; its buffer view or sparse indices or values) lies in one of the buffers
/// `without_data` (no `uri`, not the GLB's BIN chunk). `None` when it can be read.
pub(crate) fn without_data(
    primitive: &gltf::Primitive<'_>,
    without_data: &[usize],
) -> Option<String> {
    if without_data.is_empty() {
        return None;
    }
    let buffers_of = |accessor: &gltf::Accessor<'_>| -> Vec<usize> {
        let mut buffers: Vec<usize> =
            accessor.view().map(|v| v.buffer().index()).into_iter().collect();
        if let Some(sparse) = accessor.sparse() {
            buffers.push(sparse.indices().view().buffer().index());
            buffers.push(sparse.values().view().buffer().index());
        }
        buffers
    };
    let mut read: Vec<(String, gltf::Accessor<'_>)> =
        primitive.attributes().map(|(semantic, a)| (semantic.to_string(), a)).collect();
    read.extend(primitive.indices().map(|a| ("indices".to_owned(), a)));
    for (t, target) in primitive.morph_targets().enumerate() {
        let targets = [target.positions(), target.normals(), target.tangents()];
        read.extend(targets.into_iter().flatten().map(|a| (format!("target {t}"), a)));
    }
    read.into_iter().find_map(|(what, accessor)| {
        let buffer = buffers_of(&accessor).into_iter().find(|b| without_data.contains(b))?;
        Some(format!(
            "{what} (accessor {}) lies in buffer {buffer}, which has no uri and is not the GLB BIN chunk (its data comes from an extension or elsewhere)",
            accessor.index()
        ))
    })
}

/// The buffers without data: every buffer without `uri` but the first, which is the GLB's
/// BIN chunk when `has_bin` (the reader gives them no bytes).
pub(crate) fn buffers_without_data(document: &gltf::Document, has_bin: bool) -> Vec<usize> {
    document
        .buffers()
        .filter(|b| matches!(b.source(), gltf::buffer::Source::Bin))
        .map(|b| b.index())
        .skip(usize::from(has_bin))
        .collect()
}

/// The values of an accessor with neither a buffer view nor sparse data: `count` zeros
/// (glTF 2.0, 5.1 Accessor), where the gltf crate's reader gives nothing; `read` as it is
/// otherwise.
pub(crate) fn zeros_without_view<T: Clone + Default>(
    accessor: Option<&gltf::Accessor<'_>>,
    read: Option<Vec<T>>,
) -> Option<Vec<T>> {
    match accessor {
        Some(a) if read.is_none() && a.view().is_none() && a.sparse().is_none() => {
            Some(vec![T::default(); a.count()])
        }
        _ => read,
    }
}

/// The nodes that are no node's child, in index order: the scene of a file without scenes.
pub(crate) fn root_nodes(document: &gltf::Document) -> Vec<gltf::Node<'_>> {
    let mut child = vec![false; document.nodes().len()];
    for c in document.nodes().flat_map(|n| n.children()) {
        child[c.index()] = true;
    }
    document.nodes().filter(|n| !child[n.index()]).collect()
}

/// What the specification allows and gltf-json 1.4.1 refuses, made acceptable to it: a
/// scene without `nodes` (an empty scene) gets `"nodes": []`, whole numbers written as
/// floats (`"count": 3.0`) become integers (float fields read integers as well), and
/// animation channels without a target node are dropped (see `lenient.rs`). `None` when
/// there is nothing to change.
pub(super) fn lenient(document: &serde_json::Value) -> Option<serde_json::Value> {
    fn patch(value: &mut serde_json::Value, changed: &mut bool) {
        match value {
            serde_json::Value::Number(n) if n.is_f64() => {
                let x = n.as_f64().unwrap_or(f64::NAN);
                if x.fract() == 0.0 && (-9.0e15..9.0e15).contains(&x) {
                    #[expect(clippy::cast_possible_truncation, reason = "a whole number, checked")]
                    let whole = x as i64;
                    *value = serde_json::Value::from(whole);
                    *changed = true;
                }
            }
            serde_json::Value::Array(items) => items.iter_mut().for_each(|v| patch(v, changed)),
            serde_json::Value::Object(members) => {
                members.values_mut().for_each(|v| patch(v, changed));
            }
            _ => {}
        }
    }
    let mut patched = document.clone();
    let mut changed = drop_channels_without_node(&mut patched);
    patch(&mut patched, &mut changed);
    let scenes = patched.get_mut("scenes").and_then(serde_json::Value::as_array_mut);
    for scene in scenes.into_iter().flatten().filter_map(serde_json::Value::as_object_mut) {
        if !scene.contains_key("nodes") {
            scene.insert("nodes".to_owned(), serde_json::Value::Array(Vec::new()));
            changed = true;
        }
    }
    changed.then_some(patched)
}

//! What of buffer 0 the pass-through writer need not read from the input. It writes the
//! NORMAL, TANGENT and indices of the primitives it writes from the model
//! ([`super::OutputDocument`]'s `primitive`), never from the input; and their POSITION and
//! TEXCOORD_0, where stored as floats, are the model's positions and UVs bit for bit (a fix
//! never moves them). Once the model is decoded the reader keeps only the rest
//! (`read.rs`, [`crate::loaded::LoadedBuffers`]): for a GLB of geometry alone, next to
//! nothing of its BIN chunk.
//!
//! - A view named only by replaced accessors is given back. Such views are among those
//!   pruning drops (`prune.rs`): every accessor they held is one the output no longer names.
//!   Where pruning cannot give a view's place to a new one (fewer new views than freed ones),
//!   the output keeps it, unused, and its bytes are written as zeros.
//! - A view that only the positions or UVs of written primitives fill, tightly, edge to edge,
//!   is given back too, and written again from the model: the same bytes, checked against a
//!   hash of them made at load ([`crate::GltfSource::check_model`]: a model whose positions or
//!   UVs were changed is written by the generic writer instead).
//! - Every other view of buffer 0 stays as it was read.

use std::ops::Range;

use rustc_hash::{FxHashMap, FxHashSet};
use serde_json::Value;

use crate::decode::draco::{DRACO, draco_primitives};
use crate::json::{FLOAT, index, integer, usize_member};
use crate::loaded::{Attribute, FromModel, merged};
use crate::references::{
    AccessorSite, array, each_accessor_site, each_view_site, unknown_extensions,
};
use crate::source::Instance;

/// What a load keeps of buffer 0.
pub(crate) struct Unread {
    /// The byte ranges kept (offsets as loaded; they may overlap).
    pub(crate) kept: Vec<Range<usize>>,
    /// The accessors given back whose elements are the model's.
    pub(crate) from_model: Vec<FromModel>,
}

/// How the writer writes an input accessor.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Written {
    /// From its bytes.
    Input,
    /// Not at all: new data from the model takes its place.
    Replaced,
    /// From the model's elements, which are its own.
    Model(Attribute),
}

/// What a load of `json` (whose objects came from `instances`) keeps of buffer 0. `None`
/// where it keeps all of it: less than a quarter of it to give back, or a document pruning
/// does not touch (an extension whose references `references.rs` does not know) or whose
/// views the load rewrote (Draco).
pub(crate) fn unread(json: &Value, instances: &[Instance]) -> Option<Unread> {
    let draco = !draco_primitives(json).is_empty()
        || json["extensionsUsed"]
            .as_array()
            .is_some_and(|used| used.iter().any(|name| name.as_str() == Some(DRACO)));
    if draco || !unknown_extensions(json).is_empty() {
        return None;
    }
    let (written, objects) = written_accessors(json, instances);
    let views = array(json, "bufferViews");
    // Per view: how each of its users is written (a user that is no accessor: `Input`).
    let mut users: Vec<Vec<(Option<usize>, Written)>> = vec![Vec::new(); views.len()];
    each_view_site(json, |site, value| {
        let Some(view) = index(value).filter(|&v| v < views.len()) else { return };
        let accessor = site.accessor().filter(|&a| a < written.len());
        users[view].push((accessor, accessor.map_or(Written::Input, |a| written[a])));
    });
    let (mut kept, mut from_model) = (Vec::new(), Vec::new());
    for (v, view) in views.iter().enumerate() {
        if usize_member(view, "buffer") != Some(0) {
            continue;
        }
        let users = &users[v];
        if !users.is_empty() && users.iter().all(|&(_, w)| w == Written::Replaced) {
            continue;
        }
        // Every accessor written from the model names its objects (it came from their sites).
        let filled = model_filled(json, view, users).filter(|parts| {
            parts.iter().all(|(a, ..)| objects.get(a).is_some_and(|o| !o.is_empty()))
        });
        match filled {
            Some(parts) => {
                from_model.extend(parts.into_iter().map(|(accessor, bytes, attribute)| {
                    FromModel {
                        accessor,
                        bytes,
                        attribute,
                        objects: objects.get(&accessor).cloned().unwrap_or_default(),
                    }
                }));
            }
            None => kept.push(byte_range(view)),
        }
    }
    // Giving back moves the kept bytes together: worth it only for much.
    let length = usize_member(&json["buffers"][0], "byteLength").unwrap_or(0);
    let held: usize =
        merged(kept.clone()).iter().map(|r| r.end.min(length).saturating_sub(r.start)).sum();
    let given_back = length.saturating_sub(held);
    (given_back > 0 && given_back >= length / GIVE_BACK_FROM).then_some(Unread { kept, from_model })
}

/// Buffer 0 gives bytes back where at least this fraction of it goes (1 / this): less would
/// save little memory for the copying of what stays (embedded images, mostly).
const GIVE_BACK_FROM: usize = 4;

/// Per accessor, how the writer writes it; and per accessor written from the model, the
/// objects whose elements it holds.
fn written_accessors(
    json: &Value,
    instances: &[Instance],
) -> (Vec<Written>, FxHashMap<usize, Vec<usize>>) {
    // Each written primitive's objects.
    let mut primitives: FxHashMap<(usize, usize), Vec<usize>> = FxHashMap::default();
    for (object, i) in instances.iter().enumerate() {
        primitives.entry((i.mesh, i.primitive)).or_default().push(object);
    }
    let count = array(json, "accessors").len();
    let mut written: Vec<Option<Written>> = vec![None; count];
    let mut objects: FxHashMap<usize, Vec<usize>> = FxHashMap::default();
    each_accessor_site(json, |site, value| {
        let Some(a) = index(value).filter(|&a| a < count) else { return };
        let (how, of) = match site {
            AccessorSite::Attribute { mesh, primitive, name } => (
                match name {
                    "NORMAL" | "TANGENT" => Written::Replaced,
                    "POSITION" => Written::Model(Attribute::Positions),
                    "TEXCOORD_0" => Written::Model(Attribute::Uvs),
                    _ => Written::Input,
                },
                primitives.get(&(mesh, primitive)),
            ),
            AccessorSite::Indices { mesh, primitive } => {
                (Written::Replaced, primitives.get(&(mesh, primitive)))
            }
            _ => (Written::Input, None),
        };
        // Not a written primitive's: its bytes.
        let (how, of) = match of {
            Some(of) if how != Written::Input => (how, &of[..]),
            _ => (Written::Input, &[][..]),
        };
        // Named twice in different ways (or as a model attribute it is not stored as): its bytes.
        let how = match (written[a], how) {
            (Some(before), now) if before != now => Written::Input,
            (_, Written::Model(attribute)) if !stored_as(&json["accessors"][a], attribute) => {
                Written::Input
            }
            (_, now) => now,
        };
        written[a] = Some(how);
        objects.entry(a).or_default().extend_from_slice(of);
    });
    let written = written.into_iter().map(|w| w.unwrap_or(Written::Input)).collect();
    (written, objects)
}

/// Whether an accessor's elements are the model's `attribute` bit for bit: floats, not
/// normalised, not sparse, of the attribute's shape.
fn stored_as(accessor: &Value, attribute: Attribute) -> bool {
    integer(&accessor["componentType"]) == Some(FLOAT)
        && accessor["type"].as_str() == Some(attribute.shape())
        && accessor.get("sparse").is_none()
        && accessor.get("normalized").and_then(Value::as_bool) != Some(true)
        && accessor.get("bufferView").is_some()
}

/// Where a view's users are all accessors written from the model that fill it edge to
/// edge, tightly and without overlap: each one's bytes (offsets in the buffer) and attribute.
fn model_filled(
    json: &Value,
    view: &Value,
    users: &[(Option<usize>, Written)],
) -> Option<Vec<(usize, Range<usize>, Attribute)>> {
    let start = usize_member(view, "byteOffset").unwrap_or(0);
    let mut parts = Vec::with_capacity(users.len());
    let mut seen = FxHashSet::default();
    for &(accessor, written) in users {
        let (Some(a), Written::Model(attribute)) = (accessor, written) else { return None };
        if !seen.insert(a) {
            continue;
        }
        let element = attribute.element_size();
        if usize_member(view, "byteStride").is_some_and(|s| s != element) {
            return None;
        }
        let accessor = &json["accessors"][a];
        let offset = start.checked_add(usize_member(accessor, "byteOffset").unwrap_or(0))?;
        let length = usize_member(accessor, "count")?.checked_mul(element)?;
        parts.push((a, offset..offset.checked_add(length)?, attribute));
    }
    parts.sort_by_key(|(_, bytes, _)| bytes.start);
    let end =
        parts.iter().try_fold(start, |at, (_, bytes, _)| (bytes.start == at).then_some(bytes.end));
    (end == Some(byte_range(view).end) && !parts.is_empty()).then_some(parts)
}

/// A buffer view's bytes in its buffer.
fn byte_range(view: &Value) -> Range<usize> {
    let start = usize_member(view, "byteOffset").unwrap_or(0);
    start..start.saturating_add(usize_member(view, "byteLength").unwrap_or(0))
}

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
//!   does not know (`references.rs`) may hold an accessor or buffer view index; where one is
//!   present, nothing is dropped (the output keeps the input's data, as before pruning
//!   existed).
//! - Buffer 0 keeps the bytes of every buffer view it still holds, each at the same offset
//!   modulo 4 (so every accessor stays aligned to its component size), in input order.

use std::ops::Range;

use serde_json::{Value, json};

use crate::json::index;
use crate::loaded::merged;
use crate::references::{
    accessor_sites, accessors_used, array, unknown_extensions, view_sites, views_used,
};

/// How a document names one kind of entry: which of them it names, and the JSON pointers of
/// the places that do.
#[derive(Clone, Copy)]
struct Kind {
    used: fn(&Value, usize) -> Vec<bool>,
    sites: fn(&Value) -> Vec<String>,
}

const ACCESSORS: Kind = Kind { used: accessors_used, sites: accessor_sites };
const VIEWS: Kind = Kind { used: views_used, sites: view_sites };

/// Moves the entries of the array `key` appended after the input's `input_count` into the
/// places of the input entries that `before` used and `after` does not, then closes the gap
/// the moved ones left at the end; rewrites every site. Returns the places reused.
fn reuse(
    document: &mut Value,
    key: &str,
    input_count: usize,
    before: &[bool],
    kind: Kind,
) -> Vec<usize> {
    let Kind { used, sites } = kind;
    let total = array(document, key).len();
    let after = used(document, total);
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
pub(crate) struct KeptBytes {
    /// Input byte ranges kept, in order, each with its new start.
    pub ranges: Vec<(Range<usize>, usize)>,
    /// The kept bytes' extent in the output buffer (padding included), before the new data.
    pub length: usize,
}

/// Prunes `output` (the pass-through's document, new accessors and buffer views appended to
/// `input`'s): see the module docs. `appended_at` is where the new data starts in buffer 0.
/// Returns how buffer 0's input bytes move, `None` when nothing was dropped (or the document
/// may not be pruned): then buffer 0 keeps the input's bytes as they were.
pub(crate) fn prune(input: &Value, output: &mut Value, appended_at: usize) -> Option<KeptBytes> {
    if !unknown_extensions(input).is_empty() {
        return None;
    }
    let accessors = array(input, "accessors").len();
    let before = accessors_used(input, accessors);
    let freed = reuse(output, "accessors", accessors, &before, ACCESSORS);
    if freed.is_empty() {
        return None;
    }
    let views = array(input, "bufferViews").len();
    let before = views_used(input, views);
    let replaced = reuse(output, "bufferViews", views, &before, VIEWS);
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
) -> KeptBytes {
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
    let merged = merged(old.iter().map(|&i| range(&views[i])).collect());
    let mut kept = KeptBytes::default();
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

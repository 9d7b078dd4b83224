//! What of buffer 0 the pass-through writer never reads: the bytes of the buffer views that
//! only the input's NORMAL, TANGENT and indices of the primitives it writes name. It writes
//! those from the model ([`super::OutputDocument`]'s `primitive`), so once the model is
//! decoded the reader keeps only the rest (`read.rs`, [`crate::loaded::LoadedBuffers`]): for a
//! GLB with normals, tangents and indices, most of its BIN chunk.
//!
//! The views given back are among those pruning drops (`prune.rs`), since every accessor
//! they held is one the output no longer names. Where pruning cannot give a view's place to
//! a new one (fewer new views than freed ones), the output keeps the view, unused, and its
//! bytes are written as zeros.

use std::collections::HashSet;
use std::ops::Range;

use serde_json::Value;

use crate::decode::draco::{DRACO, draco_primitives};
use crate::json::{index, usize_member};
use crate::references::{accessor_sites, array, unknown_extensions, view_sites};
use crate::source::Instance;

/// The byte ranges of buffer 0 that a load keeps: every buffer view's in buffer 0 but those
/// named only by the accessors the writer replaces. `None` where nothing is given back: no
/// such view, or a document pruning does not touch (an extension whose references
/// `references.rs` does not know) or whose views the load rewrote (Draco).
pub(crate) fn kept_ranges(json: &Value, instances: &[Instance]) -> Option<Vec<Range<usize>>> {
    let draco = !draco_primitives(json).is_empty()
        || json["extensionsUsed"]
            .as_array()
            .is_some_and(|used| used.iter().any(|name| name.as_str() == Some(DRACO)));
    if draco || !unknown_extensions(json).is_empty() {
        return None;
    }
    let replaced = replaced_accessors(json, instances);
    let views = array(json, "bufferViews");
    let mut named = vec![false; views.len()];
    let mut named_by_kept = vec![false; views.len()];
    for site in view_sites(json) {
        let Some(view) = json.pointer(&site).and_then(index).filter(|&v| v < views.len()) else {
            continue;
        };
        named[view] = true;
        if !accessor_of(&site).is_some_and(|a| replaced.get(a) == Some(&true)) {
            named_by_kept[view] = true;
        }
    }
    let given_back = |v: usize| named[v] && !named_by_kept[v];
    if !(0..views.len()).any(|v| given_back(v) && in_host(&views[v])) {
        return None;
    }
    let kept = views.iter().enumerate().filter(|&(v, view)| in_host(view) && !given_back(v));
    Some(kept.map(|(_, view)| byte_range(view)).collect())
}

/// Per accessor: whether the writer replaces it everywhere the document names it (it is a
/// NORMAL, TANGENT or the indices of a primitive the writer writes, and nothing else).
fn replaced_accessors(json: &Value, instances: &[Instance]) -> Vec<bool> {
    let written: HashSet<String> = instances
        .iter()
        .flat_map(|i| {
            let at = format!("/meshes/{}/primitives/{}", i.mesh, i.primitive);
            [
                format!("{at}/attributes/NORMAL"),
                format!("{at}/attributes/TANGENT"),
                format!("{at}/indices"),
            ]
        })
        .collect();
    let count = array(json, "accessors").len();
    let (mut by_written, mut by_other) = (vec![false; count], vec![false; count]);
    for site in accessor_sites(json) {
        let Some(a) = json.pointer(&site).and_then(index).filter(|&a| a < count) else {
            continue;
        };
        if written.contains(&site) {
            by_written[a] = true;
        } else {
            by_other[a] = true;
        }
    }
    by_written.iter().zip(&by_other).map(|(&w, &o)| w && !o).collect()
}

/// The accessor whose member a view site (`/accessors/{a}/...`) is.
fn accessor_of(site: &str) -> Option<usize> {
    site.strip_prefix("/accessors/")?.split('/').next()?.parse().ok()
}

/// Whether a buffer view lies in buffer 0.
fn in_host(view: &Value) -> bool {
    usize_member(view, "buffer") == Some(0)
}

/// A buffer view's bytes in its buffer.
fn byte_range(view: &Value) -> Range<usize> {
    let start = usize_member(view, "byteOffset").unwrap_or(0);
    start..start.saturating_add(usize_member(view, "byteLength").unwrap_or(0))
}

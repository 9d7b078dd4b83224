//! Structure-aware mutations of a glTF document (issue 32): indices out of range, values of
//! the wrong type, keys deleted or added, arrays shortened or grown, enumerations swapped and
//! values copied from one place to another, in the objects that reference each other
//! (animations, skins, nodes, accessors, meshes and their morph targets, buffer views,
//! scenes, materials, textures, images). Byte mutations rarely keep a document parseable;
//! these keep the JSON well-formed and aim at the indices and types the reader must check
//! before the gltf crate unwraps them.
//!
//! Used by `tests/mutated_gltf.rs` (a fixed number of seeded cases in every `cargo test`) and,
//! included by path, by the `gltf_json` fuzz target (fuzz/fuzz_targets/gltf_json.rs), whose
//! custom mutator calls [`mutate`] with libFuzzer's seed.

use std::path::Path;

use serde_json::{Value, json};

/// The top-level arrays whose members are mutated.
pub const SECTIONS: [&str; 11] = [
    "animations",
    "skins",
    "nodes",
    "accessors",
    "meshes",
    "bufferViews",
    "scenes",
    "materials",
    "textures",
    "images",
    "buffers",
];

/// Strings that glTF enumerations take (and some they do not).
const NAMES: [&str; 20] = [
    "translation",
    "rotation",
    "scale",
    "weights",
    "pointer",
    "SCALAR",
    "VEC2",
    "VEC3",
    "VEC4",
    "MAT2",
    "MAT3",
    "MAT4",
    "LINEAR",
    "STEP",
    "CUBICSPLINE",
    "POSITION",
    "JOINTS_0",
    "WEIGHTS_0",
    "",
    "x",
];

/// Keys that glTF objects reference each other and describe data by.
const KEYS: [&str; 28] = [
    "node",
    "path",
    "sampler",
    "input",
    "output",
    "interpolation",
    "inverseBindMatrices",
    "joints",
    "skeleton",
    "skin",
    "mesh",
    "weights",
    "children",
    "count",
    "byteStride",
    "byteOffset",
    "byteLength",
    "bufferView",
    "buffer",
    "sparse",
    "targets",
    "componentType",
    "type",
    "normalized",
    "indices",
    "attributes",
    "JOINTS_0",
    "WEIGHTS_0",
];

/// Where mutations draw their choices from: a seeded generator in the tests, libFuzzer's
/// seed in the fuzz target.
pub struct Choices(u64);

impl Choices {
    /// Choices from `seed` (splitmix64).
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A number in `0..n` (`0` when `n` is 0).
    pub fn below(&mut self, n: usize) -> usize {
        if n == 0 { 0 } else { usize::try_from(self.next() % n as u64).unwrap_or(0) }
    }

    fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}

/// One step of a path into the document.
#[derive(Clone, Debug)]
pub enum Step {
    Key(String),
    Index(usize),
}

/// Every place inside the [`SECTIONS`] (the section arrays themselves included).
fn sites(document: &Value) -> Vec<Vec<Step>> {
    fn walk(value: &Value, path: &mut Vec<Step>, out: &mut Vec<Vec<Step>>) {
        out.push(path.clone());
        match value {
            Value::Array(items) => {
                for (i, item) in items.iter().enumerate() {
                    path.push(Step::Index(i));
                    walk(item, path, out);
                    path.pop();
                }
            }
            Value::Object(members) => {
                for (key, member) in members {
                    path.push(Step::Key(key.clone()));
                    walk(member, path, out);
                    path.pop();
                }
            }
            _ => {}
        }
    }
    let mut out = Vec::new();
    for section in SECTIONS {
        if let Some(value) = document.get(section) {
            walk(value, &mut vec![Step::Key(section.to_owned())], &mut out);
        }
    }
    out
}

fn at<'a>(document: &'a mut Value, path: &[Step]) -> Option<&'a mut Value> {
    path.iter().try_fold(document, |value, step| match step {
        Step::Key(key) => value.get_mut(key.as_str()),
        Step::Index(i) => value.get_mut(*i),
    })
}

/// A number that is likely an index out of range, at its edge, or not an index at all.
fn number(document: &Value, choices: &mut Choices) -> Value {
    let section = *choices.pick(&SECTIONS);
    let len = document.get(section).and_then(Value::as_array).map_or(0, Vec::len) as i64;
    match choices.below(12) {
        0 => json!(0),
        1 => json!(1),
        2 => json!(-1),
        3 => json!(len),
        4 => json!(len + 1),
        5 => json!(len - 1),
        6 => json!(255),
        7 => json!(65_535),
        8 => json!(4_294_967_295_u64),
        9 => json!(4_294_967_296_u64),
        10 => json!(1.5),
        _ => json!(choices.below(8)),
    }
}

/// A value of some type, most often not the one expected where it lands.
fn any_value(document: &Value, choices: &mut Choices) -> Value {
    match choices.below(10) {
        0 => json!("x"),
        1 => json!(choices.pick(&NAMES)),
        2 => json!(true),
        3 => Value::Null,
        4 => json!([]),
        5 => json!({}),
        6 => json!([0]),
        7 => json!([0, 1, 2, 3]),
        _ => number(document, choices),
    }
}

/// Applies one to four mutations to `document`; returns what was done, one line each.
pub fn mutate(document: &mut Value, choices: &mut Choices) -> Vec<String> {
    let rounds = 1 + choices.below(4);
    (0..rounds).filter_map(|_| mutate_once(document, choices)).collect()
}

fn mutate_once(document: &mut Value, choices: &mut Choices) -> Option<String> {
    let sites = sites(document);
    if sites.is_empty() {
        return None;
    }
    let path = choices.pick(&sites).clone();
    let snapshot = document.clone();
    let where_ = format!("{path:?}");
    let target = at(document, &path)?;
    let done = match (choices.below(8), &mut *target) {
        // A number nudged: off by one, doubled, halved, zeroed.
        (0, Value::Number(n)) => {
            let x = n.as_i64().unwrap_or(1);
            *target = json!(match choices.below(5) {
                0 => x + 1,
                1 => x - 1,
                2 => x.saturating_mul(2),
                3 => x / 2,
                _ => 0,
            });
            "nudged"
        }
        // A key deleted.
        (1, Value::Object(members)) if !members.is_empty() => {
            let keys: Vec<String> = members.keys().cloned().collect();
            members.remove(choices.pick(&keys));
            "key deleted"
        }
        // A key added (or replaced) with an index, a wrong type or a value from elsewhere.
        (2, Value::Object(_)) => {
            let key = *choices.pick(&KEYS);
            let value = if choices.below(2) == 0 {
                any_value(&snapshot, choices)
            } else {
                copy_from(&snapshot, choices)
            };
            target[key] = value;
            "key set"
        }
        // An array shortened, grown, emptied or reordered.
        (3, Value::Array(items)) if !items.is_empty() => {
            let i = choices.below(items.len());
            match choices.below(4) {
                0 => drop(items.remove(i)),
                1 => items.push(items[i].clone()),
                2 => items.clear(),
                _ => {
                    let j = choices.below(items.len());
                    items.swap(i, j);
                }
            }
            "array changed"
        }
        // A string swapped for another enumeration value.
        (4, Value::String(_)) => {
            *target = json!(choices.pick(&NAMES));
            "name swapped"
        }
        // A value copied from another place of the document.
        (5, _) => {
            *target = copy_from(&snapshot, choices);
            "copied"
        }
        // An index-like number.
        (6, _) => {
            *target = number(&snapshot, choices);
            "number"
        }
        // Anything of any type.
        _ => {
            *target = any_value(&snapshot, choices);
            "replaced"
        }
    };
    Some(format!("{done} at {where_}"))
}

/// A copy of the value at a random place of the document.
fn copy_from(document: &Value, choices: &mut Choices) -> Value {
    let sites = sites(document);
    let path: &Vec<Step> = choices.pick(&sites);
    let found = path.iter().try_fold(document, |value, step| match step {
        Step::Key(key) => value.get(key.as_str()),
        Step::Index(i) => value.get(*i),
    });
    found.cloned().unwrap_or(Value::Null)
}

/// What the binary's `fix` does with a loaded model, through the library: fix, the shared
/// copies, the seams in motion for every animation, skin seams matched, the report, posing
/// every object at two times of every animation, and writing through the pass-through (.glb
/// and .gltf) and the generic writer (.glb) into `out`. A step that returns an error ends
/// the work quietly: only a panic matters here.
pub fn use_asset(mut asset: seamlit_io::Asset, out: &Path) {
    if asset.model.triangle_count() > 0 {
        let options = seamlit_mesh::FixOptions::default();
        let Ok(copies) = seamlit_mesh::shared_copies(&asset.model, options.weld_tolerance) else {
            return;
        };
        let Ok(seams) = seamlit_mesh::seam_copies(&asset.model, &copies, &options) else {
            return;
        };
        if seamlit_mesh::fix_in_place(&mut asset.model, &options).is_err() {
            return;
        }
        for a in 0..asset.animations.len() {
            let _ = seamlit_io::motion::seam_motion(&asset, a, 3, &copies, &seams, 60.0);
        }
        let _ = seamlit_io::match_skin_seams(&mut asset, &copies);
        let _ = seamlit_mesh::report(&asset.model, &seamlit_mesh::ReportOptions::from(&options));
        let _ = seamlit_io::motion::morph_seams(&asset, &copies);
    }
    for a in 0..asset.animations.len() {
        let end = asset.animations[a].duration();
        for time in [0.0, end * 0.5] {
            let pose = seamlit_io::pose::Pose::at(&asset, a, time);
            for o in 0..asset.model.objects.len() {
                let _ = seamlit_io::pose::posed_object(&asset, &pose, o);
            }
        }
    }
    let save =
        seamlit_io::SaveOptions { overwrite_input: true, ..seamlit_io::SaveOptions::default() };
    let _ = seamlit_io::save(&asset, &out.join("pass.glb"), &save);
    let _ = seamlit_io::save(&asset, &out.join("pass.gltf"), &save);
    asset.document = None;
    let _ = seamlit_io::save(&asset, &out.join("generic.glb"), &save);
}

//! Where a glTF document names accessors and buffer views by index: the JSON pointers of
//! every such place that the specification and the extensions seamlit knows define, and
//! whether an extension it does not know could hold one. Pruning (`passthrough/prune.rs`)
//! needs every reference to renumber; the Draco decoder (`decode/draco.rs`) needs to know
//! whether anything else names a stream's buffer view.

use serde_json::Value;

use crate::json::index;

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

/// A place where a document names an accessor.
#[derive(Clone, Copy, Debug)]
pub(crate) enum AccessorSite<'a> {
    /// `meshes[mesh].primitives[primitive].attributes[name]`.
    Attribute { mesh: usize, primitive: usize, name: &'a str },
    /// `meshes[mesh].primitives[primitive].targets[target][name]`.
    Target { mesh: usize, primitive: usize, target: usize, name: &'a str },
    /// `nodes[node].extensions.EXT_mesh_gpu_instancing.attributes[name]`.
    Instancing { node: usize, name: &'a str },
    /// `meshes[mesh].primitives[primitive].indices`.
    Indices { mesh: usize, primitive: usize },
    /// `skins[skin].inverseBindMatrices`.
    InverseBindMatrices { skin: usize },
    /// `animations[animation].samplers[sampler].input` (`output` where not `input`).
    Sampler { animation: usize, sampler: usize, input: bool },
}

impl AccessorSite<'_> {
    /// The site's JSON pointer.
    pub(crate) fn pointer(self) -> String {
        match self {
            Self::Attribute { mesh, primitive, name } => {
                format!("/meshes/{mesh}/primitives/{primitive}/attributes/{}", token(name))
            }
            Self::Target { mesh, primitive, target, name } => {
                format!("/meshes/{mesh}/primitives/{primitive}/targets/{target}/{}", token(name))
            }
            Self::Instancing { node, name } => format!(
                "/nodes/{node}/extensions/EXT_mesh_gpu_instancing/attributes/{}",
                token(name)
            ),
            Self::Indices { mesh, primitive } => {
                format!("/meshes/{mesh}/primitives/{primitive}/indices")
            }
            Self::InverseBindMatrices { skin } => format!("/skins/{skin}/inverseBindMatrices"),
            Self::Sampler { animation, sampler, input } => {
                let end = if input { "input" } else { "output" };
                format!("/animations/{animation}/samplers/{sampler}/{end}")
            }
        }
    }
}

/// Every place the document names an accessor, in the order of [`accessor_sites`], each with
/// the value there (`Null` where a sampler lacks it).
pub(crate) fn each_accessor_site<'a>(
    document: &'a Value,
    mut f: impl FnMut(AccessorSite<'a>, &'a Value),
) {
    let members = |object: &'a Value| object.as_object().into_iter().flatten();
    for (m, mesh) in array(document, "meshes").iter().enumerate() {
        for (p, primitive) in array(mesh, "primitives").iter().enumerate() {
            for (name, value) in members(&primitive["attributes"]) {
                f(AccessorSite::Attribute { mesh: m, primitive: p, name }, value);
            }
            for (t, target) in array(primitive, "targets").iter().enumerate() {
                for (name, value) in members(target) {
                    f(AccessorSite::Target { mesh: m, primitive: p, target: t, name }, value);
                }
            }
        }
    }
    for (n, node) in array(document, "nodes").iter().enumerate() {
        let instancing = &node["extensions"]["EXT_mesh_gpu_instancing"]["attributes"];
        for (name, value) in members(instancing) {
            f(AccessorSite::Instancing { node: n, name }, value);
        }
    }
    for (m, mesh) in array(document, "meshes").iter().enumerate() {
        for (p, primitive) in array(mesh, "primitives").iter().enumerate() {
            if let Some(value) = primitive.get("indices") {
                f(AccessorSite::Indices { mesh: m, primitive: p }, value);
            }
        }
    }
    for (s, skin) in array(document, "skins").iter().enumerate() {
        if let Some(value) = skin.get("inverseBindMatrices") {
            f(AccessorSite::InverseBindMatrices { skin: s }, value);
        }
    }
    for (a, animation) in array(document, "animations").iter().enumerate() {
        for (s, sampler) in array(animation, "samplers").iter().enumerate() {
            f(AccessorSite::Sampler { animation: a, sampler: s, input: true }, &sampler["input"]);
            f(AccessorSite::Sampler { animation: a, sampler: s, input: false }, &sampler["output"]);
        }
    }
}

/// The JSON pointers of every place the document names an accessor by index.
pub(crate) fn accessor_sites(document: &Value) -> Vec<String> {
    let mut sites = Vec::new();
    each_accessor_site(document, |site, _| sites.push(site.pointer()));
    sites
}

/// A place where a document names a buffer view.
#[derive(Clone, Copy, Debug)]
pub(crate) enum ViewSite {
    /// `accessors[a].bufferView`.
    Accessor(usize),
    /// `accessors[a].sparse.indices.bufferView`, `accessors[a].sparse.values.bufferView`.
    SparseIndices(usize),
    SparseValues(usize),
    /// `images[i].bufferView`.
    Image(usize),
    /// `meshes[mesh].primitives[primitive].extensions.KHR_draco_mesh_compression.bufferView`.
    Draco {
        mesh: usize,
        primitive: usize,
    },
}

impl ViewSite {
    /// The site's JSON pointer.
    pub(crate) fn pointer(self) -> String {
        match self {
            Self::Accessor(a) => format!("/accessors/{a}/bufferView"),
            Self::SparseIndices(a) => format!("/accessors/{a}/sparse/indices/bufferView"),
            Self::SparseValues(a) => format!("/accessors/{a}/sparse/values/bufferView"),
            Self::Image(i) => format!("/images/{i}/bufferView"),
            Self::Draco { mesh, primitive } => format!(
                "/meshes/{mesh}/primitives/{primitive}/extensions/KHR_draco_mesh_compression/bufferView"
            ),
        }
    }

    /// The accessor it is a member of, where it is one's.
    pub(crate) fn accessor(self) -> Option<usize> {
        match self {
            Self::Accessor(a) | Self::SparseIndices(a) | Self::SparseValues(a) => Some(a),
            Self::Image(_) | Self::Draco { .. } => None,
        }
    }
}

/// Every place the document names a buffer view, in the order of [`view_sites`], each with
/// the value there (`Null` where a sparse part lacks it).
pub(crate) fn each_view_site(document: &Value, mut f: impl FnMut(ViewSite, &Value)) {
    for (a, accessor) in array(document, "accessors").iter().enumerate() {
        if let Some(value) = accessor.get("bufferView") {
            f(ViewSite::Accessor(a), value);
        }
        if let Some(sparse) = accessor.get("sparse") {
            f(ViewSite::SparseIndices(a), &sparse["indices"]["bufferView"]);
            f(ViewSite::SparseValues(a), &sparse["values"]["bufferView"]);
        }
    }
    for (i, image) in array(document, "images").iter().enumerate() {
        if let Some(value) = image.get("bufferView") {
            f(ViewSite::Image(i), value);
        }
    }
    for (m, mesh) in array(document, "meshes").iter().enumerate() {
        for (p, primitive) in array(mesh, "primitives").iter().enumerate() {
            if let Some(value) =
                primitive["extensions"]["KHR_draco_mesh_compression"].get("bufferView")
            {
                f(ViewSite::Draco { mesh: m, primitive: p }, value);
            }
        }
    }
}

/// The JSON pointers of every place the document names a buffer view by index.
pub(crate) fn view_sites(document: &Value) -> Vec<String> {
    let mut sites = Vec::new();
    each_view_site(document, |site, _| sites.push(site.pointer()));
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
pub(crate) fn array<'v>(value: &'v Value, key: &str) -> &'v [Value] {
    value.get(key).and_then(Value::as_array).map_or(&[], Vec::as_slice)
}

/// Which of `count` accessors the document names.
pub(crate) fn accessors_used(document: &Value, count: usize) -> Vec<bool> {
    let mut used = vec![false; count];
    each_accessor_site(document, |_, value| mark(&mut used, value));
    used
}

/// Which of `count` buffer views the document names.
pub(crate) fn views_used(document: &Value, count: usize) -> Vec<bool> {
    let mut used = vec![false; count];
    each_view_site(document, |_, value| mark(&mut used, value));
    used
}

/// Marks the entry `value` names, where it names one of `used`'s.
fn mark(used: &mut [bool], value: &Value) {
    if let Some(u) = index(value).and_then(|i| used.get_mut(i)) {
        *u = true;
    }
}

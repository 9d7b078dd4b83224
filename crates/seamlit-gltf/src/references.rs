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

/// The JSON pointers of every place the document names an accessor by index.
pub(crate) fn accessor_sites(document: &Value) -> Vec<String> {
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
pub(crate) fn view_sites(document: &Value) -> Vec<String> {
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
pub(crate) fn array<'v>(value: &'v Value, key: &str) -> &'v [Value] {
    value.get(key).and_then(Value::as_array).map_or(&[], Vec::as_slice)
}

/// Which of `count` entries the `sites` of `document` name.
pub(crate) fn used(document: &Value, sites: &[String], count: usize) -> Vec<bool> {
    let mut used = vec![false; count];
    for site in sites {
        let i = document.pointer(site).and_then(index);
        if let Some(u) = i.and_then(|i| used.get_mut(i)) {
            *u = true;
        }
    }
    used
}

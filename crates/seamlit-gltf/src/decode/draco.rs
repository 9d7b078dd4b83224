//! KHR_draco_mesh_compression (issue 11): a primitive whose geometry is a Draco stream in a
//! buffer view, its accessors carrying only `count`, `type`, `componentType` (and `min`,
//! `max`).
//!
//! With the `draco` feature (on by default), [`decode`] runs `draco-oxide-decoder` on each
//! such stream at load and makes the primitive plain: every attribute the extension's
//! `attributes` map names (by the stream's unique attribute id) and the indices become
//! ordinary data appended to buffer 0, the accessors pointing at new buffer views. The
//! primitive keeps the extension object in the document the loader keeps, so that the
//! pass-through writer sees the compressed view as used by the input: the writer removes the
//! extension from the output (`passthrough/uncompress.rs`), and pruning then drops the
//! compressed view and its bytes.
//!
//! The decoder is an alpha (`docs/gltf-pass-through.md`, "Quantised and compressed
//! geometry"), so nothing it returns is trusted: it runs inside
//! [`std::panic::catch_unwind`], and its result is checked (point counts, value indices,
//! component types and counts against the accessors, every index below the point count)
//! before a byte is used. Without the feature, [`refuse`] names the first Draco primitive
//! and a command that decompresses the file.

use std::path::Path;

use serde_json::Value;

use seamlit_asset::error::IoError;

/// The extension's name.
pub(crate) const DRACO: &str = "KHR_draco_mesh_compression";

/// The JSON path of primitive `(m, p)`'s extension object, for errors.
pub(crate) fn extension_path(m: usize, p: usize) -> String {
    format!("meshes[{m}].primitives[{p}].extensions.{DRACO}")
}

/// Every `(mesh, primitive)` that carries the extension, in document order.
pub(crate) fn draco_primitives(document: &Value) -> Vec<(usize, usize)> {
    let meshes = document["meshes"].as_array().map_or(&[][..], Vec::as_slice);
    let mut found = Vec::new();
    for (m, mesh) in meshes.iter().enumerate() {
        let primitives = mesh["primitives"].as_array().map_or(&[][..], Vec::as_slice);
        for (p, primitive) in primitives.iter().enumerate() {
            if primitive["extensions"].get(DRACO).is_some() {
                found.push((m, p));
            }
        }
    }
    found
}

/// Refuses a document with a Draco-compressed primitive (the build without the `draco`
/// feature), naming the first such primitive and a command that decompresses the file.
///
/// # Errors
///
/// [`IoError::Gltf`] at `meshes[m].primitives[p].extensions.KHR_draco_mesh_compression`.
#[cfg_attr(
    all(feature = "draco", not(test)),
    expect(dead_code, reason = "the refusal of the build without the `draco` feature")
)]
pub(crate) fn refuse(document: &Value, path: &Path) -> Result<(), IoError> {
    match draco_primitives(document).first() {
        Some(&(m, p)) => Err(IoError::Gltf {
            path: path.to_path_buf(),
            place: extension_path(m, p),
            kind: seamlit_asset::error::gltf::GltfKind::NoDracoDecoder { file: path.to_path_buf() },
        }),
        None => Ok(()),
    }
}

#[cfg(feature = "draco")]
pub(crate) use decoder::decode;

#[cfg(feature = "draco")]
mod decoder {
    use std::path::Path;

    use draco_oxide_core::attribute::{Attribute, ComponentDataType};
    use draco_oxide_core::mesh::Mesh;
    use serde_json::{Value, json};

    use super::{DRACO, draco_primitives, extension_path};
    use crate::json::{
        BYTE, FLOAT, SHORT, UNSIGNED_BYTE, UNSIGNED_INT, UNSIGNED_SHORT, shape, usize_member,
    };
    use seamlit_asset::error::IoError;
    use seamlit_asset::error::gltf::{Draco, GltfKind};

    /// One accessor the stream fills: the attribute's name (`indices` for the indices), its
    /// Draco unique id (`None` for the indices) and what the accessor declares.
    struct Target {
        name: String,
        accessor: usize,
        id: Option<usize>,
        count: usize,
        components: usize,
        component_type: u64,
    }

    /// Decoded data for one accessor: its elements' bytes, tightly packed or, where an
    /// element is not a multiple of 4 bytes, padded to `stride`.
    struct Plain {
        accessor: usize,
        bytes: Vec<u8>,
        stride: Option<usize>,
        indices: bool,
    }

    /// Decodes every Draco primitive of `json`: the decoded data is appended to buffer 0
    /// (`buffers[0]`, cut to its `byteLength` first) as buffer views, the primitives'
    /// accessors point at them. The first of a primitive's views takes the place of its
    /// stream's view where nothing else names that one (so the pass-through's pruning frees
    /// the stream's index for new data, and its bytes leave the buffer); the others are
    /// new (with `min` and `max` of the decoded values where the file
    /// gave them), and buffer 0's `byteLength` grows. Returns how many primitives were
    /// decoded. `max_elements` bounds every accessor's count before the decoder runs.
    ///
    /// # Errors
    ///
    /// [`IoError::Gltf`] at `meshes[m].primitives[p].extensions.KHR_draco_mesh_compression`
    /// when the stream is malformed (the decoder's error, or its panic), when it does not
    /// hold what the accessors declare, or when an accessor has data already (an
    /// uncompressed fallback); at `buffers[0]` when there is no buffer 0 with data to
    /// append to.
    pub(crate) fn decode(
        json: &mut Value,
        buffers: &mut [Vec<u8>],
        max_elements: usize,
        path: &Path,
    ) -> Result<usize, IoError> {
        let places = draco_primitives(json);
        if places.is_empty() {
            return Ok(0);
        }
        let host_length = usize_member(&json["buffers"][0], "byteLength").unwrap_or(0);
        let Some(host) = buffers.first().filter(|b| b.len() >= host_length) else {
            return Err(IoError::Gltf {
                path: path.to_path_buf(),
                place: "buffers[0]".to_owned(),
                kind: GltfKind::NoDracoHost,
            });
        };
        let mut host = host[..host_length].to_vec();
        for &(m, p) in &places {
            let error = |kind: Draco| IoError::Gltf {
                path: path.to_path_buf(),
                place: extension_path(m, p),
                kind: GltfKind::Draco(Box::new(kind)),
            };
            let plain = decode_primitive(json, (m, p), buffers, max_elements).map_err(error)?;
            let mut stream_view = stream_view_alone(json, (m, p));
            for piece in plain {
                append(json, &mut host, piece, stream_view.take());
            }
        }
        json["buffers"][0]["byteLength"] = json!(host.len());
        buffers[0] = host;
        Ok(places.len())
    }

    /// Decodes one primitive's stream into the data of its accessors.
    fn decode_primitive(
        json: &Value,
        (m, p): (usize, usize),
        buffers: &[Vec<u8>],
        max_elements: usize,
    ) -> Result<Vec<Plain>, Draco> {
        let primitive = &json["meshes"][m]["primitives"][p];
        let extension = &primitive["extensions"][DRACO];
        let stream = stream(json, extension, buffers)?;
        let targets = targets(json, primitive, extension, max_elements)?;
        let mesh = run_decoder(stream)?;
        let points = Points::of(&mesh)?;
        targets
            .iter()
            .map(|target| match target.id {
                Some(id) => attribute_data(&mesh, target, id, &points),
                None => index_data(&mesh, target, &points),
            })
            .collect()
    }

    /// The bytes of the stream's buffer view, checked to lie in their buffer.
    fn stream<'b>(
        json: &Value,
        extension: &Value,
        buffers: &'b [Vec<u8>],
    ) -> Result<&'b [u8], Draco> {
        let view_index =
            usize_member(extension, "bufferView").ok_or(Draco::Missing { member: "bufferView" })?;
        let view =
            json["bufferViews"].get(view_index).ok_or(Draco::NoSuchView { view: view_index })?;
        let buffer = usize_member(view, "buffer").unwrap_or(usize::MAX);
        let offset = usize_member(view, "byteOffset").unwrap_or(0);
        let length = usize_member(view, "byteLength").unwrap_or(0);
        buffers
            .get(buffer)
            .and_then(|b| b.get(offset..offset.checked_add(length)?))
            .ok_or(Draco::ViewOutside { view: view_index, buffer })
    }

    /// The accessors the stream fills: one per entry of the extension's `attributes` (the
    /// primitive's accessor of that name), then the indices. Each must be declared without
    /// data of its own and within `max_elements`.
    fn targets(
        json: &Value,
        primitive: &Value,
        extension: &Value,
        max_elements: usize,
    ) -> Result<Vec<Target>, Draco> {
        let ids =
            extension["attributes"].as_object().ok_or(Draco::Missing { member: "attributes" })?;
        let mut named: Vec<(String, Option<usize>, Option<usize>)> = Vec::new();
        for (name, id) in ids {
            let id = crate::json::index(id).ok_or_else(|| Draco::NotAnId { name: name.clone() })?;
            let accessor = usize_member(&primitive["attributes"], name)
                .ok_or_else(|| Draco::NotAnAttribute { name: name.clone() })?;
            named.push((name.clone(), Some(accessor), Some(id)));
        }
        named.push(("indices".to_owned(), usize_member(primitive, "indices"), None));
        let mut targets = Vec::with_capacity(named.len());
        for (name, accessor, id) in named {
            let accessor = accessor.ok_or(Draco::NoIndices)?;
            targets.push(target(json, name, accessor, id, max_elements)?);
        }
        Ok(targets)
    }

    /// What accessor `index` declares, checked.
    fn target(
        json: &Value,
        name: String,
        index: usize,
        id: Option<usize>,
        max_elements: usize,
    ) -> Result<Target, Draco> {
        let Some(accessor) = json["accessors"].get(index) else {
            return Err(Draco::NoSuchAccessor { name, accessor: index });
        };
        if accessor.get("bufferView").is_some() || accessor.get("sparse").is_some() {
            return Err(Draco::AccessorHasData { name, accessor: index });
        }
        let count = usize_member(accessor, "count").unwrap_or(0);
        if count > max_elements {
            return Err(Draco::TooManyElements {
                name,
                accessor: index,
                count,
                limit: max_elements,
            });
        }
        let Some((1, components)) = accessor["type"].as_str().and_then(shape) else {
            let found = accessor["type"].as_str().map(str::to_owned);
            return Err(Draco::AccessorType { name, accessor: index, found });
        };
        let component_type = usize_member(accessor, "componentType").unwrap_or(0) as u64;
        Ok(Target { name, accessor: index, id, count, components, component_type })
    }

    /// Runs the decoder; its error or its panic becomes the reason.
    fn run_decoder(stream: &[u8]) -> Result<Mesh, Draco> {
        match std::panic::catch_unwind(|| draco_oxide_decoder::decode_mesh(stream)) {
            Ok(Ok(mesh)) => Ok(mesh),
            Ok(Err(e)) => Err(Draco::Malformed { source: Box::new(e) }),
            Err(_) => Err(Draco::DecoderPanicked),
        }
    }

    /// The glTF vertices of a decoded mesh. The decoder may give several points that name
    /// the same value of every attribute, where Draco's reference decoder (which the
    /// files' accessor counts follow) has one point: they are merged, the first of each
    /// kept, in point order. (Points whose values are equal but are different values of an
    /// attribute, on both sides of a seam, stay apart, as in the reference decoder.)
    struct Points {
        /// Per vertex: the point it is made of.
        first: Vec<usize>,
        /// Per point: its vertex.
        vertex: Vec<usize>,
    }

    impl Points {
        /// # Errors
        ///
        /// When the attributes cover different numbers of points, or a point names a value
        /// its attribute lacks.
        fn of(mesh: &Mesh) -> Result<Self, Draco> {
            let attributes = mesh.get_attributes();
            let points = attributes.first().map_or(0, |a| a.len());
            if let Some(a) = attributes.iter().find(|a| a.len() != points) {
                return Err(Draco::PointCounts {
                    attribute: a.get_id().as_usize(),
                    points: a.len(),
                    first: attributes[0].get_id().as_usize(),
                    first_points: points,
                });
            }
            let mut seen = std::collections::HashMap::with_capacity(points);
            let (mut first, mut vertex) = (Vec::new(), Vec::with_capacity(points));
            for point in 0..points {
                let mut key = Vec::with_capacity(attributes.len());
                for attribute in attributes {
                    value(attribute, point)?;
                    key.push(value_index(attribute, point));
                }
                let next = first.len();
                let v = *seen.entry(key).or_insert(next);
                if v == next {
                    first.push(point);
                }
                vertex.push(v);
            }
            Ok(Self { first, vertex })
        }
    }

    /// The index of `point`'s value in a decoded attribute (`None` past its point map).
    fn value_index(attribute: &Attribute, point: usize) -> Option<usize> {
        match attribute.point_map_as_slice() {
            Some(map) => map.get(point).map(|&v| usize::from(v)),
            None => Some(point),
        }
    }

    /// The bytes of `point`'s value in a decoded attribute.
    fn value(attribute: &Attribute, point: usize) -> Result<&[u8], Draco> {
        let size = attribute.get_num_components() * attribute.get_component_type().size();
        value_index(attribute, point)
            .and_then(|v| {
                let start = v.checked_mul(size)?;
                attribute.get_data_as_bytes().get(start..start.checked_add(size)?)
            })
            .ok_or_else(|| Draco::NoValue { point, attribute: attribute.get_id().as_usize() })
    }

    /// glTF's component type of a decoded component type, where glTF has one.
    fn gltf_component_type(t: ComponentDataType) -> Option<u64> {
        match t {
            ComponentDataType::I8 => Some(BYTE),
            ComponentDataType::U8 => Some(UNSIGNED_BYTE),
            ComponentDataType::I16 => Some(SHORT),
            ComponentDataType::U16 => Some(UNSIGNED_SHORT),
            ComponentDataType::U32 => Some(UNSIGNED_INT),
            ComponentDataType::F32 => Some(FLOAT),
            _ => None,
        }
    }

    /// The decoded attribute `id` as the accessor's elements, one per vertex: its count,
    /// component count and type must be the accessor's.
    fn attribute_data(
        mesh: &Mesh,
        target: &Target,
        id: usize,
        points: &Points,
    ) -> Result<Plain, Draco> {
        let name = &target.name;
        let attribute = mesh
            .get_attributes()
            .iter()
            .find(|a| a.get_id().as_usize() == id)
            .ok_or_else(|| Draco::NoSuchId { name: name.clone(), id })?;
        let decoded_type = attribute.get_component_type();
        let count = points.first.len();
        if count != target.count
            || attribute.get_num_components() != target.components
            || gltf_component_type(decoded_type) != Some(target.component_type)
        {
            return Err(Draco::AttributeMismatch {
                name: name.clone(),
                count,
                components: attribute.get_num_components(),
                component: format!("{decoded_type:?}"),
                accessor: target.accessor,
                declared: target.count,
                declared_components: target.components,
                component_type: target.component_type,
            });
        }
        let size = target.components * decoded_type.size();
        let stride = size.next_multiple_of(4);
        let mut bytes = Vec::with_capacity(stride * count);
        for &point in &points.first {
            bytes.extend_from_slice(value(attribute, point)?);
            bytes.resize(bytes.len() + stride - size, 0);
        }
        let stride = (stride != size).then_some(stride);
        Ok(Plain { accessor: target.accessor, bytes, stride, indices: false })
    }

    /// The decoded faces as the indices accessor's elements: three per face, each naming a
    /// vertex, within the accessor's component type.
    fn index_data(mesh: &Mesh, target: &Target, points: &Points) -> Result<Plain, Draco> {
        let mut corners = Vec::with_capacity(mesh.get_faces().len() * 3);
        for &point in mesh.get_faces().iter().flatten() {
            let point = usize::from(point);
            let vertex = points
                .vertex
                .get(point)
                .ok_or(Draco::NoSuchPoint { point, points: points.vertex.len() })?;
            corners.push(*vertex);
        }
        if corners.len() != target.count || target.components != 1 {
            return Err(Draco::CornerCount {
                corners: corners.len(),
                accessor: target.accessor,
                declared: target.count,
            });
        }
        let limit = match target.component_type {
            UNSIGNED_BYTE => usize::from(u8::MAX),
            UNSIGNED_SHORT => usize::from(u16::MAX),
            UNSIGNED_INT => u32::MAX as usize,
            other => {
                return Err(Draco::IndexType { accessor: target.accessor, component_type: other });
            }
        };
        if points.first.len() > limit {
            return Err(Draco::IndicesTooNarrow {
                vertices: points.first.len(),
                component_type: target.component_type,
            });
        }
        #[expect(clippy::cast_possible_truncation, reason = "every corner fits, checked above")]
        let bytes: Vec<u8> = match target.component_type {
            UNSIGNED_BYTE => corners.iter().map(|&c| c as u8).collect(),
            UNSIGNED_SHORT => corners.iter().flat_map(|&c| (c as u16).to_le_bytes()).collect(),
            _ => corners.iter().flat_map(|&c| (c as u32).to_le_bytes()).collect(),
        };
        Ok(Plain { accessor: target.accessor, bytes, stride: None, indices: true })
    }

    /// The index of primitive `(m, p)`'s stream view when only that primitive names it, in a
    /// document whose every reference to a view is known.
    fn stream_view_alone(json: &Value, (m, p): (usize, usize)) -> Option<usize> {
        let view =
            usize_member(&json["meshes"][m]["primitives"][p]["extensions"][DRACO], "bufferView")?;
        let known = crate::references::unknown_extensions(json).is_empty();
        (known && crate::references::view_uses(json, view) == 1).then_some(view)
    }

    /// Appends one accessor's data to `host` (buffer 0) as a buffer view (in place of view
    /// `into`, or a new one) and points the accessor at it; its `min` and `max`, where
    /// present, become the decoded values'.
    fn append(json: &mut Value, host: &mut Vec<u8>, plain: Plain, into: Option<usize>) {
        host.resize(host.len().next_multiple_of(4), 0);
        let mut view = json!({
            "buffer": 0,
            "byteOffset": host.len(),
            "byteLength": plain.bytes.len(),
            "target": if plain.indices { 34963 } else { 34962 },
        });
        if let Some(stride) = plain.stride {
            view["byteStride"] = json!(stride);
        }
        host.extend_from_slice(&plain.bytes);
        let views = json["bufferViews"].as_array_mut().expect("the stream's view is in it");
        let view = match into {
            Some(into) => {
                views[into] = view;
                into
            }
            None => {
                views.push(view);
                views.len() - 1
            }
        };
        let accessor = &mut json["accessors"][plain.accessor];
        if accessor.get("min").is_some() || accessor.get("max").is_some() {
            let (min, max) = bounds(accessor, &plain);
            accessor["min"] = min;
            accessor["max"] = max;
        }
        if let Some(accessor) = accessor.as_object_mut() {
            accessor.remove("byteOffset");
            accessor.insert("bufferView".to_owned(), json!(view));
        }
    }

    /// Per component, the least and greatest decoded value of an accessor's data.
    fn bounds(accessor: &Value, plain: &Plain) -> (Value, Value) {
        let component_type = usize_member(accessor, "componentType").unwrap_or(0) as u64;
        let (size, read): (usize, fn(&[u8]) -> f64) = match component_type {
            BYTE => (1, |b| f64::from(b[0].cast_signed())),
            UNSIGNED_BYTE => (1, |b| f64::from(b[0])),
            SHORT => (2, |b| f64::from(i16::from_le_bytes([b[0], b[1]]))),
            UNSIGNED_SHORT => (2, |b| f64::from(u16::from_le_bytes([b[0], b[1]]))),
            UNSIGNED_INT => (4, |b| f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))),
            _ => (4, |b| f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]]))),
        };
        let components = match accessor["type"].as_str().and_then(shape) {
            Some((1, components)) => components,
            _ => 1,
        };
        let stride = plain.stride.unwrap_or(size * components);
        let mut min = vec![f64::INFINITY; components];
        let mut max = vec![f64::NEG_INFINITY; components];
        for element in plain.bytes.chunks_exact(stride) {
            for c in 0..components {
                let x = read(&element[c * size..]);
                min[c] = min[c].min(x);
                max[c] = max[c].max(x);
            }
        }
        let number = |x: f64| match component_type {
            FLOAT => json!(x),
            #[expect(
                clippy::cast_possible_truncation,
                reason = "an integer component, read as f64"
            )]
            _ => json!(x as i64),
        };
        (min.into_iter().map(number).collect(), max.into_iter().map(number).collect())
    }
}

#[cfg(test)]
mod tests {
    use serde_json::json;

    use super::*;
    use seamlit_asset::GltfKind;

    #[test]
    fn the_refusal_names_the_first_draco_primitive_and_a_way_out() {
        let document = json!({ "meshes": [
            { "primitives": [{ "attributes": {} }] },
            { "primitives": [
                { "attributes": {} },
                { "attributes": {}, "extensions": { DRACO: { "bufferView": 0, "attributes": {} } } },
            ] },
        ] });
        let path = Path::new("model.glb");
        let Err(error) = refuse(&document, path) else { panic!("not refused") };
        let IoError::Gltf { path: named, place, kind: GltfKind::NoDracoDecoder { file } } = &error
        else {
            panic!("{error:?}");
        };
        assert_eq!((named.as_path(), file.as_path()), (path, path));
        assert_eq!(place, "meshes[1].primitives[1].extensions.KHR_draco_mesh_compression");
        // What the user reads: the way out, with the file's name.
        let message = error.to_string();
        assert!(message.contains("`draco` feature"), "{message}");
        assert!(message.contains("gltf-transform/cli copy model.glb"), "{message}");
        refuse(&json!({ "meshes": [{ "primitives": [{ "attributes": {} }] }] }), path).unwrap();
    }
}

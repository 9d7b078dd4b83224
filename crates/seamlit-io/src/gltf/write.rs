//! glTF 2.0 and GLB out, through gltf-json.
//!
//! Each object becomes a mesh of one triangle primitive (POSITION with min/max, NORMAL,
//! TANGENT, TEXCOORD_0 and _1, COLOR_0 as RGBA floats, indices as u16 where every index fits
//! below 65535, else u32, and the morph targets' POSITION, NORMAL and TANGENT deltas) named
//! after the object. The node hierarchy of the asset is rebuilt when it is consistent with
//! the objects' transforms (a node carrying several objects gets one child node per object);
//! otherwise each object gets a root node with its transform. Materials and the textures
//! they use are carried through: embedded in a GLB, written beside a `.gltf` (whose buffer
//! goes to `NAME.bin` beside it too).
//!
//! The glTF validator rejects non-unit normals and tangents and tangent signs other than
//! +-1: such values (only such) are normalised on the way out, a zero vector becoming +Z
//! (normal) or +X (tangent). Texture coordinates are flipped (`v' = 1 - v`) when the model's V
//! runs up (OBJ, Newell), since glTF's runs down.

use std::collections::{BTreeMap, HashMap};
use std::io::Write;
use std::path::Path;

use glam::{Mat4, Quat, Vec2, Vec3, Vec4};
use gltf_json as json;
use json::validation::{Checked, USize64};
use seamlit_mesh::{Object, VAxis};

use crate::asset::{Asset, Material, TextureRef, UvTransform};
use crate::check::{check_object, unit_normal, unit_tangent};
use crate::error::{InvalidAsset, IoError};
use crate::files::safe_name;
use crate::texture::encoded;

/// Writes `asset` as `.glb` (`binary`) or `.gltf` (+ `.bin` and images beside it).
///
/// The binary buffer is never assembled in memory: the JSON is built first with every buffer
/// view's offset computed from the lengths, then the vertex and index data are streamed from
/// the objects to the file (after the JSON chunk in a GLB, into `NAME.bin` beside a `.gltf`).
pub(crate) fn save(asset: &Asset, path: &Path, binary: bool) -> Result<(), IoError> {
    for object in &asset.model.objects {
        check_object(object, path)?;
    }
    // glTF's indices are 32-bit: the nodes written (the asset's, or one per object) too.
    let nodes = asset.nodes.len() + asset.model.objects.len();
    if nodes >= u32::MAX as usize {
        return Err(IoError::TooManyElements {
            path: path.to_path_buf(),
            what: "the asset's nodes and objects".to_owned(),
            limit: u32::MAX as usize - 1,
            actual: nodes,
        });
    }
    let stem =
        path.file_stem().map_or_else(|| "model".to_owned(), |s| safe_name(&s.to_string_lossy()));
    let mut writer = Writer {
        root: json::Root::default(),
        pieces: Vec::new(),
        bin_len: 0,
        side_files: Vec::new(),
        path,
        binary,
        stem,
    };
    writer.root.asset = json::Asset {
        generator: Some("seamlit".to_owned()),
        version: "2.0".to_owned(),
        ..Default::default()
    };

    let textures = writer.textures(asset)?;
    for material in &asset.materials {
        let m = writer.material(material, &textures);
        writer.root.push(m);
    }
    let meshes: Vec<json::Index<json::Mesh>> = asset
        .model
        .objects
        .iter()
        .map(|o| writer.mesh(o, asset.model.v_axis, asset.materials.len()))
        .collect();
    writer.nodes(asset, &meshes);

    let bin_uri = (!binary && writer.bin_len > 0).then(|| format!("{}.bin", writer.stem));
    if writer.bin_len > 0 {
        let buffer = json::Buffer {
            byte_length: USize64::from(writer.bin_len),
            name: None,
            uri: bin_uri.clone(),
            extensions: None,
            extras: Default::default(),
        };
        writer.root.push(buffer);
    }
    let json_bytes =
        serde_json::to_vec_pretty(&writer.root).map_err(|e| IoError::InvalidAsset {
            path: path.to_path_buf(),
            object: String::new(),
            kind: InvalidAsset::Json { source: e },
        })?;
    let folder = path.parent().unwrap_or(Path::new(""));
    for (name, bytes) in &writer.side_files {
        crate::files::write(&folder.join(name), bytes)?;
    }
    if let Some(uri) = bin_uri {
        crate::files::write_with(&folder.join(uri), |out| writer.write_bin(out))?;
    }
    if !binary {
        return crate::files::write(path, &json_bytes);
    }
    let bin = (writer.bin_len > 0).then_some(writer.bin_len);
    crate::gltf::glb::write(path, json_bytes, bin, |out| writer.write_bin(out))
}

/// A part of the binary buffer, written from the asset when the file is written.
enum BinPart<'a> {
    /// Vertex positions (and morph targets' deltas), as they are.
    Positions(&'a [Vec3]),
    /// Normals, made unit length ([`unit_normal`]).
    Normals(&'a [Vec3]),
    /// Tangents, made unit length with w = +-1 ([`unit_tangent`]).
    Tangents(&'a [Vec4]),
    /// Vertex colours, linear RGBA, as they are.
    Colors(&'a [Vec4]),
    /// Texture coordinates, V flipped (`1 - v`) when `flip` is set.
    Uvs { uvs: &'a [Vec2], flip: bool },
    /// Triangle indices as u16 (every index is below 65535).
    Indices16(&'a [[u32; 3]]),
    /// Triangle indices as u32.
    Indices32(&'a [[u32; 3]]),
    /// An encoded image.
    Bytes(Vec<u8>),
}

impl BinPart<'_> {
    /// Bytes this piece takes.
    fn len(&self) -> usize {
        match self {
            Self::Positions(v) | Self::Normals(v) => v.len() * 12,
            Self::Tangents(v) | Self::Colors(v) => v.len() * 16,
            Self::Uvs { uvs, .. } => uvs.len() * 8,
            Self::Indices16(t) => t.len() * 6,
            Self::Indices32(t) => t.len() * 12,
            Self::Bytes(b) => b.len(),
        }
    }

    /// Writes the piece, little-endian.
    fn write(&self, out: &mut dyn Write) -> std::io::Result<()> {
        fn floats<const N: usize>(out: &mut dyn Write, v: [f32; N]) -> std::io::Result<()> {
            let mut bytes = [[0u8; 4]; N];
            for (b, x) in bytes.iter_mut().zip(v) {
                *b = x.to_le_bytes();
            }
            out.write_all(bytes.as_flattened())
        }
        match self {
            Self::Positions(v) => v.iter().try_for_each(|p| floats(out, p.to_array())),
            Self::Normals(v) => v.iter().try_for_each(|&n| floats(out, unit_normal(n).to_array())),
            Self::Tangents(v) => {
                v.iter().try_for_each(|&t| floats(out, unit_tangent(t).to_array()))
            }
            Self::Colors(v) => v.iter().try_for_each(|c| floats(out, c.to_array())),
            Self::Uvs { uvs, flip } => {
                uvs.iter().try_for_each(|t| floats(out, [t.x, if *flip { 1.0 - t.y } else { t.y }]))
            }
            Self::Indices16(triangles) => triangles.iter().try_for_each(|t| {
                // Every index is below 65535, checked by the caller.
                #[expect(clippy::cast_possible_truncation, reason = "below 65535, checked")]
                let [[a0, a1], [b0, b1], [c0, c1]] = t.map(|i| (i as u16).to_le_bytes());
                out.write_all(&[a0, a1, b0, b1, c0, c1])
            }),
            Self::Indices32(triangles) => triangles
                .iter()
                .try_for_each(|t| out.write_all(t.map(u32::to_le_bytes).as_flattened())),
            Self::Bytes(bytes) => out.write_all(bytes),
        }
    }
}

struct Writer<'a> {
    root: json::Root,
    /// The binary buffer's contents in order, each starting at a multiple of 4 bytes.
    pieces: Vec<BinPart<'a>>,
    /// The binary buffer's length so far.
    bin_len: usize,
    /// Files to write beside a `.gltf`: (file name, bytes).
    side_files: Vec<(String, Vec<u8>)>,
    path: &'a Path,
    binary: bool,
    stem: String,
}

impl<'a> Writer<'a> {
    /// Appends a piece to the binary buffer (4-byte aligned) as a buffer view.
    fn view(
        &mut self,
        piece: BinPart<'a>,
        target: Option<json::buffer::Target>,
    ) -> json::Index<json::buffer::View> {
        let offset = self.bin_len.next_multiple_of(4);
        let length = piece.len();
        self.bin_len = offset + length;
        self.pieces.push(piece);
        self.root.push(json::buffer::View {
            buffer: json::Index::new(0),
            byte_length: USize64::from(length),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            name: None,
            target: target.map(Checked::Valid),
            extensions: None,
            extras: Default::default(),
        })
    }

    /// Writes the binary buffer: every piece, each padded with zeros to a multiple of 4.
    fn write_bin(&self, out: &mut dyn Write) -> std::io::Result<()> {
        let mut written = 0usize;
        for piece in &self.pieces {
            let padding = written.next_multiple_of(4) - written;
            out.write_all(&[0; 3][..padding])?;
            piece.write(out)?;
            written += padding + piece.len();
        }
        debug_assert_eq!(written, self.bin_len);
        Ok(())
    }

    fn accessor(
        &mut self,
        piece: BinPart<'a>,
        count: usize,
        component: json::accessor::ComponentType,
        type_: json::accessor::Type,
        target: json::buffer::Target,
        min_max: Option<(Vec<f32>, Vec<f32>)>,
    ) -> json::Index<json::Accessor> {
        let view = self.view(piece, Some(target));
        let (min, max) = match min_max {
            Some((min, max)) => (
                Some(json::Value::from(min.iter().map(|&x| f64::from(x)).collect::<Vec<_>>())),
                Some(json::Value::from(max.iter().map(|&x| f64::from(x)).collect::<Vec<_>>())),
            ),
            None => (None, None),
        };
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(count),
            component_type: Checked::Valid(json::accessor::GenericComponentType(component)),
            extensions: None,
            extras: Default::default(),
            type_: Checked::Valid(type_),
            min,
            max,
            name: None,
            normalized: false,
            sparse: None,
        })
    }

    /// A float vertex attribute of `count` elements.
    fn float_accessor(
        &mut self,
        piece: BinPart<'a>,
        count: usize,
        type_: json::accessor::Type,
        min_max: Option<(Vec<f32>, Vec<f32>)>,
    ) -> json::Index<json::Accessor> {
        self.accessor(
            piece,
            count,
            json::accessor::ComponentType::F32,
            type_,
            json::buffer::Target::ArrayBuffer,
            min_max,
        )
    }

    fn mesh(
        &mut self,
        object: &'a Object,
        v_axis: VAxis,
        material_count: usize,
    ) -> json::Index<json::Mesh> {
        use json::accessor::Type;
        use json::mesh::Semantic;
        let mut attributes = BTreeMap::new();
        let n = object.positions.len();
        let (min, max) = object
            .positions
            .iter()
            .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| (lo.min(p), hi.max(p)));
        let bounds = Some((min.to_array().to_vec(), max.to_array().to_vec()));
        attributes.insert(
            Checked::Valid(Semantic::Positions),
            self.float_accessor(BinPart::Positions(&object.positions), n, Type::Vec3, bounds),
        );
        if let Some(normals) = &object.normals {
            attributes.insert(
                Checked::Valid(Semantic::Normals),
                self.float_accessor(BinPart::Normals(normals), n, Type::Vec3, None),
            );
            // TANGENT requires NORMAL.
            if let Some(tangents) = &object.tangents {
                attributes.insert(
                    Checked::Valid(Semantic::Tangents),
                    self.float_accessor(BinPart::Tangents(tangents), n, Type::Vec4, None),
                );
            }
        }
        for (set, uvs) in [(0, &object.uvs), (1, &object.uvs1)] {
            if let Some(uvs) = uvs {
                let piece = BinPart::Uvs { uvs, flip: v_axis == VAxis::Up };
                attributes.insert(
                    Checked::Valid(Semantic::TexCoords(set)),
                    self.float_accessor(piece, n, Type::Vec2, None),
                );
            }
        }
        if let Some(colors) = &object.colors {
            attributes.insert(
                Checked::Valid(Semantic::Colors(0)),
                self.float_accessor(BinPart::Colors(colors), n, Type::Vec4, None),
            );
        }
        let count = object.triangles.len() * 3;
        let (piece, component) = if n <= usize::from(u16::MAX) {
            (BinPart::Indices16(&object.triangles), json::accessor::ComponentType::U16)
        } else {
            (BinPart::Indices32(&object.triangles), json::accessor::ComponentType::U32)
        };
        let indices = self.accessor(
            piece,
            count,
            component,
            Type::Scalar,
            json::buffer::Target::ElementArrayBuffer,
            None,
        );
        let primitive = json::mesh::Primitive {
            attributes,
            extensions: None,
            extras: Default::default(),
            indices: Some(indices),
            material: object
                .material
                .filter(|&m| m < material_count)
                .and_then(|m| u32::try_from(m).ok())
                .map(json::Index::new),
            mode: Checked::Valid(json::mesh::Mode::Triangles),
            targets: self.morph_targets(object),
        };
        self.root.push(json::Mesh {
            extensions: None,
            extras: Default::default(),
            name: Some(object.name.clone()),
            primitives: vec![primitive],
            weights: None,
        })
    }

    /// The morph targets of an object: POSITION deltas (with the bounds the specification
    /// requires), and NORMAL and TANGENT deltas where every target has them (the attributes of
    /// all targets of a primitive are the same).
    fn morph_targets(&mut self, object: &'a Object) -> Option<Vec<json::mesh::MorphTarget>> {
        use json::accessor::Type;
        let targets = &object.morph_targets;
        if targets.is_empty() {
            return None;
        }
        let normals = object.normals.is_some() && targets.iter().all(|t| t.normal_deltas.is_some());
        let tangents = normals
            && object.tangents.is_some()
            && targets.iter().all(|t| t.tangent_deltas.is_some());
        let n = object.positions.len();
        let mut deltas = |values: Option<&'a [Vec3]>, wanted: bool, bounded: bool| {
            let values = values.filter(|_| wanted)?;
            let bounds = bounded.then(|| {
                let (min, max) =
                    values.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| {
                        (lo.min(p), hi.max(p))
                    });
                (min.to_array().to_vec(), max.to_array().to_vec())
            });
            Some(self.float_accessor(BinPart::Positions(values), n, Type::Vec3, bounds))
        };
        let out = targets
            .iter()
            .map(|target| json::mesh::MorphTarget {
                positions: deltas(Some(&target.position_deltas), n > 0, true),
                normals: deltas(target.normal_deltas.as_deref(), normals, false),
                tangents: deltas(target.tangent_deltas.as_deref(), tangents, false),
            })
            .collect();
        Some(out)
    }

    /// The node hierarchy: the asset's own when it matches the objects, else flat.
    fn nodes(&mut self, asset: &Asset, meshes: &[json::Index<json::Mesh>]) {
        let mut roots = Vec::new();
        if hierarchy_matches(asset) {
            let base = self.root.nodes.len();
            for node in &asset.nodes {
                let mut json_node = node_with_transform(node.local_transform);
                json_node.name = (!node.name.is_empty()).then(|| node.name.clone());
                if let [object] = node.objects[..] {
                    // Named after the object, so that it reads back under the same name.
                    json_node.name = Some(asset.model.objects[object].name.clone());
                    json_node.mesh = Some(meshes[object]);
                }
                self.root.push(json_node);
            }
            let mut children: Vec<Vec<json::Index<json::Node>>> =
                vec![Vec::new(); asset.nodes.len()];
            for (i, node) in asset.nodes.iter().enumerate() {
                #[expect(
                    clippy::cast_possible_truncation,
                    reason = "fewer nodes than u32::MAX, checked in `save`"
                )]
                let index = json::Index::new((base + i) as u32);
                match node.parent {
                    Some(parent) => children[parent].push(index),
                    None => roots.push(index),
                }
                if node.objects.len() > 1 {
                    for &object in &node.objects {
                        let mut child = node_with_transform(Mat4::IDENTITY);
                        child.name = Some(asset.model.objects[object].name.clone());
                        child.mesh = Some(meshes[object]);
                        children[i].push(self.root.push(child));
                    }
                }
            }
            for (i, list) in children.into_iter().enumerate() {
                if !list.is_empty() {
                    self.root.nodes[base + i].children = Some(list);
                }
            }
        } else {
            for (object, &mesh) in asset.model.objects.iter().zip(meshes) {
                let mut node = node_with_transform(object.model_transform());
                node.name = Some(object.name.clone());
                node.mesh = Some(mesh);
                roots.push(self.root.push(node));
            }
        }
        let scene = self.root.push(json::Scene {
            extensions: None,
            extras: Default::default(),
            name: None,
            nodes: roots,
        });
        self.root.scene = Some(scene);
    }

    /// Images, textures and one sampler for the textures that materials use and whose bytes
    /// are available; returns, per asset texture, its glTF texture index.
    fn textures(
        &mut self,
        asset: &'a Asset,
    ) -> Result<Vec<Option<json::Index<json::Texture>>>, IoError> {
        let used: Vec<bool> = (0..asset.textures.len())
            .map(|i| {
                asset.materials.iter().any(|m| {
                    [&m.base_color_texture, &m.normal_texture]
                        .into_iter()
                        .flatten()
                        .any(|r| r.texture == i)
                })
            })
            .collect();
        let mut out = vec![None; asset.textures.len()];
        let mut sampler = None;
        let mut names: HashMap<String, usize> = HashMap::new();
        for (i, texture) in asset.textures.iter().enumerate() {
            if !used[i] {
                continue;
            }
            let Some((bytes, mime)) = encoded(texture, self.path)? else { continue };
            let image = if self.binary {
                let view = self.view(BinPart::Bytes(bytes), None);
                json::Image {
                    buffer_view: Some(view),
                    mime_type: Some(json::image::MimeType(mime.to_owned())),
                    name: Some(texture.name.clone()),
                    uri: None,
                    extensions: None,
                    extras: Default::default(),
                }
            } else {
                let extension = if mime == "image/png" { "png" } else { "jpg" };
                let base = Path::new(&texture.name)
                    .file_stem()
                    .map_or_else(|| format!("texture{i}"), |s| s.to_string_lossy().into_owned());
                let base = format!("{}_{}", self.stem, safe_name(&base));
                let n = names.entry(base.clone()).or_default();
                let file = if *n == 0 {
                    format!("{base}.{extension}")
                } else {
                    format!("{base}_{n}.{extension}")
                };
                *n += 1;
                self.side_files.push((file.clone(), bytes));
                json::Image {
                    buffer_view: None,
                    mime_type: None,
                    name: Some(texture.name.clone()),
                    uri: Some(file),
                    extensions: None,
                    extras: Default::default(),
                }
            };
            let image = self.root.push(image);
            let sampler = *sampler.get_or_insert_with(|| {
                self.root.push(json::texture::Sampler {
                    mag_filter: Some(Checked::Valid(json::texture::MagFilter::Linear)),
                    min_filter: Some(Checked::Valid(json::texture::MinFilter::LinearMipmapLinear)),
                    ..Default::default()
                })
            });
            out[i] = Some(self.root.push(json::Texture {
                name: None,
                sampler: Some(sampler),
                source: image,
                extensions: None,
                extras: Default::default(),
            }));
        }
        Ok(out)
    }

    fn material(
        &mut self,
        m: &Material,
        textures: &[Option<json::Index<json::Texture>>],
    ) -> json::Material {
        fn lookup<'r>(
            r: &'r Option<TextureRef>,
            textures: &[Option<json::Index<json::Texture>>],
        ) -> Option<(json::Index<json::Texture>, &'r TextureRef)> {
            r.as_ref().and_then(|r| textures.get(r.texture).copied().flatten().map(|t| (t, r)))
        }
        let base_color_texture = lookup(&m.base_color_texture, textures).map(|(index, r)| {
            let extensions = r.transform.map(|t| {
                self.use_extension("KHR_texture_transform");
                json::extensions::texture::Info {
                    texture_transform: Some(texture_transform(t, r.tex_coord)),
                    others: Default::default(),
                }
            });
            json::texture::Info {
                index,
                tex_coord: r.tex_coord,
                extensions,
                extras: Default::default(),
            }
        });
        let normal_texture = lookup(&m.normal_texture, textures).map(|(index, r)| {
            let extensions = r.transform.map(|t| {
                self.use_extension("KHR_texture_transform");
                let mut others = serde_json::Map::new();
                others.insert("KHR_texture_transform".to_owned(), serde_json::json!({ "offset": t.offset, "rotation": t.rotation, "scale": t.scale }));
                json::extensions::material::NormalTexture { others }
            });
            json::material::NormalTexture { index, scale: m.normal_scale, tex_coord: r.tex_coord, extensions, extras: Default::default() }
        });
        let alpha = m.base_color[3];
        json::Material {
            alpha_mode: Checked::Valid(if alpha < 1.0 {
                json::material::AlphaMode::Blend
            } else {
                json::material::AlphaMode::Opaque
            }),
            double_sided: m.double_sided,
            name: Some(m.name.clone()),
            pbr_metallic_roughness: json::material::PbrMetallicRoughness {
                base_color_factor: json::material::PbrBaseColorFactor(
                    m.base_color.map(|c| c.clamp(0.0, 1.0)),
                ),
                base_color_texture,
                metallic_factor: json::material::StrengthFactor(m.metallic.clamp(0.0, 1.0)),
                roughness_factor: json::material::StrengthFactor(m.roughness.clamp(0.0, 1.0)),
                ..Default::default()
            },
            normal_texture,
            ..Default::default()
        }
    }

    fn use_extension(&mut self, name: &str) {
        if !self.root.extensions_used.iter().any(|e| e == name) {
            self.root.extensions_used.push(name.to_owned());
        }
    }
}

/// KHR_texture_transform of a texture read through `tex_coord`. The extension's own
/// `texCoord` repeats the texture info's: gltf-json 1.4.1 writes `None` as `null`, which the
/// validator rejects.
fn texture_transform(
    t: UvTransform,
    tex_coord: u32,
) -> json::extensions::texture::TextureTransform {
    json::extensions::texture::TextureTransform {
        offset: json::extensions::texture::TextureTransformOffset(t.offset),
        rotation: json::extensions::texture::TextureTransformRotation(t.rotation),
        scale: json::extensions::texture::TextureTransformScale(t.scale),
        tex_coord: Some(tex_coord),
        extras: Default::default(),
    }
}

/// A node with the transform as translation / rotation / scale where it decomposes, else as
/// a matrix; the identity writes nothing.
fn node_with_transform(m: Mat4) -> json::Node {
    let mut node = json::Node::default();
    if m == Mat4::IDENTITY {
        return node;
    }
    let (s, r, t) = m.to_scale_rotation_translation();
    let r = r.normalize();
    let tolerance = 1e-5 * m.to_cols_array().iter().fold(1.0f32, |a, &x| a.max(x.abs()));
    if Mat4::from_scale_rotation_translation(s, r, t).abs_diff_eq(m, tolerance)
        && s.is_finite()
        && r.is_finite()
    {
        if t != Vec3::ZERO {
            node.translation = Some(t.to_array());
        }
        if r != Quat::IDENTITY {
            node.rotation = Some(json::scene::UnitQuaternion(r.to_array()));
        }
        if s != Vec3::ONE {
            node.scale = Some(s.to_array());
        }
    } else {
        node.matrix = Some(m.to_cols_array());
    }
    node
}

/// Whether the asset's nodes describe its objects: every object carried by exactly one node,
/// parents before children, and each object's transform the composition of its node chain.
fn hierarchy_matches(asset: &Asset) -> bool {
    if asset.nodes.is_empty() {
        return false;
    }
    let mut carried = vec![0usize; asset.model.objects.len()];
    let mut globals: Vec<Mat4> = Vec::with_capacity(asset.nodes.len());
    for (i, node) in asset.nodes.iter().enumerate() {
        let parent = match node.parent {
            Some(p) if p < i => globals[p],
            Some(_) => return false,
            None => Mat4::IDENTITY,
        };
        let global = parent * node.local_transform;
        globals.push(global);
        for &object in &node.objects {
            let Some(o) = asset.model.objects.get(object) else { return false };
            carried[object] += 1;
            let tolerance =
                1e-5 * global.to_cols_array().iter().fold(1.0f32, |a, &x| a.max(x.abs()));
            if !o.model_transform().abs_diff_eq(global, tolerance) {
                return false;
            }
        }
    }
    carried.iter().all(|&n| n == 1)
}

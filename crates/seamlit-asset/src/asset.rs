//! What a loaded file holds: the model (geometry, in seamlit-mesh types) plus the materials
//! and textures that lighting needs, and the conversions between the two material models
//! (Blinn-Phong shininess and glTF roughness).

use std::path::PathBuf;
use std::sync::Arc;

use bytes::Bytes;
use seamlit_mesh::{Influences, Model, MorphTarget, Object};

use crate::animation::{Animation, Skin, SkinsChanged, Trs};
use crate::document::SourceDocument;

/// A loaded model file: geometry plus materials and textures.
///
/// `model.objects[i].material` indexes [`Asset::materials`]; a material's texture references
/// index [`Asset::textures`].
#[derive(Clone, Debug, Default)]
pub struct Asset {
    /// The geometry: one object per OBJ group, glTF primitive instance or Bezier patch.
    pub model: Model,
    /// Materials, in file order.
    pub materials: Vec<Material>,
    /// Textures (images), in file order.
    pub textures: Vec<Texture>,
    /// The scene's nodes (glTF nodes, FBX models), a parent before its children; each names
    /// the objects it carries, so writers can rebuild the hierarchy and [`crate::pose`] can
    /// move them. Empty when the format has none (OBJ, Newell patches).
    pub nodes: Vec<Node>,
    /// The file this asset was loaded from, if any.
    pub source: Option<PathBuf>,
    /// Problems that did not stop loading (a missing texture, an unsupported extension).
    pub warnings: Vec<String>,
    /// The lights the file carries (glTF KHR_lights_punctual), in model space.
    pub lights: Vec<PunctualLight>,
    /// The skins (glTF `skins`, FBX clusters), in file order; [`Node::skin`] indexes them.
    pub skins: Vec<Skin>,
    /// The animations (glTF `animations`, FBX animation stacks), in file order.
    pub animations: Vec<Animation>,
    /// The objects' influences and the skins that [`crate::match_skin_seams`] changed, which
    /// the glTF pass-through writes anew; empty after loading.
    pub skins_changed: SkinsChanged,
    /// The document the file was read from, as its format's reader keeps it for the same
    /// format's writer: the glTF document and buffers (the glTF pass-through), the OBJ text and
    /// where each object's faces are in it (the OBJ pass-through), how an OpenUSD stage was read
    /// (the `.usda` layer writer). `None` for formats without one; set it to `None` to write
    /// with the generic writer instead. Each format crate finds its own type in it with
    /// [`Asset::document`].
    pub document: Option<SourceDocument>,
    /// glTF KHR_materials_variants: the file's variants and the material each gives the
    /// objects it maps ([`Asset::select_variant`]); empty for a file without them.
    pub variants: Variants,
    /// Materials of parts of objects (OpenUSD `materialBind` GeomSubsets): for each object
    /// listed, the material of each of its triangles. `seamlit_io::save` and `seamlit_mesh::fix`
    /// ignore it (an object stays one object, its normals computed across its parts);
    /// [`Asset::split_triangle_materials`] cuts the objects into one per material for
    /// drawing. Empty for formats without it.
    pub triangle_materials: Vec<TriangleMaterials>,
}

/// The materials of one object's triangles ([`Asset::triangle_materials`]).
#[derive(Clone, Debug, PartialEq)]
pub struct TriangleMaterials {
    /// Index into `model.objects`.
    pub object: usize,
    /// Per triangle of the object: its material (an index into [`Asset::materials`]),
    /// `None` where it has the object's own.
    pub materials: Vec<Option<usize>>,
}

/// KHR_materials_variants: named sets of materials for the same geometry.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Variants {
    /// The variants' names, in file order (a variant index counts them).
    pub names: Vec<String>,
    /// The objects some variant maps, each with its own material (the primitive's
    /// `material`, which the default draws) and its mappings.
    pub objects: Vec<VariantObject>,
}

/// One object's KHR_materials_variants mappings.
#[derive(Clone, Debug, PartialEq)]
pub struct VariantObject {
    /// Index into `model.objects`.
    pub object: usize,
    /// The object's material without a variant.
    pub default: Option<usize>,
    /// `(variant, material)`: the material (an index into [`Asset::materials`]) each
    /// variant (an index into [`Variants::names`]) gives the object.
    pub mappings: Vec<(usize, usize)>,
}

/// A variant name that the asset does not have; its message lists those it has.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("no material variant {name:?}; {}", list_variants(.known))]
pub struct UnknownVariant {
    /// The name asked for.
    pub name: String,
    /// The variants the asset has.
    pub known: Vec<String>,
}

/// `the variants are "a", "b"`, or that there are none.
fn list_variants(known: &[String]) -> String {
    if known.is_empty() {
        return "the model has no variants (KHR_materials_variants)".to_owned();
    }
    let names: Vec<String> = known.iter().map(|n| format!("{n:?}")).collect();
    format!("the variants are {}", names.join(", "))
}

impl Asset {
    /// The document of type `T` the asset was read from ([`Asset::document`]), if it was read
    /// by the format that keeps a `T`: `asset.document::<seamlit_gltf::GltfSource>()`.
    #[must_use]
    pub fn document<T: std::any::Any>(&self) -> Option<&T> {
        self.document.as_ref().and_then(SourceDocument::get)
    }

    /// Gives each object the material of the variant called `name` (KHR_materials_variants),
    /// or with `None` its own material (the default); objects the variant does not map keep
    /// their own material.
    ///
    /// # Errors
    /// [`UnknownVariant`] for a name the asset has no variant of; nothing is changed then.
    pub fn select_variant(&mut self, name: Option<&str>) -> Result<(), UnknownVariant> {
        let index = match name {
            None => None,
            Some(name) => {
                Some(self.variants.names.iter().position(|n| n == name).ok_or_else(|| {
                    UnknownVariant { name: name.to_owned(), known: self.variants.names.clone() }
                })?)
            }
        };
        for v in &self.variants.objects {
            let mapped = index.and_then(|i| v.mappings.iter().find(|(variant, _)| *variant == i));
            if let Some(object) = self.model.objects.get_mut(v.object) {
                object.material = mapped.map_or(v.default, |&(_, material)| Some(material));
            }
        }
        Ok(())
    }

    /// The number of objects the model has after [`Asset::split_triangle_materials`].
    #[must_use]
    pub fn split_object_count(&self) -> usize {
        let extra: usize = self
            .model
            .objects
            .iter()
            .enumerate()
            .filter_map(|(i, object)| {
                let entry = self.split_entry(i, object)?;
                let parts = materials_in_order(object, &entry.materials).len();
                Some(parts.saturating_sub(1))
            })
            .sum();
        self.model.objects.len() + extra
    }

    /// The entry of [`Asset::triangle_materials`] that cuts object `i`, if one does.
    fn split_entry(&self, i: usize, object: &Object) -> Option<&TriangleMaterials> {
        self.triangle_materials
            .iter()
            .find(|e| e.object == i && e.materials.len() == object.triangles.len())
    }

    /// Cuts each object that [`Asset::triangle_materials`] lists into one object per material
    /// of its triangles (in the order the materials first appear), each with only the
    /// vertices its triangles use, and empties the list; node and variant references to a
    /// cut object name all its parts. For drawing, after the fix: the parts keep the normals
    /// and tangents the whole object was given, so the cut makes no seam. An entry whose
    /// length is not the object's number of triangles is skipped.
    pub fn split_triangle_materials(&mut self) {
        if self.triangle_materials.is_empty() {
            return;
        }
        let old = std::mem::take(&mut self.model.objects);
        let mut parts_of: Vec<Vec<usize>> = Vec::with_capacity(old.len());
        let mut objects = Vec::with_capacity(old.len());
        for (i, object) in old.into_iter().enumerate() {
            let first = objects.len();
            match self.split_entry(i, &object) {
                Some(entry) => objects.extend(split_object(object, &entry.materials)),
                None => objects.push(object),
            }
            parts_of.push((first..objects.len()).collect());
        }
        self.model.objects = objects;
        self.triangle_materials.clear();
        let parts = |o: usize| parts_of.get(o).cloned().unwrap_or_default();
        for node in &mut self.nodes {
            node.objects = node.objects.iter().flat_map(|&o| parts(o)).collect();
        }
        self.variants.objects = std::mem::take(&mut self.variants.objects)
            .into_iter()
            .flat_map(|v| {
                parts(v.object).into_iter().map(move |o| VariantObject { object: o, ..v.clone() })
            })
            .collect();
        self.skins_changed.objects =
            self.skins_changed.objects.iter().flat_map(|&o| parts(o)).collect();
    }
}

/// `object` cut into one object per material of its triangles (`materials`, `None` the
/// object's own), each with the vertices its triangles use, in their order.
fn split_object(object: Object, materials: &[Option<usize>]) -> Vec<Object> {
    let material_of = |t: usize| materials[t].or(object.material);
    let order = materials_in_order(&object, materials);
    if order.len() <= 1 {
        return vec![Object { material: order.first().copied().flatten(), ..object }];
    }
    order
        .iter()
        .map(|&material| {
            let triangles: Vec<usize> =
                (0..object.triangles.len()).filter(|&t| material_of(t) == material).collect();
            let mut new_index = vec![u32::MAX; object.positions.len()];
            let mut kept: Vec<usize> = Vec::new();
            let remapped: Vec<[u32; 3]> = triangles
                .iter()
                .map(|&t| {
                    object.triangles[t].map(|v| {
                        let slot = &mut new_index[v as usize];
                        if *slot == u32::MAX {
                            #[expect(clippy::cast_possible_truncation, reason = "fewer vertices")]
                            let next = kept.len() as u32;
                            *slot = next;
                            kept.push(v as usize);
                        }
                        *slot
                    })
                })
                .collect();
            Object {
                name: object.name.clone(),
                positions: pick(&object.positions, &kept),
                uvs: object.uvs.as_ref().map(|v| pick(v, &kept)),
                uvs1: object.uvs1.as_ref().map(|v| pick(v, &kept)),
                normals: object.normals.as_ref().map(|v| pick(v, &kept)),
                colors: object.colors.as_ref().map(|v| pick(v, &kept)),
                tangents: object.tangents.as_ref().map(|v| pick(v, &kept)),
                triangles: remapped,
                transform: object.transform,
                material,
                smoothing_groups: object.smoothing_groups.as_ref().map(|g| pick(g, &triangles)),
                split_from: Vec::new(),
                skin: object
                    .skin
                    .iter()
                    .map(|s| Influences {
                        joints: pick(&s.joints, &kept),
                        weights: pick(&s.weights, &kept),
                    })
                    .collect(),
                morph_targets: object
                    .morph_targets
                    .iter()
                    .map(|m| MorphTarget {
                        name: m.name.clone(),
                        position_deltas: pick(&m.position_deltas, &kept),
                        normal_deltas: m.normal_deltas.as_ref().map(|v| pick(v, &kept)),
                        tangent_deltas: m.tangent_deltas.as_ref().map(|v| pick(v, &kept)),
                    })
                    .collect(),
            }
        })
        .collect()
}

/// The materials of `object`'s triangles (`materials`, `None` the object's own), each once,
/// in the order they first appear.
fn materials_in_order(object: &Object, materials: &[Option<usize>]) -> Vec<Option<usize>> {
    let mut order: Vec<Option<usize>> = Vec::new();
    for m in materials.iter().map(|m| m.or(object.material)) {
        if !order.contains(&m) {
            order.push(m);
        }
    }
    order
}

/// `values` at `indices`, in their order (a value past the end is skipped: a per-vertex
/// array shorter than the positions, which the fix refuses, never panics here).
fn pick<T: Clone>(values: &[T], indices: &[usize]) -> Vec<T> {
    indices.iter().filter_map(|&i| values.get(i).cloned()).collect()
}

/// A node of the scene hierarchy (glTF): its name, local transform and parent.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    /// The node's name, empty when the file gives none (none is invented).
    pub name: String,
    /// Transform relative to the parent.
    pub local_transform: glam::Mat4,
    /// Index of the parent node in [`Asset::nodes`], `None` for a root.
    pub parent: Option<usize>,
    /// Indices of the objects (in `model.objects`) this node carries.
    pub objects: Vec<usize>,
    /// The local transform as translation, rotation and scale, where the file gives it so
    /// (what animations move); `None` where it gives a matrix, which
    /// [`Node::local_transform`] holds as written.
    pub trs: Option<Trs>,
    /// The skin of the node's mesh, an index into [`Asset::skins`]. The objects of a skinned
    /// node are in the skin's bind-pose space (their `transform` is `None`), and their
    /// [`seamlit_mesh::Influences`] name joints as indices into [`Asset::nodes`].
    pub skin: Option<usize>,
    /// The morph target weights of the node's mesh when no animation moves them (glTF:
    /// the node's `weights`, else its mesh's); empty where the file gives none (all 0).
    pub weights: Vec<f32>,
}

impl Node {
    /// A node with a name, a local transform and a parent, carrying no objects.
    #[must_use]
    pub fn new(
        name: impl Into<String>,
        local_transform: glam::Mat4,
        parent: Option<usize>,
    ) -> Self {
        Self {
            name: name.into(),
            local_transform,
            parent,
            objects: Vec::new(),
            trs: None,
            skin: None,
            weights: Vec::new(),
        }
    }

    /// The local transform as translation, rotation and scale: [`Node::trs`], else the
    /// matrix's decomposition.
    #[must_use]
    pub fn local_trs(&self) -> Trs {
        self.trs.unwrap_or_else(|| {
            let (scale, rotation, translation) =
                self.local_transform.to_scale_rotation_translation();
            Trs { translation, rotation, scale }
        })
    }
}

/// A material: what the renderer needs for per-pixel lighting with normal mapping.
///
/// Colours are linear RGB(A). Read from OBJ `.mtl` (Kd, Ks, Ns, d, map_Kd, map_Bump / bump /
/// norm) and glTF (baseColor, normalTexture, metallic-roughness, occlusion, emissive,
/// alphaMode, doubleSided, KHR_materials_emissive_strength, KHR_materials_unlit).
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// The material's name.
    pub name: String,
    /// Base (diffuse) colour factor, linear RGBA.
    pub base_color: [f32; 4],
    /// Base colour texture (sRGB), multiplied by `base_color`.
    pub base_color_texture: Option<TextureRef>,
    /// Tangent-space normal map (linear data).
    pub normal_texture: Option<TextureRef>,
    /// Normal map strength (glTF `normalTexture.scale`, OBJ `-bm`).
    pub normal_scale: f32,
    /// Whether the normal map uses the DirectX convention (green down).
    pub normal_green_down: bool,
    /// Specular colour, linear RGB (OBJ `Ks`; derived from metallic-roughness for glTF).
    pub specular: [f32; 3],
    /// Blinn-Phong shininess exponent (OBJ `Ns`; derived from roughness for glTF).
    pub shininess: f32,
    /// glTF metallic factor, kept for conversion.
    pub metallic: f32,
    /// glTF roughness factor, kept for conversion.
    pub roughness: f32,
    /// Whether back faces are drawn.
    pub double_sided: bool,
    /// glTF metallic-roughness texture (linear): blue is metalness, green roughness, each
    /// multiplied by its factor.
    pub metallic_roughness_texture: Option<TextureRef>,
    /// glTF ambient occlusion texture (linear, red channel).
    pub occlusion_texture: Option<TextureRef>,
    /// How much the occlusion texture darkens: 0 none, 1 all of it (glTF `strength`).
    pub occlusion_strength: f32,
    /// Emitted light, linear RGB (glTF `emissiveFactor` times
    /// KHR_materials_emissive_strength's `emissiveStrength`).
    pub emissive: [f32; 3],
    /// Emissive texture (sRGB), multiplied by `emissive`.
    pub emissive_texture: Option<TextureRef>,
    /// How the base colour's alpha is used (glTF `alphaMode`, `alphaCutoff`).
    pub alpha_mode: AlphaMode,
    /// KHR_materials_unlit: the base colour is shown as it is, without lighting.
    pub unlit: bool,
    /// The glTF PBR extensions the material uses beyond metallic-roughness (ior, specular,
    /// clearcoat, sheen); all `None` for a material without them.
    pub extensions: PbrExtensions,
    /// How the material's textures are sampled: the glTF sampler of its base colour texture
    /// (else of its first core texture that names one). Renderers sample every texture of a
    /// material alike; the default (repeat, trilinear) is glTF's for a texture without one.
    pub sampling: TextureSampling,
}

/// A glTF sampler: wrapping and filters.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TextureSampling {
    /// Wrapping across (glTF `wrapS`) and down (`wrapT`).
    pub wrap: [Wrap; 2],
    /// Magnification filter (glTF `magFilter`).
    pub mag_filter: TextureFilter,
    /// Minification filter within a mip (glTF `minFilter`).
    pub min_filter: TextureFilter,
    /// Filter between mips; `None` where `minFilter` is NEAREST or LINEAR, which sample the
    /// full-size image only.
    pub mipmap_filter: Option<TextureFilter>,
}

impl Default for TextureSampling {
    fn default() -> Self {
        Self {
            wrap: [Wrap::Repeat; 2],
            mag_filter: TextureFilter::Linear,
            min_filter: TextureFilter::Linear,
            mipmap_filter: Some(TextureFilter::Linear),
        }
    }
}

/// How texture coordinates outside 0..1 read a texture (glTF `wrapS`, `wrapT`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Wrap {
    /// The image tiles (REPEAT, 10497).
    Repeat,
    /// The edge texels extend (CLAMP_TO_EDGE, 33071).
    ClampToEdge,
    /// The image tiles, every other copy mirrored (MIRRORED_REPEAT, 33648).
    MirroredRepeat,
}

/// A texture filter (glTF's NEAREST and LINEAR, and the halves of its mipmap filters).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TextureFilter {
    /// The nearest texel (or mip).
    Nearest,
    /// A linear blend of the nearest texels (or mips).
    Linear,
}

/// glTF material extensions that add to the metallic-roughness BRDF, as their specifications
/// define them (each `None` where the material does not use it).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PbrExtensions {
    /// KHR_materials_ior: the dielectric's index of refraction (glTF's default is 1.5, which
    /// gives the core f0 of 0.04).
    pub ior: Option<f32>,
    /// KHR_materials_specular.
    pub specular: Option<Specular>,
    /// KHR_materials_clearcoat.
    pub clearcoat: Option<Clearcoat>,
    /// KHR_materials_sheen.
    pub sheen: Option<Sheen>,
    /// KHR_materials_anisotropy.
    pub anisotropy: Option<Anisotropy>,
    /// KHR_materials_transmission.
    pub transmission: Option<Transmission>,
    /// KHR_materials_volume (read only with transmission, as the renderer draws it).
    pub volume: Option<Volume>,
    /// KHR_materials_iridescence.
    pub iridescence: Option<Iridescence>,
    /// KHR_materials_dispersion's `dispersion` (default 0): how far the volume's ior spreads
    /// between red and blue (20 / Abbe number); drawn with transmission's volume.
    pub dispersion: Option<f32>,
}

impl PbrExtensions {
    /// Whether the material has a texture of transmission, volume (thickness), iridescence
    /// (factor or thickness) or anisotropy: those a renderer on a device with only 16 sampled
    /// textures a shader stage leaves out (`seamlit_render::GpuContext`).
    #[must_use]
    pub fn has_transmission_volume_iridescence_or_anisotropy_texture(&self) -> bool {
        self.transmission.as_ref().is_some_and(|t| t.texture.is_some())
            || self.volume.as_ref().is_some_and(|v| v.thickness_texture.is_some())
            || self
                .iridescence
                .as_ref()
                .is_some_and(|i| i.texture.is_some() || i.thickness_texture.is_some())
            || self.anisotropy.as_ref().is_some_and(|a| a.texture.is_some())
    }

    /// The names of the extensions in use, in the order of this struct's fields (for the
    /// viewer's panel and messages).
    #[must_use]
    pub fn names(&self) -> Vec<&'static str> {
        let mut names = Vec::new();
        if self.ior.is_some() {
            names.push("KHR_materials_ior");
        }
        if self.specular.is_some() {
            names.push("KHR_materials_specular");
        }
        if self.clearcoat.is_some() {
            names.push("KHR_materials_clearcoat");
        }
        if self.sheen.is_some() {
            names.push("KHR_materials_sheen");
        }
        if self.anisotropy.is_some() {
            names.push("KHR_materials_anisotropy");
        }
        if self.transmission.is_some() {
            names.push("KHR_materials_transmission");
        }
        if self.volume.is_some() {
            names.push("KHR_materials_volume");
        }
        if self.iridescence.is_some() {
            names.push("KHR_materials_iridescence");
        }
        if self.dispersion.is_some() {
            names.push("KHR_materials_dispersion");
        }
        names
    }
}

/// KHR_materials_specular: the dielectric's specular strength and colour.
#[derive(Clone, Debug, PartialEq)]
pub struct Specular {
    /// `specularFactor` (default 1), times the texture's alpha.
    pub factor: f32,
    /// `specularTexture` (linear; alpha).
    pub texture: Option<TextureRef>,
    /// `specularColorFactor` (linear RGB, default 1), times the colour texture.
    pub color: [f32; 3],
    /// `specularColorTexture` (sRGB; RGB).
    pub color_texture: Option<TextureRef>,
}

/// KHR_materials_clearcoat: a clear GGX layer over the material.
#[derive(Clone, Debug, PartialEq)]
pub struct Clearcoat {
    /// `clearcoatFactor` (default 0), times the texture's red.
    pub factor: f32,
    /// `clearcoatTexture` (linear; red).
    pub texture: Option<TextureRef>,
    /// `clearcoatRoughnessFactor` (default 0), times the texture's green.
    pub roughness: f32,
    /// `clearcoatRoughnessTexture` (linear; green).
    pub roughness_texture: Option<TextureRef>,
    /// `clearcoatNormalTexture` (tangent space, linear); the geometry's normal without it.
    pub normal_texture: Option<TextureRef>,
    /// The clearcoat normal texture's `scale`.
    pub normal_scale: f32,
}

/// KHR_materials_anisotropy: the specular lobe stretched along a direction of the tangent
/// plane (brushed metal).
#[derive(Clone, Debug, PartialEq)]
pub struct Anisotropy {
    /// `anisotropyStrength` (default 0), times the texture's blue.
    pub strength: f32,
    /// `anisotropyRotation` (radians, default 0): the direction's turn from the tangent
    /// towards the bitangent.
    pub rotation: f32,
    /// `anisotropyTexture` (linear; red-green: a direction in the tangent plane, turned by
    /// the rotation; blue: strength).
    pub texture: Option<TextureRef>,
}

/// KHR_materials_transmission: light passing through the surface (thin glass, and with
/// [`Volume`] a solid one), refracted by the material's ior.
#[derive(Clone, Debug, PartialEq)]
pub struct Transmission {
    /// `transmissionFactor` (default 0), times the texture's red.
    pub factor: f32,
    /// `transmissionTexture` (linear; red).
    pub texture: Option<TextureRef>,
}

/// KHR_materials_iridescence: a thin film over the surface whose interference colours its
/// Fresnel term by the viewing angle (soap bubbles, oil, anodised metal).
#[derive(Clone, Debug, PartialEq)]
pub struct Iridescence {
    /// `iridescenceFactor` (default 0), times the texture's red.
    pub factor: f32,
    /// `iridescenceTexture` (linear; red).
    pub texture: Option<TextureRef>,
    /// `iridescenceIor` (default 1.3): the film's index of refraction.
    pub ior: f32,
    /// `iridescenceThicknessMinimum` (default 100 nm).
    pub thickness_minimum: f32,
    /// `iridescenceThicknessMaximum` (default 400 nm): the film's thickness without a
    /// thickness texture.
    pub thickness_maximum: f32,
    /// `iridescenceThicknessTexture` (linear; green: from the minimum to the maximum).
    pub thickness_texture: Option<TextureRef>,
}

/// KHR_materials_volume: the thickness of the solid under a transmissive surface and how it
/// absorbs light on the way through.
#[derive(Clone, Debug, PartialEq)]
pub struct Volume {
    /// `thicknessFactor` (default 0: thin-walled), in the mesh's own units, times the
    /// texture's green.
    pub thickness: f32,
    /// `thicknessTexture` (linear; green).
    pub thickness_texture: Option<TextureRef>,
    /// `attenuationDistance` (default: infinite, `None`): the distance light travels in the
    /// medium before it is reduced to `attenuation_color`.
    pub attenuation_distance: Option<f32>,
    /// `attenuationColor` (linear RGB, default 1).
    pub attenuation_color: [f32; 3],
}

/// KHR_materials_sheen: a Charlie sheen layer (cloth) over the material.
#[derive(Clone, Debug, PartialEq)]
pub struct Sheen {
    /// `sheenColorFactor` (linear RGB, default 0), times the colour texture.
    pub color: [f32; 3],
    /// `sheenColorTexture` (sRGB; RGB).
    pub color_texture: Option<TextureRef>,
    /// `sheenRoughnessFactor` (default 0), times the texture's alpha.
    pub roughness: f32,
    /// `sheenRoughnessTexture` (linear; alpha).
    pub roughness_texture: Option<TextureRef>,
}

/// A light from a glTF file (KHR_lights_punctual), placed by its node in model space.
#[derive(Clone, Debug, PartialEq)]
pub struct PunctualLight {
    /// The light's name, empty when the file gives none.
    pub name: String,
    /// Directional, point or spot.
    pub kind: PunctualKind,
    /// Linear RGB colour.
    pub color: [f32; 3],
    /// Directional: illuminance in lux; point and spot: luminous intensity in candela.
    pub intensity: f32,
    /// The origin of the light's node, in model space (point and spot).
    pub position: glam::Vec3,
    /// The unit direction the light travels: its node's -Z, in model space (directional and
    /// spot).
    pub direction: glam::Vec3,
    /// The distance where the light's contribution reaches zero; `None`: unlimited.
    pub range: Option<f32>,
}

/// The kinds of KHR_lights_punctual light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PunctualKind {
    /// Parallel light.
    Directional,
    /// Light from a point in all directions.
    Point,
    /// A cone of light.
    Spot {
        /// Half-angle of full intensity, radians.
        inner_cone_angle: f32,
        /// Half-angle where the intensity reaches zero, radians.
        outer_cone_angle: f32,
    },
}

/// glTF `alphaMode`: what the base colour's alpha does.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum AlphaMode {
    /// Alpha is ignored; the surface is fully opaque.
    #[default]
    Opaque,
    /// Pixels whose alpha is below the cutoff are not drawn; the rest are opaque.
    Mask {
        /// glTF `alphaCutoff` (0.5 when the file gives none).
        cutoff: f32,
    },
    /// The surface is blended over what lies behind it by its alpha.
    Blend,
}

impl Material {
    /// Every texture the material uses, core and extension slots alike: what must change
    /// with the indices of [`Asset::textures`] (as when two assets are merged).
    pub fn textures_mut(&mut self) -> impl Iterator<Item = &mut TextureRef> {
        let x = &mut self.extensions;
        let specular = x.specular.as_mut().map(|s| [&mut s.texture, &mut s.color_texture]);
        let clearcoat = x
            .clearcoat
            .as_mut()
            .map(|c| [&mut c.texture, &mut c.roughness_texture, &mut c.normal_texture]);
        let sheen = x.sheen.as_mut().map(|s| [&mut s.color_texture, &mut s.roughness_texture]);
        let iridescence =
            x.iridescence.as_mut().map(|i| [&mut i.texture, &mut i.thickness_texture]);
        [
            &mut self.base_color_texture,
            &mut self.normal_texture,
            &mut self.metallic_roughness_texture,
            &mut self.occlusion_texture,
            &mut self.emissive_texture,
        ]
        .into_iter()
        .chain(specular.into_iter().flatten())
        .chain(clearcoat.into_iter().flatten())
        .chain(sheen.into_iter().flatten())
        .chain(iridescence.into_iter().flatten())
        .chain(x.anisotropy.as_mut().map(|a| &mut a.texture))
        .chain(x.transmission.as_mut().map(|t| &mut t.texture))
        .chain(x.volume.as_mut().map(|v| &mut v.thickness_texture))
        .flatten()
    }
}

impl Default for Material {
    fn default() -> Self {
        Self {
            name: String::new(),
            base_color: [0.8, 0.8, 0.8, 1.0],
            base_color_texture: None,
            normal_texture: None,
            normal_scale: 1.0,
            normal_green_down: false,
            specular: [0.5, 0.5, 0.5],
            shininess: 32.0,
            metallic: 0.0,
            roughness: 0.5,
            double_sided: false,
            metallic_roughness_texture: None,
            occlusion_texture: None,
            occlusion_strength: 1.0,
            emissive: [0.0; 3],
            emissive_texture: None,
            alpha_mode: AlphaMode::Opaque,
            unlit: false,
            extensions: PbrExtensions::default(),
            sampling: TextureSampling::default(),
        }
    }
}

/// A material's use of a texture.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureRef {
    /// Index into [`Asset::textures`].
    pub texture: usize,
    /// Which texture coordinate set: 0 reads `Object::uvs` (TEXCOORD_0), 1 reads
    /// `Object::uvs1` (TEXCOORD_1); the renderer reads set 0 for any other.
    pub tex_coord: u32,
    /// KHR_texture_transform, if present.
    pub transform: Option<UvTransform>,
}

/// KHR_texture_transform: `uv' = T(offset) * R(rotation) * S(scale) * uv`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvTransform {
    /// Translation.
    pub offset: [f32; 2],
    /// Rotation in radians, counter-clockwise.
    pub rotation: f32,
    /// Scale.
    pub scale: [f32; 2],
}

/// An image used by materials.
#[derive(Clone, Debug)]
pub struct Texture {
    /// A name for messages (the file name, or the glTF image name).
    pub name: String,
    /// Where the encoded image came from.
    pub source: TextureSource,
    /// The decoded image, RGBA8; `None` if it could not be found or decoded (a warning says
    /// why, and renderers use a neutral default).
    pub image: Option<Arc<image::RgbaImage>>,
}

/// Where a texture's encoded bytes live.
#[derive(Clone, Debug, PartialEq)]
pub enum TextureSource {
    /// A file on disk (resolved, absolute or relative to the working directory).
    File(PathBuf),
    /// Bytes embedded in the model (GLB buffer view or data URI), with their MIME type.
    Embedded {
        /// `image/png` or `image/jpeg`.
        mime_type: String,
        /// The encoded image: where it came from a model's buffer (a GLB's BIN chunk), a slice
        /// of that buffer, not a copy.
        bytes: Bytes,
    },
    /// Made in code (the demo's brick normal map); writers encode it as PNG.
    Generated,
}

impl Asset {
    /// `options` as `seamlit fix` uses them for this asset: where an object has a normal map
    /// but no tangents, [`TangentMethod::Mikktspace`](seamlit_mesh::TangentMethod) unless
    /// the caller `asked` for a tangent generator (or none). The glTF specification tells
    /// viewers to use MikkTSpace then, so that is what the map was baked for
    /// (docs/normals.md).
    #[must_use]
    pub fn fix_options(
        &self,
        options: seamlit_mesh::FixOptions,
        asked: bool,
    ) -> seamlit_mesh::FixOptions {
        use seamlit_mesh::TangentMethod;
        let normal_mapped = |material: Option<usize>| {
            material.and_then(|m| self.materials.get(m)).is_some_and(|m| m.normal_texture.is_some())
        };
        let unmapped =
            self.model.objects.iter().any(|o| o.tangents.is_none() && normal_mapped(o.material));
        if asked || !unmapped || options.tangents == TangentMethod::None {
            return options;
        }
        seamlit_mesh::FixOptions { tangents: TangentMethod::Mikktspace, ..options }
    }
}

/// Blinn-Phong shininess to glTF roughness: `sqrt(2 / (Ns + 2))`, the usual mapping
/// (Ns 0 -> 1, Ns 32 -> 0.24, Ns 1000 -> 0.045).
#[must_use]
pub fn shininess_to_roughness(shininess: f32) -> f32 {
    (2.0 / (shininess.max(0.0) + 2.0)).sqrt()
}

/// glTF roughness to Blinn-Phong shininess, the inverse of [`shininess_to_roughness`]:
/// `2 / r^2 - 2`, capped at 2048 for roughness near 0.
#[must_use]
pub fn roughness_to_shininess(roughness: f32) -> f32 {
    let r = roughness.clamp(0.03, 1.0);
    (2.0 / (r * r) - 2.0).min(2048.0)
}

//! A model on the GPU: one vertex and index buffer per object, materials with their textures.

use std::collections::HashMap;

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};
use seamlit_asset::{AlphaMode, Asset, Material, Texture, TextureRef, TextureSampling};
use seamlit_mesh::{Model, Object, VAxis};
use wgpu::util::DeviceExt;

use crate::material::{
    MAT_ANISOTROPY_TEXTURE, MAT_CLEARCOAT_NORMAL_MAP, MAT_LAYERS, MAT_NORMAL_MAP, MAT_TRANSMISSION,
    material_to_raw,
};
use crate::pose::{Deform, ObjectPose};
use crate::readback::PosedVertices;
use crate::texture::{self, ImageUpload, TexelKind, TextureOptions};
use crate::{GpuContext, RenderError};

/// One vertex as the vertex shader reads it (72 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub(crate) struct VertexRaw {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub tangent: [f32; 4],
    pub uv: [f32; 2],
    /// glTF COLOR_0 (linear RGBA), white when the object has none.
    pub color: [f32; 4],
    /// glTF TEXCOORD_1, `uv` when the object has none.
    pub uv1: [f32; 2],
}

impl VertexRaw {
    pub(crate) const ATTRIBUTES: [wgpu::VertexAttribute; 6] = wgpu::vertex_attr_array![
        0 => Float32x3, 1 => Float32x3, 2 => Float32x4, 3 => Float32x2, 4 => Float32x4,
        5 => Float32x2
    ];

    pub(crate) fn layout() -> wgpu::VertexBufferLayout<'static> {
        wgpu::VertexBufferLayout {
            array_stride: size_of::<Self>() as wgpu::BufferAddress,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &Self::ATTRIBUTES,
        }
    }
}

/// Size of [`VertexRaw`] in bytes.
const VERTEX_SIZE: u64 = size_of::<VertexRaw>() as u64;

/// Per-object uniforms (`Object` in `mesh.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub(crate) struct ObjectRaw {
    pub model: [[f32; 4]; 4],
    pub normal: [[f32; 4]; 4],
    pub det_sign: f32,
    pub object_id: u32,
    pub flip_v: u32,
    pub has_tangents: u32,
    /// Skin sets `deform.wgsl` blends (zero unless a pose with a palette is set).
    pub skin_sets: u32,
    /// Morph targets `deform.wgsl` adds (zero unless a pose is set).
    pub morph_targets: u32,
    pub vertex_count: u32,
    pub pad: u32,
}

/// One object on the GPU.
#[derive(Debug)]
pub(crate) struct GpuMesh {
    /// The object's name and its index in the model's objects.
    pub name: String,
    pub object: usize,
    /// The object's uniforms as uploaded (no pose), and their buffer.
    rest: ObjectRaw,
    uniform: wgpu::Buffer,
    /// Skin influences, morph deltas and the pose's buffers.
    deform: Deform,
    pub vertices: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    pub index_count: u32,
    /// How many vertices the TBN line pass draws (all, unless the storage binding limit
    /// is smaller than the buffer).
    pub tbn_vertex_count: u32,
    pub bind_group: wgpu::BindGroup,
    /// Index into `GpuScene::materials`.
    pub material: usize,
    /// The transform has a negative determinant: front faces wind clockwise.
    pub mirrored: bool,
    /// The pose skins or morphs the object: drawn by the pipelines that do.
    pub posed: bool,
    /// The centre of the object's world-space bounds, for sorting blended objects.
    pub center: Vec3,
}

/// A material on the GPU.
#[derive(Debug)]
pub(crate) struct GpuMaterial {
    pub bind_group: wgpu::BindGroup,
    pub double_sided: bool,
    /// alphaMode BLEND: drawn after the opaque objects, back to front, blended.
    pub blend: bool,
    /// It uses a PBR extension (ior, specular, clearcoat, sheen): drawn by the pipelines
    /// with `mesh.wgsl`'s `LAYERS` compiled in.
    pub layers: bool,
    /// KHR_materials_transmission: left out of the transmission target, which it reads.
    pub transmission: bool,
}

/// A model uploaded to the GPU: geometry, materials and textures, ready for
/// [`crate::Renderer::render`].
///
/// Geometry can be replaced without re-uploading textures ([`GpuScene::replace_model`]), for
/// a viewer that re-runs `seamlit_mesh::fix` when the user changes the mode.
#[derive(Debug)]
pub struct GpuScene {
    pub(crate) meshes: Vec<GpuMesh>,
    pub(crate) materials: Vec<GpuMaterial>,
    material_count: usize,
    bounds: Option<(Vec3, Vec3)>,
    triangles: usize,
    /// How many objects the model has, triangles or not (the poses `set_pose` takes).
    object_total: usize,
    /// A small storage buffer bound where an object has no skin, deltas or pose buffers.
    empty: wgpu::Buffer,
}

impl GpuScene {
    /// Uploads an asset (its model, materials and textures). Every object must have normals
    /// (run `seamlit_mesh::fix` first); missing tangents disable normal mapping on that object,
    /// missing UVs read as (0, 0), missing vertex colours as white, missing textures use 1x1
    /// defaults (white base colour, flat normal, white metallic-roughness, occlusion and
    /// emissive, which leave their factors as they are), objects without a material use
    /// [`Material::default`]. Every texture slot reads TEXCOORD_0 (the only set the loader
    /// keeps), through its own KHR_texture_transform.
    ///
    /// # Errors
    ///
    /// [`RenderError::MissingNormals`], [`RenderError::BadObject`] (array lengths or indices
    /// that do not fit), [`RenderError::IndexOutOfRange`] (a material or texture index),
    /// [`RenderError::TextureTooLarge`], [`RenderError::Gpu`].
    pub fn upload(ctx: &GpuContext, asset: &Asset) -> Result<Self, RenderError> {
        Self::upload_parts(
            ctx,
            &asset.model,
            &asset.materials,
            &asset.textures,
            &TextureOptions::DEFAULT,
        )
    }

    /// As [`GpuScene::upload`], from the parts of an asset, with texture options.
    ///
    /// # Errors
    ///
    /// As [`GpuScene::upload`].
    pub fn upload_parts(
        ctx: &GpuContext,
        model: &Model,
        materials: &[Material],
        textures: &[Texture],
        options: &TextureOptions,
    ) -> Result<Self, RenderError> {
        ctx.scoped("uploading the scene", || {
            let gpu_materials = upload_materials(ctx, materials, textures, options)?;
            let mut scene = Self {
                meshes: Vec::new(),
                materials: gpu_materials,
                material_count: materials.len(),
                bounds: None,
                triangles: 0,
                object_total: 0,
                empty: ctx.device().create_buffer(&wgpu::BufferDescriptor {
                    label: Some("seamlit empty storage"),
                    size: 64,
                    usage: wgpu::BufferUsages::STORAGE,
                    mapped_at_creation: false,
                }),
            };
            scene.set_model(ctx, model)?;
            Ok(scene)
        })
    }

    /// Replaces the geometry (for instance after re-running `seamlit_mesh::fix` in another
    /// mode), keeping materials and textures. Material indices must fit the materials the
    /// scene was uploaded with. The new geometry has no pose: set it again.
    ///
    /// # Errors
    ///
    /// As [`GpuScene::upload`]; on error the scene keeps its old geometry.
    pub fn replace_model(&mut self, ctx: &GpuContext, model: &Model) -> Result<(), RenderError> {
        ctx.scoped("replacing the geometry", || self.set_model(ctx, model))
    }

    fn set_model(&mut self, ctx: &GpuContext, model: &Model) -> Result<(), RenderError> {
        let flip_v = model.v_axis == VAxis::Up;
        let meshes = model
            .objects
            .iter()
            .enumerate()
            .filter(|(_, o)| !o.triangles.is_empty())
            .map(|(i, o)| {
                let upload = ObjectUpload { index: i, flip_v, material_count: self.material_count };
                upload_object(ctx, o, &upload, &self.empty)
            })
            .collect::<Result<Vec<_>, _>>()?;
        self.meshes = meshes;
        self.bounds = model.bounds();
        self.triangles = model.triangle_count();
        self.object_total = model.objects.len();
        Ok(())
    }

    /// Poses the model: `poses` has one [`ObjectPose`] per object of the model, in
    /// `model.objects` order (objects without triangles included). Each object is drawn,
    /// in the scene and shadow passes, with its morph targets weighted, then skinned by its
    /// palette (where it has a skin and the pose a palette), then placed by the pose's
    /// transform instead of its own. The bounds ([`GpuScene::bounds`]) become bounds of the
    /// posed model. A scene whose pose was never set draws each object unposed.
    ///
    /// # Errors
    ///
    /// [`RenderError::BadPose`] for a count other than the model's objects, a palette shorter
    /// than the joints an object's influences name, more weights than targets or a number
    /// that is not finite; nothing is changed then.
    pub fn set_pose(&mut self, ctx: &GpuContext, poses: &[ObjectPose]) -> Result<(), RenderError> {
        if poses.len() != self.object_total {
            return Err(RenderError::BadPose {
                object: "the scene".into(),
                what: format!("{} poses for {} objects", poses.len(), self.object_total),
            });
        }
        for mesh in &self.meshes {
            mesh.deform.check(&mesh.name, &poses[mesh.object])?;
        }
        let mut bounds: Option<(Vec3, Vec3)> = None;
        for mesh in &mut self.meshes {
            let pose = &poses[mesh.object];
            let raw = ObjectRaw {
                skin_sets: if mesh.deform.skinned(pose) { mesh.deform.skin_sets } else { 0 },
                morph_targets: mesh.deform.morph_targets,
                ..transformed_raw(mesh.rest, pose.transform)
            };
            ctx.queue().write_buffer(&mesh.uniform, 0, bytemuck::bytes_of(&raw));
            mesh.deform.write(ctx, pose);
            mesh.mirrored = raw.det_sign < 0.0;
            mesh.posed = raw.skin_sets > 0 || raw.morph_targets > 0;
            let (lo, hi) = mesh.deform.posed_bounds(pose);
            mesh.center = (lo + hi) * 0.5;
            bounds = Some(bounds.map_or((lo, hi), |(a, b)| (a.min(lo), b.max(hi))));
        }
        self.bounds = bounds;
        Ok(())
    }

    /// The vertices of object `object` (an index into the model's objects) as the vertex
    /// stage places them under the current pose, read back from the GPU: world-space
    /// positions, unit normals and tangents (xyz under the model matrix, unnormalised; w the
    /// handedness). They come from the same `deform.wgsl` the scene and shadow passes run,
    /// in a compute pass; for checks and tools, not for every frame. An object without
    /// triangles is not on the GPU: `None`. On adapters whose storage binding limit is smaller
    /// than the object's vertex buffer, the vertices that fit.
    ///
    /// # Errors
    ///
    /// [`RenderError::Gpu`], [`RenderError::Poll`], [`RenderError::Map`].
    pub fn posed_vertices(
        &self,
        ctx: &GpuContext,
        object: usize,
    ) -> Result<Option<PosedVertices>, RenderError> {
        let Some(mesh) = self.meshes.iter().find(|m| m.object == object) else {
            return Ok(None);
        };
        ctx.scoped("reading posed vertices", || {
            crate::readback::read_posed(ctx, &mesh.bind_group, mesh.tbn_vertex_count).map(Some)
        })
    }
    /// The axis-aligned bounds of the geometry in world space, `None` when empty.
    #[must_use]
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        self.bounds
    }

    /// Number of triangles uploaded.
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        self.triangles
    }

    /// Number of objects uploaded (objects without triangles are skipped).
    #[must_use]
    pub fn object_count(&self) -> usize {
        self.meshes.len()
    }

    /// The length of the TBN lines when the frame does not set one: 2% of the bounding
    /// diagonal.
    pub(crate) fn default_tbn_length(&self) -> f32 {
        self.bounds.map_or(0.05, |(lo, hi)| (hi - lo).length() * 0.02)
    }
}

/// Uploads every material, then [`Material::default`] for objects without one (the last
/// entry), sharing each texture between the materials that use it.
fn upload_materials(
    ctx: &GpuContext,
    materials: &[Material],
    textures: &[Texture],
    options: &TextureOptions,
) -> Result<Vec<GpuMaterial>, RenderError> {
    let sheen = materials.iter().any(|m| m.extensions.sheen.is_some());
    let defaults = DefaultTextures::new(ctx, options, sheen)?;
    let mut cache = TextureCache { textures, options, views: HashMap::new() };
    let default = Material::default();
    materials
        .iter()
        .chain(std::iter::once(&default))
        .map(|material| upload_material(ctx, material, &mut cache, &defaults))
        .collect()
}

/// One material: its textures' views, its uniforms and its bind group.
fn upload_material(
    ctx: &GpuContext,
    material: &Material,
    cache: &mut TextureCache<'_>,
    defaults: &DefaultTextures,
) -> Result<GpuMaterial, RenderError> {
    let views = MaterialViews {
        base: cache.view(ctx, material, material.base_color_texture.as_ref(), TexelKind::Color)?,
        normal: cache.view(ctx, material, material.normal_texture.as_ref(), TexelKind::Normal)?,
        metallic_roughness: cache.view(
            ctx,
            material,
            material.metallic_roughness_texture.as_ref(),
            TexelKind::Data,
        )?,
        occlusion: cache.view(
            ctx,
            material,
            material.occlusion_texture.as_ref(),
            TexelKind::Data,
        )?,
        emissive: cache.view(
            ctx,
            material,
            material.emissive_texture.as_ref(),
            TexelKind::Color,
        )?,
        layers: layer_views(ctx, material, cache)?,
    };
    let mut raw = material_to_raw(material);
    if views.normal.is_none() {
        // A normal map that could not be loaded is no normal map.
        raw.flags &= !MAT_NORMAL_MAP;
    }
    if views.layers.clearcoat_normal.is_none() {
        raw.flags &= !MAT_CLEARCOAT_NORMAL_MAP;
    }
    if views.layers.anisotropy.is_none() {
        // Without its texture (none, not loaded, or not bound on this device), the
        // anisotropy's direction and strength are its factors'.
        raw.flags &= !MAT_ANISOTROPY_TEXTURE;
    }
    if views.layers.iridescence_thickness.is_none() {
        raw.iridescence_thickness_minimum = raw.iridescence_thickness;
    }
    let uniform = ctx.device().create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("seamlit material"),
        contents: bytemuck::bytes_of(&raw),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    // A glTF sampler other than the default (repeat, trilinear) gets a sampler of its own.
    let own_sampler = (material.sampling != TextureSampling::default())
        .then(|| texture::sampler_for(ctx, cache.options, &material.sampling));
    let sampler = own_sampler.as_ref().unwrap_or(&defaults.sampler);
    Ok(GpuMaterial {
        bind_group: material_bind_group(ctx, &material.name, &uniform, &views, defaults, sampler),
        double_sided: material.double_sided,
        blend: material.alpha_mode == AlphaMode::Blend,
        layers: raw.flags & MAT_LAYERS != 0,
        transmission: raw.flags & MAT_TRANSMISSION != 0,
    })
}

/// The 1x1 textures that stand in for a material's missing ones, and the material sampler.
struct DefaultTextures {
    /// White sRGB colour: base colour and emissive.
    white: wgpu::TextureView,
    /// The flat tangent-space normal.
    flat: wgpu::TextureView,
    /// White linear data: metallic-roughness and occlusion multiply their factors by it.
    white_data: wgpu::TextureView,
    /// The sheen's tables (`sheen.rs`), a storage buffer: its directional albedo
    /// E(cos, roughness), then the scale of its image-based light.
    sheen_albedo: wgpu::Buffer,
    sampler: wgpu::Sampler,
}

impl DefaultTextures {
    /// The defaults; the sheen's albedo table is computed (once per process) only where a
    /// material uses `sheen`, and is one zero otherwise.
    fn new(ctx: &GpuContext, options: &TextureOptions, sheen: bool) -> Result<Self, RenderError> {
        Ok(Self {
            white: texture::solid(ctx, "default base colour", [255; 4], TexelKind::Color)?,
            flat: texture::solid(ctx, "default normal", [128, 128, 255, 255], TexelKind::Normal)?,
            white_data: texture::solid(ctx, "default data", [255; 4], TexelKind::Data)?,
            sheen_albedo: crate::sheen::albedo_table(ctx, sheen),
            sampler: texture::sampler(ctx, options),
        })
    }
}

/// The asset's textures, each uploaded once per way it is read.
struct TextureCache<'a> {
    textures: &'a [Texture],
    options: &'a TextureOptions,
    views: HashMap<(usize, TexelKind), wgpu::TextureView>,
}

impl TextureCache<'_> {
    /// The view of the texture `r` points at, read as `kind`, uploaded on first use; `None`
    /// when `r` is `None` or the texture's image could not be loaded.
    fn view(
        &mut self,
        ctx: &GpuContext,
        material: &Material,
        r: Option<&TextureRef>,
        kind: TexelKind,
    ) -> Result<Option<wgpu::TextureView>, RenderError> {
        let Some(r) = r else { return Ok(None) };
        let tex = self.textures.get(r.texture).ok_or_else(|| RenderError::IndexOutOfRange {
            what: format!("texture (of material {:?})", material.name),
            index: r.texture,
            count: self.textures.len(),
        })?;
        let Some(image) = tex.image.as_deref() else { return Ok(None) };
        if let Some(v) = self.views.get(&(r.texture, kind)) {
            return Ok(Some(v.clone()));
        }
        let upload = ImageUpload { name: &tex.name, image, kind, mipmaps: self.options.mipmaps };
        let v = texture::upload(ctx, &upload)?;
        self.views.insert((r.texture, kind), v.clone());
        Ok(Some(v))
    }
}

/// A material's texture views, `None` where it has none.
struct MaterialViews {
    base: Option<wgpu::TextureView>,
    normal: Option<wgpu::TextureView>,
    metallic_roughness: Option<wgpu::TextureView>,
    occlusion: Option<wgpu::TextureView>,
    emissive: Option<wgpu::TextureView>,
    layers: LayerViews,
}

/// The texture views of a material's PBR extensions, `None` where it has none.
struct LayerViews {
    specular: Option<wgpu::TextureView>,
    specular_color: Option<wgpu::TextureView>,
    clearcoat: Option<wgpu::TextureView>,
    clearcoat_roughness: Option<wgpu::TextureView>,
    clearcoat_normal: Option<wgpu::TextureView>,
    sheen_color: Option<wgpu::TextureView>,
    sheen_roughness: Option<wgpu::TextureView>,
    /// Transmission, volume, iridescence and anisotropy: `None` too where the device does
    /// not bind them ([`crate::GpuContext::draws_all_extension_textures`]).
    transmission: Option<wgpu::TextureView>,
    thickness: Option<wgpu::TextureView>,
    iridescence: Option<wgpu::TextureView>,
    iridescence_thickness: Option<wgpu::TextureView>,
    anisotropy: Option<wgpu::TextureView>,
}

/// The textures of a material's PBR extensions.
fn layer_views(
    ctx: &GpuContext,
    material: &Material,
    cache: &mut TextureCache<'_>,
) -> Result<LayerViews, RenderError> {
    let ext = &material.extensions;
    let mut view = |r: Option<&TextureRef>, kind| cache.view(ctx, material, r, kind);
    let specular = ext.specular.as_ref();
    let clearcoat = ext.clearcoat.as_ref();
    let sheen = ext.sheen.as_ref();
    // Bound where the device allows them; elsewhere neither uploaded nor drawn.
    let bound = ctx.layouts.extension_textures;
    let film = ext.iridescence.as_ref().filter(|_| bound);
    let volume = ext.volume.as_ref().filter(|_| bound);
    Ok(LayerViews {
        specular: view(specular.and_then(|s| s.texture.as_ref()), TexelKind::Data)?,
        specular_color: view(specular.and_then(|s| s.color_texture.as_ref()), TexelKind::Color)?,
        clearcoat: view(clearcoat.and_then(|c| c.texture.as_ref()), TexelKind::Data)?,
        clearcoat_roughness: view(
            clearcoat.and_then(|c| c.roughness_texture.as_ref()),
            TexelKind::Data,
        )?,
        clearcoat_normal: view(
            clearcoat.and_then(|c| c.normal_texture.as_ref()),
            TexelKind::Normal,
        )?,
        sheen_color: view(sheen.and_then(|s| s.color_texture.as_ref()), TexelKind::Color)?,
        sheen_roughness: view(sheen.and_then(|s| s.roughness_texture.as_ref()), TexelKind::Data)?,
        transmission: view(
            ext.transmission.as_ref().filter(|_| bound).and_then(|t| t.texture.as_ref()),
            TexelKind::Data,
        )?,
        thickness: view(volume.and_then(|v| v.thickness_texture.as_ref()), TexelKind::Data)?,
        iridescence: view(film.and_then(|i| i.texture.as_ref()), TexelKind::Data)?,
        iridescence_thickness: view(
            film.and_then(|i| i.thickness_texture.as_ref()),
            TexelKind::Data,
        )?,
        anisotropy: view(
            ext.anisotropy.as_ref().filter(|_| bound).and_then(|a| a.texture.as_ref()),
            TexelKind::Data,
        )?,
    })
}

/// Group 1 of `mesh.wgsl`: the material's uniforms, its textures (or the defaults) and the
/// sampler.
fn material_bind_group<'a>(
    ctx: &GpuContext,
    label: &str,
    uniform: &wgpu::Buffer,
    views: &'a MaterialViews,
    defaults: &'a DefaultTextures,
    sampler: &wgpu::Sampler,
) -> wgpu::BindGroup {
    let view = |binding, view: &'a Option<wgpu::TextureView>, default: &'a wgpu::TextureView| {
        wgpu::BindGroupEntry {
            binding,
            resource: wgpu::BindingResource::TextureView(view.as_ref().unwrap_or(default)),
        }
    };
    let mut entries = vec![
        wgpu::BindGroupEntry { binding: 0, resource: uniform.as_entire_binding() },
        view(1, &views.base, &defaults.white),
        view(2, &views.normal, &defaults.flat),
        wgpu::BindGroupEntry { binding: 3, resource: wgpu::BindingResource::Sampler(sampler) },
        view(4, &views.metallic_roughness, &defaults.white_data),
        view(5, &views.occlusion, &defaults.white_data),
        view(6, &views.emissive, &defaults.white),
        view(7, &views.layers.specular, &defaults.white_data),
        view(8, &views.layers.specular_color, &defaults.white),
        view(9, &views.layers.clearcoat, &defaults.white_data),
        view(10, &views.layers.clearcoat_roughness, &defaults.white_data),
        view(11, &views.layers.clearcoat_normal, &defaults.flat),
        view(12, &views.layers.sheen_color, &defaults.white),
        view(13, &views.layers.sheen_roughness, &defaults.white_data),
        wgpu::BindGroupEntry { binding: 14, resource: defaults.sheen_albedo.as_entire_binding() },
    ];
    if ctx.layouts.extension_textures {
        let layers = &views.layers;
        entries.extend([
            view(15, &layers.transmission, &defaults.white_data),
            view(16, &layers.thickness, &defaults.white_data),
            view(17, &layers.iridescence, &defaults.white_data),
            view(18, &layers.iridescence_thickness, &defaults.white_data),
            view(19, &layers.anisotropy, &defaults.white_data),
        ]);
    }
    ctx.device().create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout: &ctx.layouts.material,
        entries: &entries,
    })
}

/// Checks an object's arrays and indices and interleaves its vertices.
pub(crate) fn interleave(object: &Object) -> Result<Vec<VertexRaw>, RenderError> {
    let n = object.positions.len();
    let bad = |what: String| RenderError::BadObject { object: object.name.clone(), what };
    let normals = object
        .normals
        .as_ref()
        .ok_or_else(|| RenderError::MissingNormals { object: object.name.clone() })?;
    let check = |name: &str, len: usize| {
        if len == n { Ok(()) } else { Err(bad(format!("{len} {name} for {n} positions"))) }
    };
    check("normals", normals.len())?;
    if let Some(t) = &object.tangents {
        check("tangents", t.len())?;
    }
    for (name, uvs) in [("uvs", &object.uvs), ("uvs1", &object.uvs1)] {
        if let Some(uv) = uvs {
            check(name, uv.len())?;
        }
    }
    if let Some(c) = &object.colors {
        check("colors", c.len())?;
    }
    if let Some((t, &i)) = object
        .triangles
        .iter()
        .enumerate()
        .find_map(|(t, tri)| tri.iter().find(|&&i| i as usize >= n).map(|i| (t, i)))
    {
        return Err(bad(format!("triangle {t} uses vertex {i}, but there are {n}")));
    }
    Ok((0..n)
        .map(|i| {
            let uv = object.uvs.as_ref().map_or([0.0; 2], |uv| uv[i].to_array());
            VertexRaw {
                position: object.positions[i].to_array(),
                normal: normals[i].to_array(),
                tangent: object.tangents.as_ref().map_or([0.0, 0.0, 0.0, 1.0], |t| t[i].to_array()),
                uv,
                color: object.colors.as_ref().map_or([1.0; 4], |c| c[i].to_array()),
                uv1: object.uvs1.as_ref().map_or(uv, |uv1| uv1[i].to_array()),
            }
        })
        .collect())
}

/// Where an object goes in the scene: its index in the model, whether V runs up, and the
/// number of materials its index must fit.
struct ObjectUpload {
    index: usize,
    flip_v: bool,
    material_count: usize,
}

/// One object: its material index checked, its vertices, indices, uniforms, skin influences
/// and morph deltas uploaded, its bind group (`empty` bound where it has no skin or targets).
fn upload_object(
    ctx: &GpuContext,
    object: &Object,
    upload: &ObjectUpload,
    empty: &wgpu::Buffer,
) -> Result<GpuMesh, RenderError> {
    let vertices = interleave(object)?;
    let material = material_index(object, upload.material_count)?;
    let deform = Deform::upload(ctx, object)?;
    let model: Mat4 = object.model_transform();
    let id = u32::try_from(upload.index).unwrap_or(u32::MAX);
    let raw = object_to_raw(object, model, id, upload.flip_v);
    // The TBN lines read the vertices as a storage buffer, which may be smaller than the
    // vertex buffer on some adapters: lines are drawn for the vertices that fit.
    let max_storage = ctx.device().limits().max_storage_buffer_binding_size;
    let tbn_vertices =
        usize::try_from(max_storage / VERTEX_SIZE).unwrap_or(usize::MAX).min(vertices.len()).max(1);
    let buffer = |contents: &[u8], usage| {
        ctx.device().create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(&object.name),
            contents,
            usage,
        })
    };
    let vertex_buffer = buffer(
        bytemuck::cast_slice(&vertices),
        wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::STORAGE,
    );
    let index_buffer = buffer(bytemuck::cast_slice(&object.triangles), wgpu::BufferUsages::INDEX);
    let uniform = buffer(
        bytemuck::bytes_of(&raw),
        wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
    );
    let bind_group = object_bind_group(
        ctx,
        &object.name,
        &ObjectBuffers { uniform: &uniform, vertices: &vertex_buffer, deform: &deform, empty },
        tbn_vertices,
    );
    let too_many = |what: &str| RenderError::BadObject {
        object: object.name.clone(),
        what: format!("too many {what} for 32-bit indices"),
    };
    Ok(GpuMesh {
        name: object.name.clone(),
        object: upload.index,
        rest: raw,
        uniform,
        deform,
        index_count: u32::try_from(object.triangles.len() * 3)
            .map_err(|_| too_many("triangles"))?,
        tbn_vertex_count: u32::try_from(tbn_vertices.min(vertices.len()))
            .map_err(|_| too_many("vertices"))?,
        vertices: vertex_buffer,
        indices: index_buffer,
        bind_group,
        material,
        mirrored: raw.det_sign < 0.0,
        posed: false,
        center: world_center(object, model),
    })
}

/// The object's material index, checked against `material_count`; objects without a
/// material get the default one, which follows the asset's materials.
fn material_index(object: &Object, material_count: usize) -> Result<usize, RenderError> {
    match object.material {
        Some(m) if m >= material_count => Err(RenderError::IndexOutOfRange {
            what: format!("material (of object {:?})", object.name),
            index: m,
            count: material_count,
        }),
        Some(m) => Ok(m),
        None => Ok(material_count),
    }
}

/// The object's uniforms under the transform `model`, unposed.
fn object_to_raw(object: &Object, model: Mat4, id: u32, flip_v: bool) -> ObjectRaw {
    let raw = ObjectRaw {
        model: [[0.0; 4]; 4],
        normal: [[0.0; 4]; 4],
        det_sign: 1.0,
        object_id: id,
        flip_v: u32::from(flip_v),
        has_tangents: u32::from(object.tangents.is_some()),
        skin_sets: 0,
        morph_targets: 0,
        vertex_count: u32::try_from(object.positions.len()).unwrap_or(u32::MAX),
        pad: 0,
    };
    transformed_raw(raw, model)
}

/// `raw` with its model matrix, normal matrix and determinant's sign those of `model`.
fn transformed_raw(raw: ObjectRaw, model: Mat4) -> ObjectRaw {
    let det = model.determinant();
    ObjectRaw {
        model: model.to_cols_array_2d(),
        normal: model.inverse().transpose().to_cols_array_2d(),
        det_sign: if det < 0.0 { -1.0 } else { 1.0 },
        ..raw
    }
}

/// The buffers of an object's bind group.
struct ObjectBuffers<'a> {
    uniform: &'a wgpu::Buffer,
    vertices: &'a wgpu::Buffer,
    deform: &'a Deform,
    /// Bound where the object has no skin, deltas or pose buffers.
    empty: &'a wgpu::Buffer,
}

/// Group 2 of `mesh.wgsl`: the object's uniforms, its first `tbn_vertices` vertices as
/// storage (for the TBN lines and the posed-vertex readback), its skin influences and morph
/// deltas, its pose's palette and weights.
fn object_bind_group<'a>(
    ctx: &GpuContext,
    label: &str,
    buffers: &ObjectBuffers<'a>,
    tbn_vertices: usize,
) -> wgpu::BindGroup {
    let d = buffers.deform;
    let empty = buffers.empty;
    let storage = |binding, buffer: &'a Option<wgpu::Buffer>| wgpu::BindGroupEntry {
        binding,
        resource: buffer.as_ref().unwrap_or(empty).as_entire_binding(),
    };
    ctx.device().create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout: &ctx.layouts.object,
        entries: &[
            wgpu::BindGroupEntry { binding: 0, resource: buffers.uniform.as_entire_binding() },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: buffers.vertices,
                    offset: 0,
                    size: wgpu::BufferSize::new(tbn_vertices as u64 * VERTEX_SIZE),
                }),
            },
            storage(2, &d.skin),
            storage(3, &d.morph),
            storage(4, &d.palette),
            storage(5, &d.weights),
        ],
    })
}

/// The centre of an object's bounds after `model`, the point blended objects are sorted by.
fn world_center(object: &Object, model: Mat4) -> Vec3 {
    let (lo, hi) = object.positions.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), &p| {
            let w = model.transform_point3(p);
            (lo.min(w), hi.max(w))
        },
    );
    if lo.cmple(hi).all() { (lo + hi) * 0.5 } else { Vec3::ZERO }
}

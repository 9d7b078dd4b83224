//! A material as the shaders read it (`Material` in `mesh.wgsl`): its flags, factors, texture
//! transforms and the PBR extensions' parameters, from seamlit-io's `Material`.

use bytemuck::{Pod, Zeroable};
use seamlit_asset::{AlphaMode, Material, PbrExtensions, TextureRef, Volume};

/// Material flag: the material has a normal map.
pub(crate) const MAT_NORMAL_MAP: u32 = 1;
/// Material flag: the normal map is green-down (DirectX).
const MAT_GREEN_DOWN: u32 = 2;
/// Material flag: back faces are drawn and lit from behind.
const MAT_DOUBLE_SIDED: u32 = 4;
/// Material flag: alphaMode MASK, pixels under the cutoff are discarded.
const MAT_ALPHA_MASK: u32 = 8;
/// Material flag: alphaMode BLEND, the pixel's alpha is written for blending.
const MAT_ALPHA_BLEND: u32 = 16;
/// Material flag: KHR_materials_unlit.
const MAT_UNLIT: u32 = 32;
/// Material flag: KHR_materials_clearcoat (a coat layer is drawn).
const MAT_CLEARCOAT: u32 = 64;
/// Material flag: the clearcoat has a normal map.
pub(crate) const MAT_CLEARCOAT_NORMAL_MAP: u32 = 128;
/// Material flag: KHR_materials_sheen.
const MAT_SHEEN: u32 = 256;
/// Material flag: KHR_materials_specular or KHR_materials_ior (the dielectric's f0 and f90
/// are the material's; the specular and specular colour textures are read).
const MAT_SPECULAR: u32 = 512;
/// Material flag: KHR_materials_anisotropy.
const MAT_ANISOTROPY: u32 = 1024;
/// Material flag: KHR_materials_transmission (and _volume): what lies behind is seen through
/// the surface, from the renderer's transmission target.
pub(crate) const MAT_TRANSMISSION: u32 = 2048;
/// Material flag: KHR_materials_iridescence.
const MAT_IRIDESCENCE: u32 = 4096;
/// Material flag: KHR_materials_anisotropy has a texture (its direction and strength are
/// read from it; without, the direction is the tangent's and the strength the factor's).
pub(crate) const MAT_ANISOTROPY_TEXTURE: u32 = 8192;
/// Any of the flags of the PBR extensions' layers.
pub(crate) const MAT_LAYERS: u32 =
    MAT_CLEARCOAT | MAT_SHEEN | MAT_SPECULAR | MAT_ANISOTROPY | MAT_TRANSMISSION | MAT_IRIDESCENCE;

/// Material uniforms (`Material` in `mesh.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub(crate) struct MaterialRaw {
    pub base_color: [f32; 4],
    pub specular: [f32; 3],
    pub shininess: f32,
    pub base_uv: [[f32; 4]; 2],
    pub normal_uv: [[f32; 4]; 2],
    pub metallic_roughness_uv: [[f32; 4]; 2],
    pub occlusion_uv: [[f32; 4]; 2],
    pub emissive_uv: [[f32; 4]; 2],
    pub emissive: [f32; 3],
    pub normal_scale: f32,
    pub metallic: f32,
    pub roughness: f32,
    pub occlusion_strength: f32,
    pub alpha_cutoff: f32,
    pub flags: u32,
    pub pad: [u32; 3],
    /// KHR_materials_specular's texture slots (alpha: strength; RGB: colour), then
    /// clearcoat's (factor, roughness, normal) and sheen's (colour, roughness).
    pub specular_uv: [[f32; 4]; 2],
    pub specular_color_uv: [[f32; 4]; 2],
    pub clearcoat_uv: [[f32; 4]; 2],
    pub clearcoat_roughness_uv: [[f32; 4]; 2],
    pub clearcoat_normal_uv: [[f32; 4]; 2],
    pub sheen_color_uv: [[f32; 4]; 2],
    pub sheen_roughness_uv: [[f32; 4]; 2],
    /// The dielectric's f0 (KHR_materials_ior: ((ior - 1) / (ior + 1))^2, 0.04 by default)
    /// times KHR_materials_specular's colour, and its strength (`specularFactor`).
    pub f0_dielectric: [f32; 3],
    pub specular_weight: f32,
    /// KHR_materials_sheen's colour and roughness.
    pub sheen_color: [f32; 3],
    pub sheen_roughness: f32,
    /// KHR_materials_clearcoat's factor, roughness and normal scale, and its f0 (from the
    /// material's ior).
    pub clearcoat: f32,
    pub clearcoat_roughness: f32,
    pub clearcoat_normal_scale: f32,
    pub clearcoat_f0: f32,
    /// KHR_materials_anisotropy: cos and sin of its rotation, its strength.
    pub anisotropy: [f32; 3],
    pub pad1: f32,
    /// KHR_materials_transmission's factor; KHR_materials_volume's thickness (mesh units),
    /// attenuation distance (0: none) and colour; the ior (KHR_materials_ior, 1.5 by
    /// default) that refracts the view through the volume.
    pub transmission: f32,
    pub thickness: f32,
    pub attenuation_distance: f32,
    pub ior: f32,
    pub attenuation_color: [f32; 3],
    pub pad2: f32,
    /// KHR_materials_iridescence: its factor, the film's ior and its thickness (nm) at the
    /// thickness texture's green 1, its maximum (see `iridescence_thickness_minimum`).
    pub iridescence: f32,
    pub iridescence_ior: f32,
    pub iridescence_thickness: f32,
    /// KHR_materials_dispersion (with a volume): the ior's spread, 20 / Abbe number.
    pub dispersion: f32,
    /// The texture slots of transmission (red), volume's thickness (green), iridescence
    /// (red), its thickness (green) and anisotropy (red-green direction, blue strength).
    pub transmission_uv: [[f32; 4]; 2],
    pub thickness_uv: [[f32; 4]; 2],
    pub iridescence_uv: [[f32; 4]; 2],
    pub iridescence_thickness_uv: [[f32; 4]; 2],
    pub anisotropy_uv: [[f32; 4]; 2],
    /// The film's thickness (nm) at the thickness texture's green 0: its minimum, or its
    /// maximum where it has no thickness texture (so that the film is the maximum).
    pub iridescence_thickness_minimum: f32,
    pub pad3: [f32; 3],
}

/// The rows of the 2x3 affine UV matrix of KHR_texture_transform, `T * R * S`, and in the
/// first row's `w` the texture coordinate set the slot reads (1: TEXCOORD_1, else
/// TEXCOORD_0).
fn uv_rows(texture: Option<&TextureRef>) -> [[f32; 4]; 2] {
    let set = texture.map_or(0.0, |r| if r.tex_coord == 1 { 1.0 } else { 0.0 });
    let Some(t) = texture.and_then(|r| r.transform.as_ref()) else {
        return [[1.0, 0.0, 0.0, set], [0.0, 1.0, 0.0, 0.0]];
    };
    let (s, c) = t.rotation.sin_cos();
    [
        [c * t.scale[0], s * t.scale[1], t.offset[0], set],
        [-s * t.scale[0], c * t.scale[1], t.offset[1], 0.0],
    ]
}

/// Builds a material's uniforms: the core material's, then its extensions'.
pub(crate) fn material_to_raw(material: &Material) -> MaterialRaw {
    let (flags, alpha_cutoff) = core_flags(material);
    let slot_uv = |r: &Option<TextureRef>| uv_rows(r.as_ref());
    let mut raw = MaterialRaw {
        base_color: material.base_color,
        specular: material.specular,
        // pow(0, 0) is undefined in WGSL: keep the exponent positive.
        shininess: material.shininess.max(1e-3),
        base_uv: slot_uv(&material.base_color_texture),
        normal_uv: slot_uv(&material.normal_texture),
        metallic_roughness_uv: slot_uv(&material.metallic_roughness_texture),
        occlusion_uv: slot_uv(&material.occlusion_texture),
        emissive_uv: slot_uv(&material.emissive_texture),
        emissive: material.emissive,
        normal_scale: material.normal_scale,
        metallic: material.metallic.clamp(0.0, 1.0),
        roughness: material.roughness.clamp(0.0, 1.0),
        occlusion_strength: material.occlusion_strength.clamp(0.0, 1.0),
        alpha_cutoff,
        flags: flags | extension_flags(&material.extensions),
        ..MaterialRaw::zeroed()
    };
    set_texture_slots(&mut raw, &material.extensions);
    set_surface_layers(&mut raw, &material.extensions);
    set_volume_and_film(&mut raw, &material.extensions);
    raw
}

/// The core material's flags (normal map, green down, double-sided, unlit, alpha mode) and
/// its alpha cutoff (0 unless MASK).
fn core_flags(material: &Material) -> (u32, f32) {
    let mut flags = 0;
    if material.normal_texture.is_some() {
        flags |= MAT_NORMAL_MAP;
    }
    if material.normal_green_down {
        flags |= MAT_GREEN_DOWN;
    }
    if material.double_sided {
        flags |= MAT_DOUBLE_SIDED;
    }
    if material.unlit {
        flags |= MAT_UNLIT;
    }
    match material.alpha_mode {
        AlphaMode::Opaque => (flags, 0.0),
        AlphaMode::Mask { cutoff } => (flags | MAT_ALPHA_MASK, cutoff),
        AlphaMode::Blend => (flags | MAT_ALPHA_BLEND, 0.0),
    }
}

/// The flags of the PBR extensions a material uses.
fn extension_flags(ext: &PbrExtensions) -> u32 {
    let flag = |used: bool, flag: u32| if used { flag } else { 0 };
    flag(ext.ior.is_some() || ext.specular.is_some(), MAT_SPECULAR)
        | flag(ext.clearcoat.is_some(), MAT_CLEARCOAT)
        | flag(
            ext.clearcoat.as_ref().is_some_and(|c| c.normal_texture.is_some()),
            MAT_CLEARCOAT_NORMAL_MAP,
        )
        | flag(ext.sheen.is_some(), MAT_SHEEN)
        | flag(ext.anisotropy.is_some(), MAT_ANISOTROPY)
        | flag(ext.anisotropy.as_ref().is_some_and(|a| a.texture.is_some()), MAT_ANISOTROPY_TEXTURE)
        | flag(ext.transmission.is_some(), MAT_TRANSMISSION)
        | flag(ext.iridescence.is_some(), MAT_IRIDESCENCE)
}

/// KHR_materials_volume, read only with KHR_materials_transmission (its specification:
/// alone it changes nothing).
fn volume(ext: &PbrExtensions) -> Option<&Volume> {
    ext.volume.as_ref().filter(|_| ext.transmission.is_some())
}

/// The texture slots of the extensions (the identity, TEXCOORD_0, where a material has no
/// such texture).
fn set_texture_slots(raw: &mut MaterialRaw, ext: &PbrExtensions) {
    let slot = |r: Option<&Option<TextureRef>>| uv_rows(r.and_then(Option::as_ref));
    let (specular, clearcoat, sheen) = (&ext.specular, &ext.clearcoat, &ext.sheen);
    raw.specular_uv = slot(specular.as_ref().map(|s| &s.texture));
    raw.specular_color_uv = slot(specular.as_ref().map(|s| &s.color_texture));
    raw.clearcoat_uv = slot(clearcoat.as_ref().map(|c| &c.texture));
    raw.clearcoat_roughness_uv = slot(clearcoat.as_ref().map(|c| &c.roughness_texture));
    raw.clearcoat_normal_uv = slot(clearcoat.as_ref().map(|c| &c.normal_texture));
    raw.sheen_color_uv = slot(sheen.as_ref().map(|s| &s.color_texture));
    raw.sheen_roughness_uv = slot(sheen.as_ref().map(|s| &s.roughness_texture));
    raw.transmission_uv = slot(ext.transmission.as_ref().map(|t| &t.texture));
    raw.thickness_uv = slot(volume(ext).map(|v| &v.thickness_texture));
    raw.iridescence_uv = slot(ext.iridescence.as_ref().map(|i| &i.texture));
    raw.iridescence_thickness_uv = slot(ext.iridescence.as_ref().map(|i| &i.thickness_texture));
    raw.anisotropy_uv = slot(ext.anisotropy.as_ref().map(|a| &a.texture));
}

/// The layers on the surface: ior and specular (the dielectric's f0 and strength), sheen,
/// clearcoat and anisotropy.
fn set_surface_layers(raw: &mut MaterialRaw, ext: &PbrExtensions) {
    // KHR_materials_ior: f0 = ((ior - 1) / (ior + 1))^2; glTF's default 1.5 gives 0.04.
    let f0 = ext.ior.map_or(0.04, |ior| ((ior - 1.0) / (ior + 1.0)).powi(2));
    let specular = ext.specular.as_ref();
    let clearcoat = ext.clearcoat.as_ref();
    let sheen = ext.sheen.as_ref();
    raw.f0_dielectric = specular.map_or([f0; 3], |s| s.color.map(|c| (f0 * c).clamp(0.0, 1.0)));
    raw.specular_weight = specular.map_or(1.0, |s| s.factor.max(0.0));
    raw.sheen_color = sheen.map_or([0.0; 3], |s| s.color.map(|c| c.max(0.0)));
    raw.sheen_roughness = sheen.map_or(0.0, |s| s.roughness.clamp(0.0, 1.0));
    raw.clearcoat = clearcoat.map_or(0.0, |c| c.factor.clamp(0.0, 1.0));
    raw.clearcoat_roughness = clearcoat.map_or(0.0, |c| c.roughness.clamp(0.0, 1.0));
    raw.clearcoat_normal_scale = clearcoat.map_or(1.0, |c| c.normal_scale);
    raw.clearcoat_f0 = f0;
    raw.anisotropy = ext.anisotropy.as_ref().map_or([1.0, 0.0, 0.0], |a| {
        let (sin, cos) = a.rotation.sin_cos();
        [cos, sin, a.strength.clamp(0.0, 1.0)]
    });
}

/// Transmission and its volume (the ior refracts through it), dispersion, and the
/// iridescent film.
fn set_volume_and_film(raw: &mut MaterialRaw, ext: &PbrExtensions) {
    let volume = volume(ext);
    raw.transmission = ext.transmission.as_ref().map_or(0.0, |t| t.factor.clamp(0.0, 1.0));
    raw.thickness = volume.map_or(0.0, |v| v.thickness.max(0.0));
    raw.attenuation_distance = volume.and_then(|v| v.attenuation_distance).unwrap_or(0.0);
    raw.ior = ext.ior.unwrap_or(1.5).max(1.0);
    raw.attenuation_color =
        volume.map_or([1.0; 3], |v| v.attenuation_color.map(|c| c.clamp(0.0, 1.0)));
    raw.dispersion = volume.and(ext.dispersion).map_or(0.0, |d| d.max(0.0));
    let film = ext.iridescence.as_ref();
    raw.iridescence = film.map_or(0.0, |i| i.factor.clamp(0.0, 1.0));
    raw.iridescence_ior = film.map_or(1.3, |i| i.ior.max(1.0));
    raw.iridescence_thickness = film.map_or(0.0, |i| i.thickness_maximum.max(0.0));
    raw.iridescence_thickness_minimum = match film {
        Some(i) if i.thickness_texture.is_some() => i.thickness_minimum.max(0.0),
        _ => raw.iridescence_thickness,
    };
}

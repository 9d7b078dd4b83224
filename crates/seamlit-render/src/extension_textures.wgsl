// The textures of KHR_materials_transmission, _volume, _iridescence and _anisotropy, bound
// where the device allows 21 sampled textures a fragment stage (context.rs); elsewhere
// extension_textures_unbound.wgsl stands in for this file. shaders.rs appends one of them to
// mesh.wgsl.
@group(1) @binding(15) var transmission_texture: texture_2d<f32>;
@group(1) @binding(16) var thickness_texture: texture_2d<f32>;
@group(1) @binding(17) var iridescence_texture: texture_2d<f32>;
@group(1) @binding(18) var iridescence_thickness_texture: texture_2d<f32>;
@group(1) @binding(19) var anisotropy_texture: texture_2d<f32>;

// What those textures say at this pixel, each through its own texture coordinate set and
// KHR_texture_transform, in the channels their specifications name: transmission (red),
// thickness (green), iridescence (red), iridescence thickness (green: from the minimum to
// the maximum), anisotropy (red-green: a direction, blue: strength). A missing texture is
// white (1 x 1): its factor alone.
fn extension_samples(g: UvGrads) -> ExtensionSamples {
    var out: ExtensionSamples;
    out.transmission = sample_slot(transmission_texture, material.transmission_uv, g).r;
    out.thickness = sample_slot(thickness_texture, material.thickness_uv, g).g;
    out.iridescence = sample_slot(iridescence_texture, material.iridescence_uv, g).r;
    out.iridescence_thickness = sample_slot(iridescence_thickness_texture, material.iridescence_thickness_uv, g).g;
    out.anisotropy = sample_slot(anisotropy_texture, material.anisotropy_uv, g).rgb;
    return out;
}

// extension_textures.wgsl's stand-in for devices with fewer than 21 sampled textures a
// fragment stage: no texture of transmission, volume, iridescence or anisotropy is bound,
// and each reads as white (their factors alone; material.rs leaves MAT_ANISOTROPY_TEXTURE
// unset and the film at its maximum thickness there).
fn extension_samples(g: UvGrads) -> ExtensionSamples {
    var out: ExtensionSamples;
    out.transmission = 1.0;
    out.thickness = 1.0;
    out.iridescence = 1.0;
    out.iridescence_thickness = 1.0;
    out.anisotropy = vec3<f32>(1.0);
    return out;
}

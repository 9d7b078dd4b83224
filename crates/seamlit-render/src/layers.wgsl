// The PBR extension layers of the scene pass: mesh.wgsl's fragment stage calls them, and
// shaders.rs appends this file to it (same bindings and structs). At its end, the material's
// layers at a pixel (material_layers): its factors times its textures, read with explicit
// gradients (sample_slot).

// The PBR extensions that add to the metallic-roughness BRDF, as their glTF specifications
// define them and the Khronos glTF Sample Viewer composes them (read for the maths, written
// here anew): KHR_materials_ior and _specular change the dielectric's Fresnel term
// (f0 = ((ior - 1) / (ior + 1))^2 times the specular colour, both f0 and f90 times the
// specular strength); KHR_materials_sheen adds a Charlie sheen lobe over the material and
// scales what lies under it by 1 - max(sheen colour) * E (its directional albedo, sheen.rs);
// KHR_materials_clearcoat mixes a clear GGX layer (its own roughness and normal) over all of
// it by clearcoat * Fresnel(n_c.v). Drawn only for materials that use one (MAT_LAYERS): a
// material without them takes shade_pbr and shade_environment as before.
struct Layers {
    // The dielectric's f0 (ior, specular colour) and its strength (the specular factor).
    f0_dielectric: vec3<f32>,
    specular_weight: f32,
    sheen_color: vec3<f32>,
    sheen_roughness: f32,
    // The clearcoat's normal, factor, roughness and f0.
    clearcoat_n: vec3<f32>,
    clearcoat: f32,
    clearcoat_roughness: f32,
    clearcoat_f0: f32,
    // KHR_materials_anisotropy: the direction of the stretch (t) and across it (b) in world
    // space, and the strength (0: none, the isotropic lobe).
    anisotropy_t: vec3<f32>,
    anisotropy_b: vec3<f32>,
    anisotropy: f32,
    // KHR_materials_transmission's factor (0: opaque), and with KHR_materials_volume the
    // path through the volume from this point (refracted by the ior, as long as the thickness
    // in world units: zero for a thin wall) and how it absorbs (attenuation distance, 0: it
    // does not, and colour).
    transmission: f32,
    ior: f32,
    volume_ray: vec3<f32>,
    attenuation_distance: f32,
    attenuation_color: vec3<f32>,
    // The volume's thickness (mesh units) and KHR_materials_dispersion's spread of its ior.
    thickness: f32,
    dispersion: f32,
    // KHR_materials_iridescence's factor (0: none) and the film's Fresnel terms at this
    // pixel's view angle over the dielectric and over the metal (iridescence_fresnel).
    iridescence: f32,
    iridescence_dielectric: vec3<f32>,
    iridescence_metal: vec3<f32>,
}

// KHR_materials_anisotropy's GGX lobe, D times V, stretched along t: alpha along t is
// mix(alpha, 1, strength^2), across it alpha (the extension's specification, "BRDF").
fn ggx_dv_anisotropic(alpha: f32, strength: f32, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>, h: vec3<f32>, t: vec3<f32>, b: vec3<f32>) -> f32 {
    let at = mix(alpha, 1.0, strength * strength);
    let ab = clamp(alpha, 0.001, 1.0);
    let n_dot_l = clamp(dot(n, l), 0.0, 1.0);
    let n_dot_h = clamp(dot(n, h), 0.001, 1.0);
    let n_dot_v = dot(n, v);
    let a2 = at * ab;
    let f = vec3<f32>(ab * dot(t, h), at * dot(b, h), a2 * n_dot_h);
    let w2 = a2 / dot(f, f);
    let d = a2 * w2 * w2 / PI;
    let ggx_v = n_dot_l * length(vec3<f32>(at * dot(t, v), ab * dot(b, v), n_dot_v));
    let ggx_l = n_dot_v * length(vec3<f32>(at * dot(t, l), ab * dot(b, l), n_dot_l));
    let vis = clamp(0.5 / (ggx_v + ggx_l), 0.0, 1.0);
    return d * vis;
}

// GGX distribution times height-correlated Smith visibility (Appendix B), with alpha kept
// above 1e-3 as in shade_pbr.
fn ggx_dv(alpha: f32, n_dot_l: f32, n_dot_v: f32, n_dot_h: f32) -> f32 {
    let a2 = max(alpha, 1e-3) * max(alpha, 1e-3);
    let dd = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0;
    let distribution = a2 / (PI * dd * dd);
    let vis_denom = n_dot_l * sqrt(n_dot_v * n_dot_v * (1.0 - a2) + a2)
        + n_dot_v * sqrt(n_dot_l * n_dot_l * (1.0 - a2) + a2);
    return distribution * select(0.0, 0.5 / vis_denom, vis_denom > 0.0);
}

// The sheen's Charlie distribution (Estevez and Kulla 2017).
fn charlie_d(roughness: f32, n_dot_h: f32) -> f32 {
    let inv = 1.0 / (max(roughness, 1e-6) * max(roughness, 1e-6));
    let sin2 = max(1.0 - n_dot_h * n_dot_h, 0.0);
    return (2.0 + inv) * pow(sin2, inv * 0.5) / (2.0 * PI);
}

// Estevez and Kulla's fitted lambda for the sheen's visibility.
fn sheen_lambda_fit(x: f32, alpha: f32) -> f32 {
    let t = (1.0 - alpha) * (1.0 - alpha);
    let a = mix(21.5473, 25.3245, t);
    let b = mix(3.82987, 3.32435, t);
    let c = mix(0.19823, 0.16801, t);
    let d = mix(-1.97760, -1.27393, t);
    let e = mix(-4.32054, -4.85967, t);
    return a / (1.0 + b * pow(x, c)) + d * x + e;
}

fn sheen_lambda(cos_theta: f32, alpha: f32) -> f32 {
    if abs(cos_theta) < 0.5 {
        return exp(sheen_lambda_fit(cos_theta, alpha));
    }
    return exp(2.0 * sheen_lambda_fit(0.5, alpha) - sheen_lambda_fit(1.0 - cos_theta, alpha));
}

fn sheen_v(n_dot_l: f32, n_dot_v: f32, roughness: f32) -> f32 {
    let alpha = max(roughness, 1e-6) * max(roughness, 1e-6);
    let denom = (1.0 + sheen_lambda(n_dot_v, alpha) + sheen_lambda(n_dot_l, alpha)) * (4.0 * n_dot_v * n_dot_l);
    return clamp(1.0 / denom, 0.0, 1.0);
}

// Entries a side of the sheen's tables (sheen.rs SIZE).
const SHEEN_TABLE_SIZE: u32 = 32u;
// The sheen's Charlie-prefiltered environment: the irradiance cube's mips 1 to SHEEN_MIPS,
// mip 1 + m for sheen roughness m / (SHEEN_MIPS - 1) (environment.rs SHEEN_MIPS).
const SHEEN_MIPS: u32 = 5u;

// Entry (cos, roughness) of the sheen's table that starts at `first` in sheen_albedo_table,
// filtered bilinearly between entry centres and clamped at the edges (as the reference
// viewer's texture lookup is).
fn sheen_table(first: u32, cos_theta: f32, roughness: f32) -> f32 {
    let last = f32(SHEEN_TABLE_SIZE - 1u);
    let p = clamp(vec2<f32>(cos_theta, roughness) * f32(SHEEN_TABLE_SIZE) - 0.5, vec2<f32>(0.0), vec2<f32>(last));
    let i0 = vec2<u32>(floor(p));
    let i1 = min(i0 + 1u, vec2<u32>(SHEEN_TABLE_SIZE - 1u));
    let f = p - floor(p);
    let row0 = mix(sheen_albedo_table[first + i0.y * SHEEN_TABLE_SIZE + i0.x], sheen_albedo_table[first + i0.y * SHEEN_TABLE_SIZE + i1.x], f.x);
    let row1 = mix(sheen_albedo_table[first + i1.y * SHEEN_TABLE_SIZE + i0.x], sheen_albedo_table[first + i1.y * SHEEN_TABLE_SIZE + i1.x], f.x);
    return mix(row0, row1, f.y);
}

// The sheen's directional albedo E(cos, roughness) (the first table).
fn sheen_albedo(cos_theta: f32, roughness: f32) -> f32 {
    return sheen_table(0u, cos_theta, roughness);
}

// The scale of the sheen's image-based light (the second table: the Sample Viewer's Charlie
// table, sheen.rs environment_scale).
fn sheen_environment_scale(cos_theta: f32, roughness: f32) -> f32 {
    return sheen_table(SHEEN_TABLE_SIZE * SHEEN_TABLE_SIZE, cos_theta, roughness);
}

fn max3(c: vec3<f32>) -> f32 {
    return max(c.r, max(c.g, c.b));
}

// Direct light with the layers: rgb the colour under the clearcoat (base, specular, sheen),
// summed over the lights, and (second) the clearcoat's own lobe, summed likewise; the caller
// mixes them by clearcoat * Fresnel.
struct LayeredLight {
    base: vec3<f32>,
    coat: vec3<f32>,
}

fn shade_layers(n: vec3<f32>, v: vec3<f32>, p: vec3<f32>, albedo: vec3<f32>, metallic: f32, alpha: f32, layers: Layers) -> LayeredLight {
    var out: LayeredLight;
    out.base = vec3<f32>(0.0);
    out.coat = vec3<f32>(0.0);
    let n_dot_v = max(abs(dot(n, v)), 1e-4);
    let cc_n_dot_v = max(dot(layers.clearcoat_n, v), 1e-4);
    let sheen = (material.flags & MAT_SHEEN) != 0u;
    let sheen_max = max3(layers.sheen_color);
    let sheen_e_v = select(0.0, sheen_albedo(n_dot_v, layers.sheen_roughness), sheen);
    let f0 = layers.f0_dielectric * layers.specular_weight;
    let f90 = layers.specular_weight;
    for (var i = 0u; i < frame.light_count; i = i + 1u) {
        let light = lights[i];
        let inc = incidence(light, p);
        if inc.w <= 0.0 {
            continue;
        }
        let l = inc.xyz;
        let radiance = light.color * inc.w * shadow_factor(light, p, n);
        let h = safe_normalize(l + v, n);
        let v_dot_h = max(dot(v, h), 0.0);
        // pow of a negative base is undefined in WGSL: v.h can round above 1.
        let schlick = pow(max(1.0 - v_dot_h, 0.0), 5.0);
        let n_dot_l = max(dot(n, l), 0.0);
        // A transmissive surface is lit through from behind too.
        if n_dot_l > 0.0 || layers.transmission > 0.0 {
            let n_dot_h = max(dot(n, h), 0.0);
            let fresnel_dielectric = f0 + (vec3<f32>(f90) - f0) * schlick;
            let fresnel_metal = albedo + (1.0 - albedo) * schlick;
            var diffuse = radiance * n_dot_l * albedo / PI;
            if layers.transmission > 0.0 {
                // KHR_materials_transmission: the light that reaches the point through the
                // surface (towards the light from where the view leaves the volume), by the
                // transmission lobe, mixed into the diffuse by the factor.
                let to_light = select(light.position - p, -light.direction, light.kind == LIGHT_DIRECTIONAL);
                let lt = safe_normalize(to_light - layers.volume_ray, n);
                let through = radiance * transmission_lobe(n, v, lt, alpha, albedo, layers);
                diffuse = mix(diffuse, volume_attenuation(through, length(layers.volume_ray), layers), layers.transmission);
            }
            var lobe = ggx_dv(alpha, n_dot_l, n_dot_v, n_dot_h);
            if layers.anisotropy > 0.0 {
                lobe = ggx_dv_anisotropic(alpha, layers.anisotropy, n, v, l, h, layers.anisotropy_t, layers.anisotropy_b);
            }
            let specular = radiance * n_dot_l * lobe;
            var dielectric = mix(diffuse, specular, fresnel_dielectric);
            var metal = fresnel_metal * specular;
            if layers.iridescence > 0.0 {
                dielectric = mix(dielectric, rgb_mix(diffuse, specular, layers.iridescence_dielectric), layers.iridescence);
                metal = mix(metal, specular * layers.iridescence_metal, layers.iridescence);
            }
            var color = mix(dielectric, metal, metallic);
            if sheen {
                let lobe = radiance * n_dot_l * layers.sheen_color
                    * charlie_d(layers.sheen_roughness, n_dot_h) * sheen_v(n_dot_l, n_dot_v, layers.sheen_roughness);
                let scale = min(1.0 - sheen_max * sheen_e_v, 1.0 - sheen_max * sheen_albedo(n_dot_l, layers.sheen_roughness));
                color = lobe + color * scale;
            }
            out.base = out.base + color;
        }
        let cc_n_dot_l = max(dot(layers.clearcoat_n, l), 0.0);
        if layers.clearcoat > 0.0 && cc_n_dot_l > 0.0 {
            let cc_n_dot_h = max(dot(layers.clearcoat_n, h), 0.0);
            let cc_alpha = layers.clearcoat_roughness * layers.clearcoat_roughness;
            out.coat = out.coat + radiance * cc_n_dot_l * ggx_dv(cc_alpha, cc_n_dot_l, cc_n_dot_v, cc_n_dot_h);
        }
    }
    return out;
}

// The environment's light with the layers, under (base) and of (coat) the clearcoat. The
// sheen's environment term is the Sample Viewer's (ibl.glsl getIBLRadianceCharlie): the
// Charlie-prefiltered environment about the mirror direction at the sheen roughness, times
// the sheen colour and its environment scale; what lies under it is scaled by 1 - max(sheen
// colour) E, as under direct light.
fn shade_environment_layers(n: vec3<f32>, v: vec3<f32>, albedo: vec3<f32>, metallic: f32, roughness: f32, layers: Layers) -> LayeredLight {
    var out: LayeredLight;
    let n_dot_v = clamp(abs(dot(n, v)), 1e-3, 1.0);
    let ab = brdf_lut_ab(n_dot_v, roughness);
    // Anisotropy reflects about a normal bent towards the stretch (the extension's
    // image-based approximation).
    var reflect_n = n;
    if layers.anisotropy > 0.0 {
        let across = cross(layers.anisotropy_b, v);
        let stretched = cross(across, layers.anisotropy_b);
        let bend = 1.0 - layers.anisotropy * (1.0 - roughness);
        reflect_n = safe_normalize(mix(stretched, n, bend * bend * bend * bend), n);
    }
    let r = environment_direction(reflect(-v, reflect_n));
    let specular = textureSampleLevel(environment_specular, environment_sampler, r, roughness * frame.environment_max_lod).rgb;
    let irradiance = textureSampleLevel(environment_irradiance, environment_sampler, environment_direction(n), 0.0).rgb;
    let fresnel_dielectric = environment_fresnel(layers.f0_dielectric, ab, n_dot_v, roughness, layers.specular_weight);
    // What transmission sees through replaces the diffuse by its factor (added by the
    // caller, transmission_ambient).
    let diffuse = irradiance * albedo * (1.0 - layers.transmission);
    var dielectric = mix(diffuse, specular, fresnel_dielectric);
    var metal = specular * environment_fresnel(albedo, ab, n_dot_v, roughness, 1.0);
    if layers.iridescence > 0.0 {
        dielectric = mix(dielectric, rgb_mix(diffuse, specular, layers.iridescence_dielectric), layers.iridescence);
        metal = mix(metal, specular * layers.iridescence_metal, layers.iridescence);
    }
    var color = mix(dielectric, metal, metallic);
    if (material.flags & MAT_SHEEN) != 0u {
        let mirror = environment_direction(reflect(-v, n));
        let lod = 1.0 + layers.sheen_roughness * f32(SHEEN_MIPS - 1u);
        let sheen_light = textureSampleLevel(environment_irradiance, environment_sampler, mirror, lod).rgb;
        let lobe = sheen_light * layers.sheen_color * sheen_environment_scale(n_dot_v, layers.sheen_roughness);
        color = lobe + color * (1.0 - max3(layers.sheen_color) * sheen_albedo(n_dot_v, layers.sheen_roughness));
    }
    out.base = color * frame.environment_intensity;
    let rc = environment_direction(reflect(-v, layers.clearcoat_n));
    out.coat = textureSampleLevel(environment_specular, environment_sampler, rc, layers.clearcoat_roughness * frame.environment_max_lod).rgb * frame.environment_intensity;
    return out;
}

// KHR_materials_transmission's lobe for light from `l` behind the surface: GGX about the
// direction mirrored through the surface, at the roughness the ior widens (alpha times
// clamp(2 ior - 2, 0, 1), as the Sample Viewer's applyIorToRoughness), times what the
// dielectric's Fresnel term lets in and the base colour.
fn transmission_lobe(n: vec3<f32>, v: vec3<f32>, l: vec3<f32>, alpha: f32, albedo: vec3<f32>, layers: Layers) -> vec3<f32> {
    let rough = alpha * clamp(layers.ior * 2.0 - 2.0, 0.0, 1.0);
    let l_mirror = safe_normalize(l + 2.0 * n * dot(-l, n), n);
    let h = safe_normalize(l_mirror + v, n);
    let fresnel = layers.f0_dielectric + (1.0 - layers.f0_dielectric) * pow(1.0 - clamp(dot(v, h), 0.0, 1.0), 5.0);
    let lobe = ggx_dv(rough, clamp(dot(n, l_mirror), 0.0, 1.0), clamp(dot(n, v), 0.0, 1.0), clamp(dot(n, h), 0.0, 1.0));
    return (1.0 - fresnel) * albedo * lobe;
}

// KHR_materials_volume's absorption over `distance`: the attenuation colour to the power of
// the distance over the attenuation distance (none without one).
fn volume_attenuation(radiance: vec3<f32>, distance: f32, layers: Layers) -> vec3<f32> {
    if layers.attenuation_distance <= 0.0 {
        return radiance;
    }
    return pow(layers.attenuation_color, vec3<f32>(distance / layers.attenuation_distance)) * radiance;
}

// The view's path through the volume from a point: the view direction refracted by the ior,
// as long as the thickness scaled by the object's transform (zero for a thin wall).
fn volume_ray(n: vec3<f32>, v: vec3<f32>, thickness: f32, ior: f32) -> vec3<f32> {
    let r = safe_normalize(refract(-v, n, 1.0 / ior), -v);
    let scale = vec3<f32>(length(object.model[0].xyz), length(object.model[1].xyz), length(object.model[2].xyz));
    return r * thickness * scale;
}

// The split-sum scale and bias (Karis' analytic fit, as env_specular uses it): for the
// transmission's Fresnel terms, which the Sample Viewer takes from its table under punctual
// light too, where seamlit has no environment and so no table.
fn split_sum_fit(roughness: f32, n_dot_v: f32) -> vec2<f32> {
    let c0 = vec4<f32>(-1.0, -0.0275, -0.572, 0.022);
    let c1 = vec4<f32>(1.0, 0.0425, 1.04, -0.04);
    let r = roughness * c0 + c1;
    let a004 = min(r.x * r.x, exp2(-9.28 * n_dot_v)) * r.x + r.y;
    return vec2<f32>(-1.04, 1.04) * a004 + r.zw;
}

// The transmission target where `ray` from `p` leaves the volume, at the mip of the
// roughness widened by the ior.
fn transmission_sample(p: vec3<f32>, ray: vec3<f32>, roughness: f32, ior: f32) -> vec3<f32> {
    let clip = frame.view_proj * vec4<f32>(p + ray, 1.0);
    let ndc = clip.xy / clip.w;
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    let size = f32(textureDimensions(transmission_target).x);
    let lod = log2(size) * roughness * clamp(ior * 2.0 - 2.0, 0.0, 1.0);
    return textureSampleLevel(transmission_target, environment_sampler, uv, lod).rgb;
}

// What transmission shows of the scene behind (the transmission target, rendered without
// the transmissive objects): read where the view leaves the volume, as blurred as the
// roughness (widened by the ior) says, absorbed by the volume, through the surface's
// Fresnel term and the base colour; then, as the diffuse it replaces, under the dielectric's
// environment Fresnel term, by the transmission factor and one less metallic (the Sample
// Viewer's getIBLVolumeRefraction and its composition).
fn transmission_ambient(n: vec3<f32>, v: vec3<f32>, p: vec3<f32>, albedo: vec3<f32>, metallic: f32, roughness: f32, layers: Layers) -> vec3<f32> {
    let n_dot_v = clamp(abs(dot(n, v)), 1e-3, 1.0);
    var behind = transmission_sample(p, layers.volume_ray, roughness, layers.ior);
    var path = length(layers.volume_ray);
    if layers.dispersion > 0.0 && layers.thickness > 0.0 {
        // KHR_materials_dispersion: red, green and blue each refracted by their own ior,
        // spread about the material's by (ior - 1) * 0.025 * dispersion (the Sample Viewer's
        // getIBLVolumeRefraction); the path is blue's.
        let half_spread = (layers.ior - 1.0) * 0.025 * layers.dispersion;
        let iors = vec3<f32>(layers.ior - half_spread, layers.ior, layers.ior + half_spread);
        for (var i = 0; i < 3; i = i + 1) {
            let ray = volume_ray(n, v, layers.thickness, iors[i]);
            behind[i] = transmission_sample(p, ray, roughness, iors[i])[i];
            path = length(ray);
        }
    }
    let ab = split_sum_fit(roughness, n_dot_v);
    let refraction = (1.0 - (layers.f0_dielectric * ab.x + ab.y)) * volume_attenuation(behind, path, layers) * albedo;
    let fresnel = environment_fresnel(layers.f0_dielectric, ab, n_dot_v, roughness, layers.specular_weight);
    var through = (1.0 - fresnel) * refraction * layers.transmission * (1.0 - metallic);
    if (material.flags & MAT_SHEEN) != 0u {
        through = through * (1.0 - max3(layers.sheen_color) * sheen_albedo(n_dot_v, layers.sheen_roughness));
    }
    return through;
}

// A layer over a base by a colour's weights: the layer times them, over the base times one
// less their largest (the Sample Viewer's rgb_mix).
fn rgb_mix(base: vec3<f32>, layer: vec3<f32>, weights: vec3<f32>) -> vec3<f32> {
    return (1.0 - max3(weights)) * base + weights * layer;
}

fn sq3(x: vec3<f32>) -> vec3<f32> {
    return x * x;
}

// The CIE sensitivity of an optical path difference (nm) at a phase shift, as linear Rec. 709
// (L. Belcour and P. Barla, "A Practical Extension to Microfacet Theory for the Modeling of
// Varying Iridescence", 2017: Gaussian fits of the colour matching functions, as the
// KHR_materials_iridescence specification gives them).
fn iridescence_sensitivity(opd: f32, shift: vec3<f32>) -> vec3<f32> {
    let phase = 2.0 * PI * opd * 1.0e-9;
    let val = vec3<f32>(5.4856e-13, 4.4201e-13, 5.2481e-13);
    let pos = vec3<f32>(1.6810e+06, 1.7953e+06, 2.2084e+06);
    let var_ = vec3<f32>(4.3278e+09, 9.3046e+09, 6.6121e+09);
    var xyz = val * sqrt(2.0 * PI * var_) * cos(pos * phase + shift) * exp(-phase * phase * var_);
    xyz.x = xyz.x + 9.7470e-14 * sqrt(2.0 * PI * 4.5282e+09) * cos(2.2399e+06 * phase + shift.x) * exp(-4.5282e+09 * phase * phase);
    xyz = xyz / 1.0685e-7;
    let xyz_to_rec709 = mat3x3<f32>(3.2404542, -0.9692660, 0.0556434, -1.5371385, 1.8760108, -0.2040259, -0.4985314, 0.0415560, 1.0572252);
    return xyz_to_rec709 * xyz;
}

// KHR_materials_iridescence's Fresnel term: air over a film of ior `film_ior` and thickness
// `thickness` (nm) over a base of reflectance `base_f0`, at cos theta = `cos1`: the Airy
// sum of the film's two interfaces to the second order (Belcour and Barla; the
// specification's and the Sample Viewer's evalIridescence, written anew).
fn iridescence_fresnel(film_ior_in: f32, cos1: f32, thickness: f32, base_f0: vec3<f32>) -> vec3<f32> {
    let outside = 1.0;
    // The film fades in over its first 30 nm.
    let film_ior = mix(outside, film_ior_in, smoothstep(0.0, 0.03, thickness));
    let sin2_sq = (outside / film_ior) * (outside / film_ior) * (1.0 - cos1 * cos1);
    let cos2_sq = 1.0 - sin2_sq;
    if cos2_sq < 0.0 {
        return vec3<f32>(1.0);
    }
    let cos2 = sqrt(cos2_sq);
    let r0 = ((film_ior - outside) / (film_ior + outside)) * ((film_ior - outside) / (film_ior + outside));
    let r12 = r0 + (1.0 - r0) * pow(max(1.0 - cos1, 0.0), 5.0);
    let t121 = 1.0 - r12;
    let phi12 = select(0.0, PI, film_ior < outside);
    let phi21 = PI - phi12;
    let sqrt_f0 = sqrt(clamp(base_f0, vec3<f32>(0.0), vec3<f32>(0.9999)));
    let base_ior = (1.0 + sqrt_f0) / (1.0 - sqrt_f0);
    let r1 = sq3((base_ior - film_ior) / (base_ior + film_ior));
    let r23 = r1 + (1.0 - r1) * pow(max(1.0 - cos2, 0.0), 5.0);
    let phi23 = select(vec3<f32>(0.0), vec3<f32>(PI), base_ior < vec3<f32>(film_ior));
    let opd = 2.0 * film_ior * thickness * cos2;
    let phi = vec3<f32>(phi21) + phi23;
    let r123 = clamp(r12 * r23, vec3<f32>(1e-5), vec3<f32>(0.9999));
    let rs = t121 * t121 * r23 / (1.0 - r123);
    var intensity = r12 + rs;
    var cm = rs - t121;
    for (var m = 1; m <= 2; m = m + 1) {
        cm = cm * sqrt(r123);
        intensity = intensity + cm * 2.0 * iridescence_sensitivity(f32(m) * opd, f32(m) * phi);
    }
    return max(intensity, vec3<f32>(0.0));
}

// The extension textures' samples at a pixel (extension_textures.wgsl).
struct ExtensionSamples {
    transmission: f32,
    thickness: f32,
    iridescence: f32,
    iridescence_thickness: f32,
    anisotropy: vec3<f32>,
}

// The texture coordinates and their screen derivatives, for textureSampleGrad.
struct UvGrads {
    uv0: vec2<f32>,
    uv1: vec2<f32>,
    dx0: vec2<f32>,
    dy0: vec2<f32>,
    dx1: vec2<f32>,
    dy1: vec2<f32>,
}

// A texture slot sampled with explicit gradients (so that it may be read where control flow
// is not uniform): its set's derivatives through the slot's transform (its linear part, and
// V flipped as material_uv flips it).
fn sample_slot(t: texture_2d<f32>, rows: array<vec4<f32>, 2>, g: UvGrads) -> vec4<f32> {
    let use1 = rows[0].w > 0.5;
    let dx = select(g.dx0, g.dx1, use1);
    let dy = select(g.dy0, g.dy1, use1);
    var tdx = vec2<f32>(dot(rows[0].xy, dx), dot(rows[1].xy, dx));
    var tdy = vec2<f32>(dot(rows[0].xy, dy), dot(rows[1].xy, dy));
    if object.flip_v != 0u {
        tdx.y = -tdx.y;
        tdy.y = -tdy.y;
    }
    return textureSampleGrad(t, material_sampler, material_uv(rows, g.uv0, g.uv1), tdx, tdy);
}

// The material's layers at this pixel: factors times textures, and the clearcoat's normal
// (the geometry's, or its own normal map's in the same tangent frame).
fn material_layers(g: UvGrads, geometry_n: vec3<f32>, shading_n: vec3<f32>, albedo: vec3<f32>, in: VertexOut) -> Layers {
    var out: Layers;
    let specular = sample_slot(specular_texture, material.specular_uv, g).a;
    let specular_color = sample_slot(specular_color_texture, material.specular_color_uv, g).rgb;
    out.f0_dielectric = min(material.f0_dielectric * specular_color, vec3<f32>(1.0));
    out.specular_weight = material.specular_weight * specular;
    out.sheen_color = material.sheen_color * sample_slot(sheen_color_texture, material.sheen_color_uv, g).rgb;
    out.sheen_roughness = clamp(material.sheen_roughness * sample_slot(sheen_roughness_texture, material.sheen_roughness_uv, g).a, 0.0, 1.0);
    out.clearcoat = clamp(material.clearcoat * sample_slot(clearcoat_texture, material.clearcoat_uv, g).r, 0.0, 1.0);
    out.clearcoat_roughness = clamp(material.clearcoat_roughness * sample_slot(clearcoat_roughness_texture, material.clearcoat_roughness_uv, g).g, 0.0, 1.0);
    out.clearcoat_f0 = material.clearcoat_f0;
    out.clearcoat_n = geometry_n;
    let t_len2 = dot(in.tangent, in.tangent);
    let ext = extension_samples(g);
    out.anisotropy = 0.0;
    out.anisotropy_t = vec3<f32>(1.0, 0.0, 0.0);
    out.anisotropy_b = vec3<f32>(0.0, 1.0, 0.0);
    if (material.flags & MAT_ANISOTROPY) != 0u && object.has_tangents != 0u && t_len2 > 1e-12 {
        // The direction (1, 0) of the tangent plane, or the texture's, turned by the
        // rotation, in the frame of the shading normal; the bitangent across it about the
        // geometry's normal; the strength times the texture's blue.
        var direction = vec2<f32>(1.0, 0.0);
        var strength = 1.0;
        if (material.flags & MAT_ANISOTROPY_TEXTURE) != 0u {
            direction = ext.anisotropy.xy * 2.0 - 1.0;
            strength = ext.anisotropy.z;
        }
        let c = material.anisotropy.x;
        let s = material.anisotropy.y;
        let turned = vec2<f32>(c * direction.x - s * direction.y, s * direction.x + c * direction.y);
        let t = safe_normalize(in.tangent - dot(in.tangent, shading_n) * shading_n, in.tangent);
        let b = safe_normalize(in.bitangent, cross(shading_n, t) * in.handedness);
        out.anisotropy_t = safe_normalize(t * turned.x + b * turned.y, t);
        out.anisotropy_b = safe_normalize(cross(geometry_n, out.anisotropy_t), b);
        out.anisotropy = clamp(material.anisotropy.z * strength, 0.0, 1.0);
    }
    out.transmission = 0.0;
    out.ior = material.ior;
    out.volume_ray = vec3<f32>(0.0);
    out.attenuation_distance = material.attenuation_distance;
    out.attenuation_color = material.attenuation_color;
    out.thickness = material.thickness * ext.thickness;
    out.dispersion = material.dispersion;
    if (material.flags & MAT_TRANSMISSION) != 0u {
        out.transmission = material.transmission * ext.transmission;
        out.volume_ray = volume_ray(shading_n, safe_normalize(frame.eye - in.world, shading_n), out.thickness, material.ior);
    }
    out.iridescence = 0.0;
    out.iridescence_dielectric = vec3<f32>(0.0);
    out.iridescence_metal = vec3<f32>(0.0);
    // The film's thickness: from the minimum to the maximum by the texture's green (the
    // minimum is the maximum without a texture).
    let film = mix(material.iridescence_thickness_minimum, material.iridescence_thickness, ext.iridescence_thickness);
    if (material.flags & MAT_IRIDESCENCE) != 0u && film > 0.0 {
        // The film's Fresnel terms at this view angle, over the dielectric and over the metal.
        let v = safe_normalize(frame.eye - in.world, shading_n);
        let n_dot_v = clamp(dot(shading_n, v), 0.0, 1.0);
        out.iridescence = material.iridescence * ext.iridescence;
        out.iridescence_dielectric = iridescence_fresnel(material.iridescence_ior, n_dot_v, film, out.f0_dielectric);
        out.iridescence_metal = iridescence_fresnel(material.iridescence_ior, n_dot_v, film, albedo);
    }
    if (material.flags & MAT_CLEARCOAT_NORMAL_MAP) != 0u && object.has_tangents != 0u && t_len2 > 1e-12 {
        var tn = sample_slot(clearcoat_normal_texture, material.clearcoat_normal_uv, g).xyz * 2.0 - 1.0;
        tn = vec3<f32>(tn.xy * material.clearcoat_normal_scale, tn.z);
        let n = geometry_n;
        let t = safe_normalize(in.tangent - dot(in.tangent, n) * n, in.tangent);
        let b = safe_normalize(in.bitangent, cross(n, t) * in.handedness);
        out.clearcoat_n = safe_normalize(t * tn.x + b * tn.y + n * tn.z, n);
    }
    return out;
}

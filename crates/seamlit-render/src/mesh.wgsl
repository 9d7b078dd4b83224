// Per-pixel lighting with normal mapping for seamlit.
//
// P. Mileff, "Per-pixel lighting for multi-object models" (2024): the lighting equation of
// section 3 (ambient + sum over lights of diffuse + specular) evaluated in one pass over a
// storage buffer of lights, and the tangent frame of section 5.3 built in the vertex shader
// with Gram-Schmidt, B = cross(N, T) * w. Tangent-space normals decode as rgb * 2 - 1 (the
// paper's encoding line has a sign typo). Lighting is in linear space; the target is sRGB.
//
// The PBR model is glTF 2.0's metallic-roughness, Appendix B of the specification: Lambert
// diffuse, GGX (Trowbridge-Reitz) distribution, height-correlated Smith visibility and
// Schlick Fresnel, c_diff = mix(base, black, metallic), f0 = mix(0.04, base, metallic),
// alpha = roughness^2; the diffuse term is weighted by 1 - F with the dielectric's f0 = 0.04
// (the specification's fresnel_mix, as the Khronos Sample Viewer has it). Lit colours are scaled by the exposure and tone mapped (Khronos PBR
// Neutral) when the frame asks for it.
//
// Image-based light (PBR only) is the split sum (B. Karis, "Real Shading in Unreal Engine 4",
// 2013) over the textures ibl.wgsl prefiltered: the specular cube at the mip of the
// roughness times a Fresnel term from the BRDF table (with multiple scattering), over the
// irradiance cube times the albedo for the dielectric, mixed by metallic with the metal's,
// darkened by occlusion; composed as the Khronos glTF Sample Viewer does.
//
// Entry points: vs_main / fs_main draw the meshes; vs_sky / fs_sky the environment behind
// them; vs_tbn / fs_tbn draw each vertex's tangent, bitangent and normal as lines, reading
// the vertex buffer as storage.

struct Frame {
    view_proj: mat4x4<f32>,
    eye: vec3<f32>,
    light_count: u32,
    ambient: vec3<f32>,
    lighting_model: u32,
    debug_view: u32,
    flags: u32,
    normal_strength: f32,
    tbn_length: f32,
    exposure: f32,
    tone_mapping: u32,
    environment_intensity: f32,
    environment_max_lod: f32,
    inv_view_proj: mat4x4<f32>,
    environment_rotation: vec2<f32>,
    background_lod: f32,
    shadow_normal_offset: f32,
}

struct Light {
    position: vec3<f32>,
    kind: u32,
    direction: vec3<f32>,
    range: f32,
    color: vec3<f32>,
    cos_inner: f32,
    cos_outer: f32,
    shadow: f32,
    pad1: f32,
    pad2: f32,
}

struct Material {
    base_color: vec4<f32>,
    specular: vec3<f32>,
    shininess: f32,
    base_uv: array<vec4<f32>, 2>,
    normal_uv: array<vec4<f32>, 2>,
    metallic_roughness_uv: array<vec4<f32>, 2>,
    occlusion_uv: array<vec4<f32>, 2>,
    emissive_uv: array<vec4<f32>, 2>,
    emissive: vec3<f32>,
    normal_scale: f32,
    metallic: f32,
    roughness: f32,
    occlusion_strength: f32,
    alpha_cutoff: f32,
    flags: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
    specular_uv: array<vec4<f32>, 2>,
    specular_color_uv: array<vec4<f32>, 2>,
    clearcoat_uv: array<vec4<f32>, 2>,
    clearcoat_roughness_uv: array<vec4<f32>, 2>,
    clearcoat_normal_uv: array<vec4<f32>, 2>,
    sheen_color_uv: array<vec4<f32>, 2>,
    sheen_roughness_uv: array<vec4<f32>, 2>,
    f0_dielectric: vec3<f32>,
    specular_weight: f32,
    sheen_color: vec3<f32>,
    sheen_roughness: f32,
    clearcoat: f32,
    clearcoat_roughness: f32,
    clearcoat_normal_scale: f32,
    clearcoat_f0: f32,
    anisotropy: vec3<f32>,
    pad3: f32,
    transmission: f32,
    thickness: f32,
    attenuation_distance: f32,
    ior: f32,
    attenuation_color: vec3<f32>,
    pad4: f32,
    iridescence: f32,
    iridescence_ior: f32,
    iridescence_thickness: f32,
    dispersion: f32,
    transmission_uv: array<vec4<f32>, 2>,
    thickness_uv: array<vec4<f32>, 2>,
    iridescence_uv: array<vec4<f32>, 2>,
    iridescence_thickness_uv: array<vec4<f32>, 2>,
    anisotropy_uv: array<vec4<f32>, 2>,
    iridescence_thickness_minimum: f32,
    pad5: f32,
    pad6: f32,
    pad7: f32,
}

// `Object` (group 2, the per-object uniforms) is in object.wgsl, put in front of this file.

// Light kinds (LightRaw::DIRECTIONAL, POINT, SPOT).
const LIGHT_DIRECTIONAL: u32 = 0u;
const LIGHT_SPOT: u32 = 2u;

// Lighting models (LightingModel::to_raw).
const MODEL_BLINN_PHONG: u32 = 0u;
const MODEL_PHONG: u32 = 1u;
const MODEL_LAMBERT: u32 = 2u;
const MODEL_GOURAUD: u32 = 3u;
const MODEL_PBR: u32 = 4u;

// Debug views (DebugView::to_raw).
const VIEW_NORMALS: u32 = 1u;
const VIEW_TANGENTS: u32 = 2u;
const VIEW_BITANGENT_SIGN: u32 = 3u;
const VIEW_UVS: u32 = 4u;
const VIEW_OBJECT_IDS: u32 = 5u;
const VIEW_LIGHTING_ONLY: u32 = 6u;
const VIEW_METALLIC: u32 = 7u;
const VIEW_ROUGHNESS: u32 = 8u;
const VIEW_OCCLUSION: u32 = 9u;

// Tone mapping (ToneMapping::to_raw).
const TONE_PBR_NEUTRAL: u32 = 1u;
const TONE_ACES: u32 = 2u;

// Frame flags (settings.rs).
const FLAG_NORMAL_MAPPING: u32 = 1u;
const FLAG_FLIP_GREEN: u32 = 2u;
const FLAG_ENCODE_SRGB: u32 = 4u;
const FLAG_ENVIRONMENT: u32 = 8u;
const FLAG_SHADOWS: u32 = 16u;

// Material flags (scene.rs).
const MAT_NORMAL_MAP: u32 = 1u;
const MAT_GREEN_DOWN: u32 = 2u;
const MAT_DOUBLE_SIDED: u32 = 4u;
const MAT_ALPHA_MASK: u32 = 8u;
const MAT_ALPHA_BLEND: u32 = 16u;
const MAT_UNLIT: u32 = 32u;
const MAT_CLEARCOAT: u32 = 64u;
const MAT_CLEARCOAT_NORMAL_MAP: u32 = 128u;
const MAT_SHEEN: u32 = 256u;
const MAT_SPECULAR: u32 = 512u;
const MAT_ANISOTROPY: u32 = 1024u;
const MAT_TRANSMISSION: u32 = 2048u;
const MAT_IRIDESCENCE: u32 = 4096u;
const MAT_ANISOTROPY_TEXTURE: u32 = 8192u;
// Any of the PBR extensions that add to the BRDF: drawn by shade_layers.
const MAT_LAYERS: u32 = 8000u;

// The PBR extensions' layers compiled in (pipeline.rs): false for the pipelines that draw
// materials without them, so that those cost what they did.
override LAYERS: bool = true;

const PI: f32 = 3.141592653589793;

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> lights: array<Light>;
@group(0) @binding(2) var shadow_maps: texture_depth_2d_array;
@group(0) @binding(3) var shadow_sampler: sampler_comparison;
@group(0) @binding(4) var<uniform> shadow_matrices: array<mat4x4<f32>, 4>;
// What KHR_materials_transmission sees through: the scene without transmissive objects,
// linear, with mips (renderer.rs, transmission.rs); a black texel in frames without one.
@group(0) @binding(5) var transmission_target: texture_2d<f32>;
@group(1) @binding(0) var<uniform> material: Material;
@group(1) @binding(1) var base_texture: texture_2d<f32>;
@group(1) @binding(2) var normal_texture: texture_2d<f32>;
@group(1) @binding(3) var material_sampler: sampler;
@group(1) @binding(4) var metallic_roughness_texture: texture_2d<f32>;
@group(1) @binding(5) var occlusion_texture: texture_2d<f32>;
@group(1) @binding(6) var emissive_texture: texture_2d<f32>;
@group(1) @binding(7) var specular_texture: texture_2d<f32>;
@group(1) @binding(8) var specular_color_texture: texture_2d<f32>;
@group(1) @binding(9) var clearcoat_texture: texture_2d<f32>;
@group(1) @binding(10) var clearcoat_roughness_texture: texture_2d<f32>;
@group(1) @binding(11) var clearcoat_normal_texture: texture_2d<f32>;
@group(1) @binding(12) var sheen_color_texture: texture_2d<f32>;
@group(1) @binding(13) var sheen_roughness_texture: texture_2d<f32>;
// The sheen's tables (sheen.rs): its albedo E, then its environment scale (layers.wgsl).
@group(1) @binding(14) var<storage, read> sheen_albedo_table: array<f32>;
@group(2) @binding(0) var<uniform> object: Object;
@group(2) @binding(1) var<storage, read> vertex_data: array<f32>;
@group(2) @binding(2) var<storage, read> skin: array<SkinVertex>;
@group(2) @binding(3) var<storage, read> morph_deltas: array<vec4<f32>>;
@group(2) @binding(4) var<storage, read> joint_palette: array<mat4x4<f32>>;
@group(2) @binding(5) var<storage, read> morph_weights: array<f32>;
@group(3) @binding(0) var environment_specular: texture_cube<f32>;
@group(3) @binding(1) var environment_irradiance: texture_cube<f32>;
// The split-sum BRDF table (64 x 64 texels of two halves packed in a u32, then two unused
// halves), a storage buffer so that the 16 sampled textures a stage WebGPU guarantees leave
// room for the transmission target.
@group(3) @binding(2) var<storage, read> brdf_lut: array<u32>;
@group(3) @binding(3) var environment_sampler: sampler;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) tangent: vec4<f32>,
    @location(3) uv: vec2<f32>,
    @location(4) color: vec4<f32>,
    @location(5) uv1: vec2<f32>,
    @builtin(vertex_index) index: u32,
}

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) tangent: vec3<f32>,
    @location(3) bitangent: vec3<f32>,
    @location(4) uv: vec2<f32>,
    @location(5) @interpolate(flat) handedness: f32,
    @location(6) gouraud_diffuse: vec3<f32>,
    @location(7) gouraud_specular: vec3<f32>,
    @location(8) color: vec4<f32>,
    @location(9) uv1: vec2<f32>,
}

// The world-space frame of a vertex: normal, Gram-Schmidt tangent (zero when the vertex has
// none) and bitangent B = cross(N, T) * w * sign(det(model)) * skin_sign (the sign of the
// skinning matrix's determinant, deform.wgsl).
struct Tbn {
    t: vec3<f32>,
    b: vec3<f32>,
    n: vec3<f32>,
}

fn world_tbn(normal: vec3<f32>, tangent: vec4<f32>, skin_sign: f32) -> Tbn {
    var out: Tbn;
    out.n = safe_normalize((object.normal * vec4<f32>(normal, 0.0)).xyz, vec3<f32>(0.0, 0.0, 1.0));
    let t = (object.model * vec4<f32>(tangent.xyz, 0.0)).xyz;
    let t_ortho = t - dot(t, out.n) * out.n;
    out.t = safe_normalize(t_ortho, vec3<f32>(0.0));
    let w = select(1.0, -1.0, tangent.w < 0.0) * object.det_sign * skin_sign;
    out.b = cross(out.n, out.t) * w;
    return out;
}

struct Shade {
    diffuse: vec3<f32>,
    specular: vec3<f32>,
}

// Where light i comes from at point p: the unit vector toward it (xyz) and its attenuation
// (w), KHR_lights_punctual's range fade and spot cone.
fn incidence(light: Light, p: vec3<f32>) -> vec4<f32> {
    var l = -light.direction;
    var attenuation = 1.0;
    if light.kind != LIGHT_DIRECTIONAL {
        let to_light = light.position - p;
        let d2 = max(dot(to_light, to_light), 1e-12);
        let d = sqrt(d2);
        l = to_light / d;
        attenuation = 1.0 / d2;
        if light.range > 0.0 {
            let r = d / light.range;
            let fade = clamp(1.0 - r * r * r * r, 0.0, 1.0);
            attenuation = attenuation * fade * fade;
        }
        if light.kind == LIGHT_SPOT {
            let cos_angle = dot(-l, light.direction);
            let cone = clamp((cos_angle - light.cos_outer) / max(light.cos_inner - light.cos_outer, 1e-4), 0.0, 1.0);
            attenuation = attenuation * cone * cone;
        }
    }
    return vec4<f32>(l, attenuation);
}

// How much of a light reaches point p with unit normal n past its shadow map: 3 x 3
// comparisons, each filtered bilinearly (percentage-closer filtering), from a point moved
// a little along the normal against self-shadowing. 1 outside the map or without one.
fn shadow_factor(light: Light, p: vec3<f32>, n: vec3<f32>) -> f32 {
    if (frame.flags & FLAG_SHADOWS) == 0u || light.shadow < 0.0 {
        return 1.0;
    }
    let layer = i32(light.shadow);
    let clip = shadow_matrices[layer] * vec4<f32>(p + n * frame.shadow_normal_offset, 1.0);
    let ndc = clip.xyz / clip.w;
    let uv = ndc.xy * vec2<f32>(0.5, -0.5) + 0.5;
    if any(uv < vec2<f32>(0.0)) || any(uv > vec2<f32>(1.0)) || ndc.z > 1.0 || clip.w <= 0.0 {
        return 1.0;
    }
    let texel = 1.0 / vec2<f32>(textureDimensions(shadow_maps));
    var lit = 0.0;
    for (var y = -1; y <= 1; y = y + 1) {
        for (var x = -1; x <= 1; x = x + 1) {
            let at = uv + vec2<f32>(f32(x), f32(y)) * texel;
            lit = lit + textureSampleCompareLevel(shadow_maps, shadow_sampler, at, layer, ndc.z);
        }
    }
    return lit / 9.0;
}

// One light's diffuse and specular terms (without the material's colours) at point p with
// unit normal n and unit view vector v, before shadowing.
fn light_terms(light: Light, n: vec3<f32>, v: vec3<f32>, p: vec3<f32>, shininess: f32, model: u32) -> Shade {
    var out: Shade;
    out.diffuse = vec3<f32>(0.0);
    out.specular = vec3<f32>(0.0);
    let inc = incidence(light, p);
    let l = inc.xyz;
    let n_dot_l = dot(n, l);
    if n_dot_l <= 0.0 || inc.w <= 0.0 {
        return out;
    }
    let radiance = light.color * inc.w;
    out.diffuse = radiance * n_dot_l;
    if model == MODEL_LAMBERT {
        return out;
    }
    var s: f32;
    if model == MODEL_PHONG {
        s = pow(max(dot(reflect(-l, n), v), 0.0), shininess);
    } else {
        s = pow(max(dot(n, safe_normalize(l + v, n)), 0.0), shininess);
    }
    out.specular = radiance * s;
    return out;
}

// Sum over all lights of the diffuse and specular terms, unshadowed (Gouraud, per vertex:
// the shadow maps are read in the fragment shader only).
fn shade(n: vec3<f32>, v: vec3<f32>, p: vec3<f32>, shininess: f32, model: u32) -> Shade {
    var out: Shade;
    out.diffuse = vec3<f32>(0.0);
    out.specular = vec3<f32>(0.0);
    for (var i = 0u; i < frame.light_count; i = i + 1u) {
        let t = light_terms(lights[i], n, v, p, shininess, model);
        out.diffuse = out.diffuse + t.diffuse;
        out.specular = out.specular + t.specular;
    }
    return out;
}

// As shade, each light darkened by its shadow map.
fn shade_shadowed(n: vec3<f32>, v: vec3<f32>, p: vec3<f32>, shininess: f32, model: u32) -> Shade {
    var out: Shade;
    out.diffuse = vec3<f32>(0.0);
    out.specular = vec3<f32>(0.0);
    for (var i = 0u; i < frame.light_count; i = i + 1u) {
        let t = light_terms(lights[i], n, v, p, shininess, model);
        let visible = shadow_factor(lights[i], p, n);
        out.diffuse = out.diffuse + t.diffuse * visible;
        out.specular = out.specular + t.specular * visible;
    }
    return out;
}

// The glTF metallic-roughness BRDF (specification, Appendix B) times n.l, summed over all
// lights, at point p with unit normal n and unit view vector v. alpha = roughness^2, kept
// above 1e-3 so that a mirror-smooth surface does not divide zero by zero.
fn shade_pbr(n: vec3<f32>, v: vec3<f32>, p: vec3<f32>, c_diff: vec3<f32>, f0: vec3<f32>, alpha: f32) -> vec3<f32> {
    var sum = vec3<f32>(0.0);
    let a2 = max(alpha, 1e-3) * max(alpha, 1e-3);
    let n_dot_v = abs(dot(n, v));
    for (var i = 0u; i < frame.light_count; i = i + 1u) {
        let light = lights[i];
        let inc = incidence(light, p);
        let l = inc.xyz;
        let n_dot_l = dot(n, l);
        if n_dot_l <= 0.0 || inc.w <= 0.0 {
            continue;
        }
        let h = safe_normalize(l + v, n);
        let n_dot_h = max(dot(n, h), 0.0);
        let v_dot_h = max(dot(v, h), 0.0);
        // pow of a negative base is undefined in WGSL: v.h can round above 1.
        let schlick = pow(max(1.0 - v_dot_h, 0.0), 5.0);
        let fresnel = f0 + (1.0 - f0) * schlick;
        // Appendix B: the diffuse layer sits under the dielectric's Fresnel (f0 = 0.04), not
        // under the metallic-mixed f0 (which would tint it with the base colour's complement).
        let fresnel_dielectric = 0.04 + 0.96 * schlick;
        let dd = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0;
        let distribution = a2 / (PI * dd * dd);
        let vis_denom = n_dot_l * sqrt(n_dot_v * n_dot_v * (1.0 - a2) + a2)
            + n_dot_v * sqrt(n_dot_l * n_dot_l * (1.0 - a2) + a2);
        let visibility = select(0.0, 0.5 / vis_denom, vis_denom > 0.0);
        let diffuse = (1.0 - fresnel_dielectric) * c_diff / PI;
        let specular = fresnel * distribution * visibility;
        sum = sum + light.color * inc.w * shadow_factor(light, p, n) * n_dot_l * (diffuse + specular);
    }
    return sum;
}

// The specular reflectance of a surface under a uniform environment: Karis' analytic fit of
// the split-sum lookup table ("Physically based shading on mobile", 2014).
fn env_specular(f0: vec3<f32>, roughness: f32, n_dot_v: f32) -> vec3<f32> {
    let c0 = vec4<f32>(-1.0, -0.0275, -0.572, 0.022);
    let c1 = vec4<f32>(1.0, 0.0425, 1.04, -0.04);
    let r = roughness * c0 + c1;
    let a004 = min(r.x * r.x, exp2(-9.28 * n_dot_v)) * r.x + r.y;
    let ab = vec2<f32>(-1.04, 1.04) * a004 + r.zw;
    return f0 * ab.x + ab.y;
}

// A world direction in the environment's own frame: turned back by its rotation about +Y.
fn environment_direction(d: vec3<f32>) -> vec3<f32> {
    let c = frame.environment_rotation.x;
    let s = frame.environment_rotation.y;
    return vec3<f32>(c * d.x - s * d.z, d.y, s * d.x + c * d.z);
}

// Texels a side of the BRDF table (environment.rs LUT_SIZE).
const BRDF_LUT_SIZE: u32 = 64u;

// An IEEE half (the low 16 bits of h) as f32, by its bits: unpack2x16float needs a
// capability (f16 in f32) not every adapter has. The table holds no infinities or NaNs.
fn half_to_f32(h: u32) -> f32 {
    let e = (h >> 10u) & 0x1fu;
    let m = h & 0x3ffu;
    if e == 0u {
        return f32(m) * 5.9604645e-8;
    }
    return bitcast<f32>(((h & 0x8000u) << 16u) | ((e + 112u) << 23u) | (m << 13u));
}

fn brdf_lut_texel(x: u32, y: u32) -> vec2<f32> {
    let word = brdf_lut[(y * BRDF_LUT_SIZE + x) * 2u];
    return vec2<f32>(half_to_f32(word & 0xffffu), half_to_f32(word >> 16u));
}

// The BRDF table's scale and bias at (n.v, roughness), filtered bilinearly between texel
// centres as a texture's linear filter reads it (texel coordinates (n.v, roughness) times
// the size less one).
fn brdf_lut_ab(n_dot_v: f32, roughness: f32) -> vec2<f32> {
    let last = f32(BRDF_LUT_SIZE - 1u);
    let p = clamp(vec2<f32>(n_dot_v, roughness), vec2<f32>(0.0), vec2<f32>(1.0)) * last;
    let i0 = vec2<u32>(floor(p));
    let i1 = min(i0 + 1u, vec2<u32>(BRDF_LUT_SIZE - 1u));
    let f = p - floor(p);
    let row0 = mix(brdf_lut_texel(i0.x, i0.y), brdf_lut_texel(i1.x, i0.y), f.x);
    let row1 = mix(brdf_lut_texel(i0.x, i1.y), brdf_lut_texel(i1.x, i1.y), f.x);
    return mix(row0, row1, f.y);
}

// The split-sum reflectance for f0, with the BRDF table's scale and bias `ab`: single
// scattering with a roughness-dependent Fresnel term, plus the energy multiple scattering
// adds back (C. Fdez-Aguera, "A Multiple-Scattering Microfacet Model for Real-Time
// Image-based Lighting", JCGT 2019), as the Khronos glTF Sample Viewer computes it.
fn environment_fresnel(f0: vec3<f32>, ab: vec2<f32>, n_dot_v: f32, roughness: f32, weight: f32) -> vec3<f32> {
    let fr = max(vec3<f32>(1.0 - roughness), f0) - f0;
    let k_s = f0 + fr * pow(max(1.0 - n_dot_v, 0.0), 5.0);
    let single = weight * (k_s * ab.x + ab.y);
    let e_ms = 1.0 - (ab.x + ab.y);
    let f_avg = weight * (f0 + (1.0 - f0) / 21.0);
    return single + e_ms * single * f_avg / (1.0 - f_avg * e_ms);
}

// The environment's light reflected at a point with unit normal n and unit view vector v,
// composed as glTF's metallic-roughness BRDF is: a dielectric (irradiance times the albedo,
// under the split-sum specular by its Fresnel term, so a white dielectric in a uniform
// environment of radiance L returns L) mixed by metallic with a metal (the specular times
// its Fresnel term with f0 = albedo).
fn shade_environment(n: vec3<f32>, v: vec3<f32>, albedo: vec3<f32>, metallic: f32, roughness: f32) -> vec3<f32> {
    let n_dot_v = clamp(abs(dot(n, v)), 1e-3, 1.0);
    let ab = brdf_lut_ab(n_dot_v, roughness);
    let r = environment_direction(reflect(-v, n));
    let specular = textureSampleLevel(environment_specular, environment_sampler, r, roughness * frame.environment_max_lod).rgb;
    let irradiance = textureSampleLevel(environment_irradiance, environment_sampler, environment_direction(n), 0.0).rgb;
    let dielectric = mix(irradiance * albedo, specular, environment_fresnel(vec3<f32>(0.04), ab, n_dot_v, roughness, 1.0));
    let metal = specular * environment_fresnel(albedo, ab, n_dot_v, roughness, 1.0);
    return mix(dielectric, metal, metallic) * frame.environment_intensity;
}

// ACES filmic tone mapping, S. Hill's fit (the Khronos glTF Sample Viewer's "ACES Hill"):
// sRGB to the ACES working space, the RRT and ODT fit, and back.
fn aces_hill(color_in: vec3<f32>) -> vec3<f32> {
    let to_aces = mat3x3<f32>(0.59719, 0.07600, 0.02840, 0.35458, 0.90834, 0.13383, 0.04823, 0.01566, 0.83777);
    let from_aces = mat3x3<f32>(1.60475, -0.10208, -0.00327, -0.53108, 1.10813, -0.07276, -0.07367, -0.00605, 1.07602);
    let c = to_aces * color_in;
    let a = c * (c + 0.0245786) - 0.000090537;
    let b = c * (0.983729 * c + 0.4329510) + 0.238081;
    return clamp(from_aces * (a / b), vec3<f32>(0.0), vec3<f32>(1.0));
}

// Khronos PBR Neutral tone mapping (github.com/KhronosGroup/ToneMapping, PBR_Neutral).
fn pbr_neutral(color_in: vec3<f32>) -> vec3<f32> {
    let start_compression = 0.8 - 0.04;
    let desaturation = 0.15;
    var color = color_in;
    let x = min(color.r, min(color.g, color.b));
    let offset = select(0.04, x - 6.25 * x * x, x < 0.08);
    color = color - offset;
    let peak = max(color.r, max(color.g, color.b));
    if peak < start_compression {
        return color;
    }
    let d = 1.0 - start_compression;
    let new_peak = 1.0 - d * d / (peak + d - start_compression);
    color = color * (new_peak / peak);
    let g = 1.0 - 1.0 / (desaturation * (peak - new_peak) + 1.0);
    return mix(color, vec3<f32>(new_peak), g);
}

// A lit colour (linear, unbounded) with its alpha, exposed and tone mapped as the frame says,
// as the target wants it.
fn out_lit(c: vec3<f32>, alpha: f32) -> vec4<f32> {
    var mapped = c * frame.exposure;
    if frame.tone_mapping == TONE_PBR_NEUTRAL {
        mapped = pbr_neutral(mapped);
    } else if frame.tone_mapping == TONE_ACES {
        mapped = aces_hill(mapped);
    }
    return vec4<f32>(out_linear(mapped).rgb, alpha);
}

@vertex
fn vs_main(in: VertexIn) -> VertexOut {
    var out: VertexOut;
    let posed = deform(in.index, in.position, in.normal, in.tangent);
    let world = object.model * vec4<f32>(posed.position, 1.0);
    let tbn = world_tbn(posed.normal, posed.tangent, posed.det_sign);
    out.clip = frame.view_proj * world;
    out.world = world.xyz;
    out.normal = tbn.n;
    out.tangent = tbn.t;
    out.bitangent = tbn.b;
    out.uv = in.uv;
    out.uv1 = in.uv1;
    out.color = in.color;
    out.handedness = select(1.0, -1.0, in.tangent.w < 0.0);
    out.gouraud_diffuse = vec3<f32>(0.0);
    out.gouraud_specular = vec3<f32>(0.0);
    if frame.lighting_model == MODEL_GOURAUD {
        // Per-vertex Blinn-Phong with the vertex normal (the paper's Figure 3).
        let v = safe_normalize(frame.eye - world.xyz, tbn.n);
        let s = shade(tbn.n, v, world.xyz, material.shininess, MODEL_BLINN_PHONG);
        out.gouraud_diffuse = s.diffuse;
        out.gouraud_specular = s.specular;
    }
    return out;
}

// The texture coordinate set a slot reads (rows[0].w: 1 = TEXCOORD_1, 0 = TEXCOORD_0)
// through its 2x3 texture transform, then V flipped for V-up texcoords (the texture's first
// row is the top of the image).
fn material_uv(rows: array<vec4<f32>, 2>, uv0: vec2<f32>, uv1: vec2<f32>) -> vec2<f32> {
    let uv = select(uv0, uv1, rows[0].w > 0.5);
    let t = vec2<f32>(dot(rows[0].xyz, vec3<f32>(uv, 1.0)), dot(rows[1].xyz, vec3<f32>(uv, 1.0)));
    if object.flip_v != 0u {
        return vec2<f32>(t.x, 1.0 - t.y);
    }
    return t;
}

fn srgb_to_linear(c: vec3<f32>) -> vec3<f32> {
    return select(pow((c + 0.055) / 1.055, vec3<f32>(2.4)), c / 12.92, c <= vec3<f32>(0.04045));
}

fn linear_to_srgb(c: vec3<f32>) -> vec3<f32> {
    let l = clamp(c, vec3<f32>(0.0), vec3<f32>(1.0));
    return select(1.055 * pow(l, vec3<f32>(1.0 / 2.4)) - 0.055, l * 12.92, l <= vec3<f32>(0.0031308));
}

// A lit colour (linear) as the target wants it.
fn out_linear(c: vec3<f32>) -> vec4<f32> {
    if (frame.flags & FLAG_ENCODE_SRGB) != 0u {
        return vec4<f32>(linear_to_srgb(c), 1.0);
    }
    return vec4<f32>(c, 1.0);
}

// A debug colour, meant to land in the image as these very values.
fn out_display(c: vec3<f32>) -> vec4<f32> {
    let d = clamp(c, vec3<f32>(0.0), vec3<f32>(1.0));
    if (frame.flags & FLAG_ENCODE_SRGB) != 0u {
        return vec4<f32>(d, 1.0);
    }
    return vec4<f32>(srgb_to_linear(d), 1.0);
}

// A distinct colour per object id.
fn id_color(id: u32) -> vec3<f32> {
    let h = (id + 1u) * 2654435761u;
    let c = vec3<f32>(f32(h & 255u), f32((h >> 8u) & 255u), f32((h >> 16u) & 255u)) / 255.0;
    return 0.2 + 0.8 * c;
}

@fragment
fn fs_main(in: VertexOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    // Sample first: texture sampling must stay in uniform control flow.
    let base_sample = textureSample(base_texture, material_sampler, material_uv(material.base_uv, in.uv, in.uv1));
    var tn = textureSample(normal_texture, material_sampler, material_uv(material.normal_uv, in.uv, in.uv1)).xyz * 2.0 - 1.0;
    let mr_sample = textureSample(metallic_roughness_texture, material_sampler, material_uv(material.metallic_roughness_uv, in.uv, in.uv1));
    let occlusion_sample = textureSample(occlusion_texture, material_sampler, material_uv(material.occlusion_uv, in.uv, in.uv1)).r;
    let emissive_sample = textureSample(emissive_texture, material_sampler, material_uv(material.emissive_uv, in.uv, in.uv1)).rgb;
    // The texture coordinates' derivatives, for the PBR extensions' textures, which are read
    // (with these gradients) only by materials that have them.
    let grads = UvGrads(in.uv, in.uv1, dpdx(in.uv), dpdy(in.uv), dpdx(in.uv1), dpdy(in.uv1));

    // Base colour: factor x texture x COLOR_0; its alpha cuts (MASK) or blends (BLEND).
    let base = material.base_color * base_sample * in.color;
    if (material.flags & MAT_ALPHA_MASK) != 0u && base.a < material.alpha_cutoff {
        discard;
    }
    let alpha = select(1.0, base.a, (material.flags & MAT_ALPHA_BLEND) != 0u);
    let metallic = clamp(material.metallic * mr_sample.b, 0.0, 1.0);
    let roughness = clamp(material.roughness * mr_sample.g, 0.0, 1.0);
    let occlusion = 1.0 + material.occlusion_strength * (occlusion_sample - 1.0);

    var n = safe_normalize(in.normal, vec3<f32>(0.0, 0.0, 1.0));
    if !front && (material.flags & MAT_DOUBLE_SIDED) != 0u {
        n = -n;
    }
    // The geometry's normal, before the normal map: the clearcoat's.
    let geometry_n = n;
    let t_len2 = dot(in.tangent, in.tangent);
    let mapping = (frame.flags & FLAG_NORMAL_MAPPING) != 0u && (material.flags & MAT_NORMAL_MAP) != 0u;
    if mapping && object.has_tangents != 0u && t_len2 > 1e-12 {
        let flip = ((frame.flags & FLAG_FLIP_GREEN) != 0u) != ((material.flags & MAT_GREEN_DOWN) != 0u);
        if flip {
            tn.y = -tn.y;
        }
        let strength = material.normal_scale * frame.normal_strength;
        tn = vec3<f32>(tn.xy * strength, tn.z);
        // Re-orthonormalise the interpolated frame (Gram-Schmidt again, paper 5.3).
        let t = safe_normalize(in.tangent - dot(in.tangent, n) * n, in.tangent);
        let b = safe_normalize(in.bitangent, cross(n, t) * in.handedness);
        n = safe_normalize(t * tn.x + b * tn.y + n * tn.z, n);
    }

    switch frame.debug_view {
        case VIEW_NORMALS: {
            return out_display(n * 0.5 + 0.5);
        }
        case VIEW_TANGENTS: {
            return out_display(safe_normalize(in.tangent, vec3<f32>(0.0)) * 0.5 + 0.5);
        }
        case VIEW_BITANGENT_SIGN: {
            return out_display(select(vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(1.0, 0.0, 0.0), in.handedness < 0.0));
        }
        case VIEW_UVS: {
            return out_display(vec3<f32>(fract(in.uv), 0.0));
        }
        case VIEW_OBJECT_IDS: {
            return out_display(id_color(object.object_id));
        }
        case VIEW_METALLIC: {
            return out_display(vec3<f32>(metallic));
        }
        case VIEW_ROUGHNESS: {
            return out_display(vec3<f32>(roughness));
        }
        case VIEW_OCCLUSION: {
            return out_display(vec3<f32>(occlusion));
        }
        default: {}
    }

    var albedo = base.rgb;
    if frame.debug_view == VIEW_LIGHTING_ONLY {
        albedo = vec3<f32>(1.0);
    }
    if (material.flags & MAT_UNLIT) != 0u {
        // KHR_materials_unlit: the base colour as it is.
        return vec4<f32>(out_linear(albedo).rgb, alpha);
    }
    let emissive = material.emissive * emissive_sample;
    if frame.lighting_model == MODEL_GOURAUD {
        return out_lit(albedo * (frame.ambient + in.gouraud_diffuse) + material.specular * in.gouraud_specular + emissive, alpha);
    }
    let v = safe_normalize(frame.eye - in.world, n);
    if LAYERS && frame.lighting_model == MODEL_PBR && (material.flags & MAT_LAYERS) != 0u {
        let layers = material_layers(grads, geometry_n, n, albedo, in);
        let lit = shade_layers(n, v, in.world, albedo, metallic, roughness * roughness, layers);
        let c_diff = mix(albedo, vec3<f32>(0.0), metallic);
        let f0 = mix(layers.f0_dielectric * layers.specular_weight, albedo, metallic);
        var ambient = frame.ambient * (c_diff + env_specular(f0, roughness, abs(dot(n, v))));
        var coat_ambient = vec3<f32>(0.0);
        if (frame.flags & FLAG_ENVIRONMENT) != 0u {
            let env = shade_environment_layers(n, v, albedo, metallic, roughness, layers);
            ambient = ambient + env.base;
            coat_ambient = env.coat;
        }
        if layers.transmission > 0.0 {
            ambient = ambient + transmission_ambient(n, v, in.world, albedo, metallic, roughness, layers);
        }
        // Over everything, the clearcoat by its factor times its Fresnel term at n_c.v.
        let coat = layers.clearcoat * (layers.clearcoat_f0 + (1.0 - layers.clearcoat_f0) * pow(1.0 - max(dot(layers.clearcoat_n, v), 0.0), 5.0));
        let direct = mix(lit.base, lit.coat, coat);
        return out_lit(direct + mix(ambient, coat_ambient, coat) * occlusion + emissive * (1.0 - coat), alpha);
    }
    if frame.lighting_model == MODEL_PBR {
        let c_diff = mix(albedo, vec3<f32>(0.0), metallic);
        let f0 = mix(vec3<f32>(0.04), albedo, metallic);
        let direct = shade_pbr(n, v, in.world, c_diff, f0, roughness * roughness);
        var ambient = frame.ambient * (c_diff + env_specular(f0, roughness, abs(dot(n, v))));
        if (frame.flags & FLAG_ENVIRONMENT) != 0u {
            ambient = ambient + shade_environment(n, v, albedo, metallic, roughness);
        }
        return out_lit(direct + ambient * occlusion + emissive, alpha);
    }
    let s = shade_shadowed(n, v, in.world, material.shininess, frame.lighting_model);
    return out_lit(albedo * (frame.ambient + s.diffuse) + material.specular * s.specular + emissive, alpha);
}

struct SkyOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) ndc: vec2<f32>,
}

// One triangle that covers the screen, at the far plane.
@vertex
fn vs_sky(@builtin(vertex_index) index: u32) -> SkyOut {
    let p = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u)) * 2.0 - 1.0;
    var out: SkyOut;
    out.clip = vec4<f32>(p, 1.0, 1.0);
    out.ndc = p;
    return out;
}

// The environment behind the scene, blurred (a rough mip of the specular cube), exposed and
// tone mapped as the lit colours are.
@fragment
fn fs_sky(in: SkyOut) -> @location(0) vec4<f32> {
    let far = frame.inv_view_proj * vec4<f32>(in.ndc, 1.0, 1.0);
    let near = frame.inv_view_proj * vec4<f32>(in.ndc, 0.0, 1.0);
    let d = safe_normalize(far.xyz / far.w - near.xyz / near.w, vec3<f32>(0.0, 0.0, -1.0));
    let c = textureSampleLevel(environment_specular, environment_sampler, environment_direction(d), frame.background_lod).rgb;
    return out_lit(c * frame.environment_intensity, 1.0);
}

struct LineOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) color: vec3<f32>,
}

// Six vertices per mesh vertex: tangent (red), bitangent (green), normal (blue), each a line
// from the vertex outward by frame.tbn_length. Reads the interleaved vertex buffer
// (18 floats: position, normal, tangent, uv, colour, uv1).
@vertex
fn vs_tbn(@builtin(vertex_index) index: u32) -> LineOut {
    let vertex = index / 6u;
    let axis = (index / 2u) % 3u;
    let tip = f32(index % 2u);
    let o = vertex * 18u;
    let position = vec3<f32>(vertex_data[o], vertex_data[o + 1u], vertex_data[o + 2u]);
    let normal = vec3<f32>(vertex_data[o + 3u], vertex_data[o + 4u], vertex_data[o + 5u]);
    let tangent = vec4<f32>(vertex_data[o + 6u], vertex_data[o + 7u], vertex_data[o + 8u], vertex_data[o + 9u]);
    let posed = deform(vertex, position, normal, tangent);
    let tbn = world_tbn(posed.normal, posed.tangent, posed.det_sign);
    var dir = tbn.n;
    var color = vec3<f32>(0.1, 0.3, 1.0);
    if axis == 0u {
        dir = tbn.t;
        color = vec3<f32>(1.0, 0.1, 0.1);
    } else if axis == 1u {
        dir = tbn.b;
        color = vec3<f32>(0.1, 1.0, 0.1);
    }
    let world = (object.model * vec4<f32>(posed.position, 1.0)).xyz + dir * frame.tbn_length * tip;
    var out: LineOut;
    out.clip = frame.view_proj * vec4<f32>(world, 1.0);
    out.color = color;
    return out;
}

@fragment
fn fs_tbn(in: LineOut) -> @location(0) vec4<f32> {
    return out_display(in.color);
}

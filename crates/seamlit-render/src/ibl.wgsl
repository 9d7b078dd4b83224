// Image-based lighting, prefiltered on the GPU at load: the split-sum approximation of
// B. Karis, "Real Shading in Unreal Engine 4" (SIGGRAPH 2013 course notes).
//
// cs_sky fills the base cube map (mip 0) from an equirectangular image, a procedural studio
// or a uniform colour; cs_downsample builds its mips (2x2 averages); cs_specular prefilters
// one mip of the specular cube for one roughness by GGX importance sampling, reading the base
// cube at the mip that matches each sample's solid angle (filtered importance sampling,
// GPU Gems 3, chapter 20); cs_irradiance integrates cos-weighted radiance over every texel of
// a small mip of the base cube; cs_sheen prefilters KHR_materials_sheen's environment with
// the Charlie distribution, as the Khronos glTF Sample Viewer 1.1 does (into the irradiance
// cube's mips 1 and after); cs_brdf_lut integrates the GGX BRDF with height-correlated
// Smith visibility (glTF 2.0, Appendix B) into the scale and bias applied to f0.
//
// Cube faces are in wgpu's order +X, -X, +Y, -Y, +Z, -Z. Equirectangular images: the
// longitude runs across (the centre column looks toward +Z, a quarter to the right toward -X,
// the left and right edges toward -Z), the top row looks up (+Y); the Khronos glTF Sample
// Viewer maps them so at its default environmentRotation of 90 degrees.

struct Params {
    // Face size in texels of the mip being written.
    size: u32,
    // cs_sky: 0 = equirectangular image, 1 = procedural studio, 2 = uniform colour.
    kind: u32,
    // cs_specular: perceptual roughness; cs_irradiance: unused.
    roughness: f32,
    // cs_specular: face size of the base cube's mip 0.
    base_size: f32,
    // cs_sky kind 2: the radiance.
    color: vec4<f32>,
}

const PI: f32 = 3.141592653589793;
const SKY_EQUIRECT: u32 = 0u;
const SKY_STUDIO: u32 = 1u;
const SPECULAR_SAMPLES: u32 = 128u;
const LUT_SAMPLES: u32 = 256u;
// The Sample Viewer's sample count for its Charlie-prefiltered cube.
const SHEEN_SAMPLES: u32 = 64u;

@group(0) @binding(0) var<uniform> params: Params;
// cs_sky
@group(0) @binding(1) var equirect: texture_2d<f32>;
@group(0) @binding(2) var sky_out: texture_storage_2d_array<rgba16float, write>;
// cs_downsample and cs_irradiance read a mip as an array of six faces.
@group(0) @binding(3) var faces_in: texture_2d_array<f32>;
@group(0) @binding(4) var faces_out: texture_storage_2d_array<rgba16float, write>;
// cs_specular and cs_sheen
@group(0) @binding(5) var base_cube: texture_cube<f32>;
@group(0) @binding(6) var base_sampler: sampler;
@group(0) @binding(7) var specular_out: texture_storage_2d_array<rgba16float, write>;
// cs_brdf_lut
@group(0) @binding(8) var lut_out: texture_storage_2d<rgba16float, write>;

// The unit direction through texel (x, y) of cube face `face` of `size` texels.
fn face_direction(face: u32, x: u32, y: u32, size: u32) -> vec3<f32> {
    let s = 2.0 * (f32(x) + 0.5) / f32(size) - 1.0;
    let t = 2.0 * (f32(y) + 0.5) / f32(size) - 1.0;
    var d: vec3<f32>;
    switch face {
        case 0u: { d = vec3<f32>(1.0, -t, -s); }
        case 1u: { d = vec3<f32>(-1.0, -t, s); }
        case 2u: { d = vec3<f32>(s, 1.0, t); }
        case 3u: { d = vec3<f32>(s, -1.0, -t); }
        case 4u: { d = vec3<f32>(s, -t, 1.0); }
        default: { d = vec3<f32>(-s, -t, -1.0); }
    }
    return normalize(d);
}

// The solid angle of texel (x, y) of a face of `size` texels.
fn texel_solid_angle(x: u32, y: u32, size: u32) -> f32 {
    let s = 2.0 * (f32(x) + 0.5) / f32(size) - 1.0;
    let t = 2.0 * (f32(y) + 0.5) / f32(size) - 1.0;
    let texel = 2.0 / f32(size);
    return texel * texel / pow(1.0 + s * s + t * t, 1.5);
}

// Bilinear read of the equirectangular image in direction d (wrapping across, clamped at the
// poles).
fn sample_equirect(d: vec3<f32>) -> vec3<f32> {
    let dims = vec2<f32>(textureDimensions(equirect));
    let u = 0.5 + atan2(-d.x, d.z) / (2.0 * PI);
    let v = acos(clamp(d.y, -1.0, 1.0)) / PI;
    let p = vec2<f32>(u, v) * dims - 0.5;
    let p0 = floor(p);
    let f = p - p0;
    let w = i32(dims.x);
    let h = i32(dims.y);
    let x0 = (i32(p0.x) % w + w) % w;
    let x1 = (x0 + 1) % w;
    let y0 = clamp(i32(p0.y), 0, h - 1);
    let y1 = clamp(i32(p0.y) + 1, 0, h - 1);
    let top = mix(textureLoad(equirect, vec2<i32>(x0, y0), 0).rgb, textureLoad(equirect, vec2<i32>(x1, y0), 0).rgb, f.x);
    let bottom = mix(textureLoad(equirect, vec2<i32>(x0, y1), 0).rgb, textureLoad(equirect, vec2<i32>(x1, y1), 0).rgb, f.x);
    return mix(top, bottom, f.y);
}

// A soft round light of `radiance` around `axis`, `radius` radians across, seen in direction d.
fn softbox(d: vec3<f32>, axis: vec3<f32>, radius: f32, radiance: vec3<f32>) -> vec3<f32> {
    let angle = acos(clamp(dot(d, normalize(axis)), -1.0, 1.0));
    return radiance * (1.0 - smoothstep(radius * 0.6, radius, angle));
}

// The built-in environment: a photographer's studio. A light grey cyclorama brightening
// toward the horizon, a darker floor, a large warm key softbox high at the front left, a
// cooler strip to the right and a rim light behind.
fn studio(d: vec3<f32>) -> vec3<f32> {
    let up = d.y;
    let wall = mix(vec3<f32>(0.62, 0.63, 0.66), vec3<f32>(0.32, 0.33, 0.36), smoothstep(0.0, 0.9, up));
    let floor = vec3<f32>(0.16, 0.155, 0.15);
    var c = mix(floor, wall, smoothstep(-0.06, 0.02, up));
    c = c + softbox(d, vec3<f32>(-0.55, 0.6, 0.6), 0.42, vec3<f32>(5.0, 4.7, 4.3));
    c = c + softbox(d, vec3<f32>(0.9, 0.25, 0.2), 0.3, vec3<f32>(1.6, 1.75, 2.0));
    c = c + softbox(d, vec3<f32>(0.1, 0.45, -1.0), 0.25, vec3<f32>(2.5, 2.5, 2.5));
    return c;
}

@compute @workgroup_size(8, 8, 1)
fn cs_sky(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.size || id.y >= params.size {
        return;
    }
    let d = face_direction(id.z, id.x, id.y, params.size);
    var c: vec3<f32>;
    if params.kind == SKY_EQUIRECT {
        c = sample_equirect(d);
    } else if params.kind == SKY_STUDIO {
        c = studio(d);
    } else {
        c = params.color.rgb;
    }
    // Half floats top out at 65504: keep the sun of an HDR photograph finite.
    c = clamp(c, vec3<f32>(0.0), vec3<f32>(60000.0));
    textureStore(sky_out, vec2<u32>(id.xy), id.z, vec4<f32>(c, 1.0));
}

@compute @workgroup_size(8, 8, 1)
fn cs_downsample(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.size || id.y >= params.size {
        return;
    }
    let p = vec2<i32>(id.xy) * 2;
    let face = i32(id.z);
    let sum = textureLoad(faces_in, p, face, 0) + textureLoad(faces_in, p + vec2<i32>(1, 0), face, 0)
        + textureLoad(faces_in, p + vec2<i32>(0, 1), face, 0) + textureLoad(faces_in, p + vec2<i32>(1, 1), face, 0);
    textureStore(faces_out, vec2<u32>(id.xy), id.z, sum * 0.25);
}

// Point i of n of the Hammersley set.
fn hammersley(i: u32, n: u32) -> vec2<f32> {
    return vec2<f32>(f32(i) / f32(n), f32(reverseBits(i)) * 2.3283064365386963e-10);
}

// A GGX-distributed half vector about n for a = roughness^2, from the point xi.
fn importance_ggx(xi: vec2<f32>, n: vec3<f32>, a: f32) -> vec3<f32> {
    let phi = 2.0 * PI * xi.x;
    // GPUs' square roots are not correctly rounded: near the narrow lobe of a smooth surface
    // cos_theta can come out a hair above 1, and 1 - cos^2 below 0 (NaN through the whole
    // table, seen on an NVIDIA H200; lavapipe rounds exactly). Both clamped.
    let cos_theta = min(sqrt((1.0 - xi.y) / (1.0 + (a * a - 1.0) * xi.y)), 1.0);
    let sin_theta = sqrt(max(1.0 - cos_theta * cos_theta, 0.0));
    let h = vec3<f32>(sin_theta * cos(phi), sin_theta * sin(phi), cos_theta);
    let up = select(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 0.0, 1.0), abs(n.z) < 0.999);
    let tx = normalize(cross(up, n));
    let ty = cross(n, tx);
    return normalize(tx * h.x + ty * h.y + n * h.z);
}

fn ggx(n_dot_h: f32, a: f32) -> f32 {
    let a2 = a * a;
    let d = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0;
    return a2 / (PI * d * d);
}

@compute @workgroup_size(8, 8, 1)
fn cs_specular(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.size || id.y >= params.size {
        return;
    }
    let n = face_direction(id.z, id.x, id.y, params.size);
    let a = max(params.roughness * params.roughness, 1e-3);
    if params.roughness <= 0.0 {
        textureStore(specular_out, vec2<u32>(id.xy), id.z, vec4<f32>(textureSampleLevel(base_cube, base_sampler, n, 0.0).rgb, 1.0));
        return;
    }
    // Solid angle of one base texel (at the face centre).
    let texel_angle = 4.0 * PI / (6.0 * params.base_size * params.base_size);
    var sum = vec3<f32>(0.0);
    var weight = 0.0;
    for (var i = 0u; i < SPECULAR_SAMPLES; i = i + 1u) {
        let h = importance_ggx(hammersley(i, SPECULAR_SAMPLES), n, a);
        let l = normalize(2.0 * dot(n, h) * h - n);
        let n_dot_l = dot(n, l);
        if n_dot_l <= 0.0 {
            continue;
        }
        // With n = v, the pdf of l is D / 4.
        let n_dot_h = max(dot(n, h), 0.0);
        let pdf = ggx(n_dot_h, a) * 0.25;
        let sample_angle = 1.0 / (f32(SPECULAR_SAMPLES) * pdf + 1e-6);
        let lod = max(0.5 * log2(sample_angle / texel_angle) + 1.0, 0.0);
        sum = sum + textureSampleLevel(base_cube, base_sampler, l, lod).rgb * n_dot_l;
        weight = weight + n_dot_l;
    }
    textureStore(specular_out, vec2<u32>(id.xy), id.z, vec4<f32>(sum / max(weight, 1e-6), 1.0));
}

// The Charlie distribution as the Sample Viewer's prefilter evaluates it (ibl_filtering.frag
// D_Charlie, given alpha = roughness^2 where the shading gives the roughness).
fn charlie_of_alpha(alpha: f32, n_dot_h: f32) -> f32 {
    let inv = 1.0 / max(alpha, 1e-6);
    let sin2 = max(1.0 - n_dot_h * n_dot_h, 0.0);
    return (2.0 + inv) * pow(sin2, inv * 0.5) / (2.0 * PI);
}

// The frame about n in which the Sample Viewer lays out its samples (generateTBN): the
// tangent across +Y, or across +Z or -Z where n is +Y or -Y.
fn viewer_frame(n: vec3<f32>) -> mat3x3<f32> {
    var b = vec3<f32>(0.0, 1.0, 0.0);
    let n_dot_up = dot(n, b);
    if 1.0 - abs(n_dot_up) <= 1e-7 {
        b = vec3<f32>(0.0, 0.0, sign(n_dot_up));
    }
    let t = normalize(cross(b, n));
    return mat3x3<f32>(t, cross(n, t), n);
}

// KHR_materials_sheen's environment for a sheen roughness (one mip of the irradiance cube):
// the Sample Viewer's Charlie prefilter. Half vectors drawn from the Charlie distribution
// (sin theta = xi^(alpha / (2 alpha + 1))), reflected about n = v; each sample reads the base
// cube at the mip its pdf (D / 4) gives over 64 samples, and weighs by n.l. Most of these
// half vectors lie near the horizon and reflect below it, so the few kept come from near n
// at small pdfs: the result is the base cube's smallest mips around n.
@compute @workgroup_size(8, 8, 1)
fn cs_sheen(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.size || id.y >= params.size {
        return;
    }
    let n = face_direction(id.z, id.x, id.y, params.size);
    let frame = viewer_frame(n);
    let alpha = params.roughness * params.roughness;
    let exponent = alpha / (2.0 * alpha + 1.0);
    let last_mip = f32(textureNumLevels(base_cube) - 1u);
    var sum = vec3<f32>(0.0);
    var weight = 0.0;
    for (var i = 0u; i < SHEEN_SAMPLES; i = i + 1u) {
        let xi = hammersley(i, SHEEN_SAMPLES);
        // pow(0, e) is 0 for e > 0; at roughness 0 every half vector lies on the horizon.
        var sin_theta = select(pow(xi.y, exponent), 0.0, xi.y <= 0.0);
        if exponent <= 0.0 {
            sin_theta = 1.0;
        }
        let cos_theta = sqrt(max(1.0 - sin_theta * sin_theta, 0.0));
        let phi = 2.0 * PI * xi.x;
        let h = normalize(frame * vec3<f32>(sin_theta * cos(phi), sin_theta * sin(phi), cos_theta));
        let l = normalize(2.0 * dot(n, h) * h - n);
        let n_dot_l = dot(n, l);
        if n_dot_l <= 0.0 {
            continue;
        }
        let pdf = charlie_of_alpha(alpha, cos_theta) * 0.25;
        let lod = 0.5 * log2(6.0 * params.base_size * params.base_size / (f32(SHEEN_SAMPLES) * max(pdf, 1e-30)));
        sum = sum + textureSampleLevel(base_cube, base_sampler, l, clamp(lod, 0.0, last_mip)).rgb * n_dot_l;
        weight = weight + n_dot_l;
    }
    textureStore(specular_out, vec2<u32>(id.xy), id.z, vec4<f32>(sum / max(weight, 1e-6), 1.0));
}

// Irradiance divided by pi (the radiance a white Lambert surface reflects), exactly summed
// over every texel of the mip bound as faces_in.
@compute @workgroup_size(8, 8, 1)
fn cs_irradiance(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.size || id.y >= params.size {
        return;
    }
    let n = face_direction(id.z, id.x, id.y, params.size);
    let src = textureDimensions(faces_in).x;
    var sum = vec3<f32>(0.0);
    for (var face = 0u; face < 6u; face = face + 1u) {
        for (var y = 0u; y < src; y = y + 1u) {
            for (var x = 0u; x < src; x = x + 1u) {
                let l = face_direction(face, x, y, src);
                let n_dot_l = dot(n, l);
                if n_dot_l > 0.0 {
                    let radiance = textureLoad(faces_in, vec2<u32>(x, y), face, 0).rgb;
                    sum = sum + radiance * n_dot_l * texel_solid_angle(x, y, src);
                }
            }
        }
    }
    textureStore(faces_out, vec2<u32>(id.xy), id.z, vec4<f32>(sum / PI, 1.0));
}

// The split-sum scale (r) and bias (g) on f0 for n.v = x and perceptual roughness = y.
@compute @workgroup_size(8, 8, 1)
fn cs_brdf_lut(@builtin(global_invocation_id) id: vec3<u32>) {
    let dims = vec2<u32>(params.size);
    if id.x >= dims.x || id.y >= dims.y {
        return;
    }
    let n_dot_v = max((f32(id.x) + 0.5) / f32(dims.x), 1e-3);
    let roughness = (f32(id.y) + 0.5) / f32(dims.y);
    let a = max(roughness * roughness, 1e-3);
    let a2 = a * a;
    let v = vec3<f32>(sqrt(1.0 - n_dot_v * n_dot_v), 0.0, n_dot_v);
    let n = vec3<f32>(0.0, 0.0, 1.0);
    var scale = 0.0;
    var bias = 0.0;
    for (var i = 0u; i < LUT_SAMPLES; i = i + 1u) {
        let h = importance_ggx(hammersley(i, LUT_SAMPLES), n, a);
        let l = normalize(2.0 * dot(v, h) * h - v);
        let n_dot_l = l.z;
        let n_dot_h = max(h.z, 0.0);
        let v_dot_h = max(dot(v, h), 0.0);
        if n_dot_l <= 0.0 {
            continue;
        }
        // Height-correlated Smith visibility, as in the direct lighting.
        let vis = 0.5 / (n_dot_l * sqrt(n_dot_v * n_dot_v * (1.0 - a2) + a2) + n_dot_v * sqrt(n_dot_l * n_dot_l * (1.0 - a2) + a2));
        // BRDF * n.l / pdf with pdf = D * n.h / (4 v.h).
        let g = vis * 4.0 * n_dot_l * v_dot_h / max(n_dot_h, 1e-6);
        // pow of a negative base is undefined in WGSL (NaN on GPUs): v.h can round above 1.
        let fc = pow(max(1.0 - v_dot_h, 0.0), 5.0);
        scale = scale + (1.0 - fc) * g;
        bias = bias + fc * g;
    }
    textureStore(lut_out, vec2<u32>(id.xy), vec4<f32>(scale, bias, 0.0, 1.0) / f32(LUT_SAMPLES));
}

// The shadow-map pass: each mesh's depth as a light sees it (directional lights through an
// orthographic projection that holds the scene's bounds, spot lights through a perspective
// one the width of their outer cone). mesh.wgsl compares against these depths, 3 x 3 taps of
// a comparison sampler (percentage-closer filtering, W. Reeves et al. 1987).

// `Object` (the per-object uniforms, as mesh.wgsl reads them) is in object.wgsl, and
// `deform` (morph targets and skinning, as the scene pass applies them) in deform.wgsl, both
// put in front of this file.

@group(0) @binding(0) var<uniform> light_view_proj: mat4x4<f32>;
@group(1) @binding(0) var<uniform> object: Object;
@group(1) @binding(2) var<storage, read> skin: array<SkinVertex>;
@group(1) @binding(3) var<storage, read> morph_deltas: array<vec4<f32>>;
@group(1) @binding(4) var<storage, read> joint_palette: array<mat4x4<f32>>;
@group(1) @binding(5) var<storage, read> morph_weights: array<f32>;

@vertex
fn vs_shadow(
    @location(0) position: vec3<f32>,
    @builtin(vertex_index) index: u32,
) -> @builtin(position) vec4<f32> {
    // Normal and tangent do not move a depth: the morph and skin of the position alone.
    let posed = deform(index, position, vec3<f32>(0.0, 0.0, 1.0), vec4<f32>(1.0, 0.0, 0.0, 1.0));
    return light_view_proj * object.model * vec4<f32>(posed.position, 1.0);
}

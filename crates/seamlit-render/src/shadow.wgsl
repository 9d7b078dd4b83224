// The shadow-map pass: each mesh's depth as a light sees it (directional lights through an
// orthographic projection that holds the scene's bounds, spot lights through a perspective
// one the width of their outer cone). mesh.wgsl compares against these depths, 3 x 3 taps of
// a comparison sampler (percentage-closer filtering, W. Reeves et al. 1987).

// `Object` (the per-object uniforms, as mesh.wgsl reads them) is in object.wgsl, put in
// front of this file.

@group(0) @binding(0) var<uniform> light_view_proj: mat4x4<f32>;
@group(1) @binding(0) var<uniform> object: Object;

@vertex
fn vs_shadow(@location(0) position: vec3<f32>) -> @builtin(position) vec4<f32> {
    return light_view_proj * object.model * vec4<f32>(position, 1.0);
}

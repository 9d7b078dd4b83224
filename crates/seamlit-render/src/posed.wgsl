// The posed-vertex readback (GpuScene::posed_vertices): one invocation per vertex runs the
// vertex stage's `deform` (deform.wgsl) and the object's transform, and writes the world-space
// position, normal and tangent, 12 floats a vertex: position (w = 1), unit normal (w = 0),
// tangent (xyz transformed by the model matrix, unnormalised; w the handedness).

@group(0) @binding(0) var<uniform> object: Object;
@group(0) @binding(1) var<storage, read> vertex_data: array<f32>;
@group(0) @binding(2) var<storage, read> skin: array<SkinVertex>;
@group(0) @binding(3) var<storage, read> morph_deltas: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read> joint_palette: array<mat4x4<f32>>;
@group(0) @binding(5) var<storage, read> morph_weights: array<f32>;
@group(1) @binding(0) var<storage, read_write> posed: array<vec4<f32>>;

@compute @workgroup_size(64)
fn cs_posed(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
) {
    let v = id.y * groups.x * 64u + id.x;
    if v >= arrayLength(&posed) / 3u {
        return;
    }
    let o = v * 18u;
    let position = vec3<f32>(vertex_data[o], vertex_data[o + 1u], vertex_data[o + 2u]);
    let normal = vec3<f32>(vertex_data[o + 3u], vertex_data[o + 4u], vertex_data[o + 5u]);
    let tangent = vec4<f32>(vertex_data[o + 6u], vertex_data[o + 7u], vertex_data[o + 8u], vertex_data[o + 9u]);
    let d = deform(v, position, normal, tangent);
    let n = safe_normalize((object.normal * vec4<f32>(d.normal, 0.0)).xyz, vec3<f32>(0.0, 0.0, 1.0));
    posed[v * 3u] = object.model * vec4<f32>(d.position, 1.0);
    posed[v * 3u + 1u] = vec4<f32>(n, 0.0);
    posed[v * 3u + 2u] = vec4<f32>((object.model * vec4<f32>(d.tangent.xyz, 0.0)).xyz, d.tangent.w);
}

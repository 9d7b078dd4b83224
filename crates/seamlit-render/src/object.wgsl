// The per-object uniforms (`ObjectRaw` in scene.rs), which the scene pass (mesh.wgsl), the
// shadow pass (shadow.wgsl) and the posed-vertex readback (posed.wgsl) all read. WGSL has no
// include: shaders.rs puts this file in front of each of them, so the struct is written once.
//
// `skin_sets` and `morph_targets` are zero unless a pose is set (GpuScene::set_pose): then
// deform.wgsl reads that many JOINTS/WEIGHTS sets and morph targets for each vertex.

struct Object {
    model: mat4x4<f32>,
    normal: mat4x4<f32>,
    det_sign: f32,
    object_id: u32,
    flip_v: u32,
    has_tangents: u32,
    skin_sets: u32,
    morph_targets: u32,
    vertex_count: u32,
    pad0: u32,
}

// The per-object uniforms (`ObjectRaw` in scene.rs), which the scene pass (mesh.wgsl) and the
// shadow pass (shadow.wgsl) both read. WGSL has no include: shaders.rs puts this file in front
// of each of them, so the struct is written once.

struct Object {
    model: mat4x4<f32>,
    normal: mat4x4<f32>,
    det_sign: f32,
    object_id: u32,
    flip_v: u32,
    has_tangents: u32,
}


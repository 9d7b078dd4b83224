// Morph targets and linear blend skinning of one vertex, shared by the scene pass, the shadow
// pass and the posed-vertex readback (shaders.rs puts this file after object.wgsl in front of
// each). Each of them declares, in its own bind group, `object: Object` and the storage
// buffers read here (the object's group, `Layouts::object` in context.rs):
//   skin: array<SkinVertex>        set s of vertex v at s * vertex_count + v
//   morph_deltas: array<vec4<f32>> target k of vertex v at (k * vertex_count + v) * 3:
//                                  position, normal, tangent deltas in xyz (zeros where
//                                  none; vectors, so that each is one load)
//   joint_palette: array<mat4x4>   model-space joint matrices, indexed by SkinVertex.joints
//   morph_weights: array<f32>      one per target
//
// The maths (glTF 2.0, "Skins" and "Morph Targets"; seamlit_asset::pose::posed_object on the
// CPU): v = base + sum_k w_k * delta_k for position, normal and tangent; then, for a skinned
// object, M = sum over sets and lanes of weight * joint_palette[joint], position = M * v,
// normal with M's inverse-transpose (the cofactor matrix times sign(det M)) normalised,
// tangent xyz with M, w kept.

// False in the pipelines that draw objects without a pose (pipeline.rs, shadow.rs), so that
// they run none of this: unposed objects cost what they did before skinning existed.
override DEFORM: bool = true;

struct SkinVertex {
    joints: vec4<u32>,
    weights: vec4<f32>,
}

struct Deformed {
    position: vec3<f32>,
    normal: vec3<f32>,
    tangent: vec4<f32>,
    // The sign of the skinning matrix's determinant (1 unskinned): a mirroring joint flips
    // the bitangent as a mirroring transform does.
    det_sign: f32,
}

fn deform(v: u32, position: vec3<f32>, normal: vec3<f32>, tangent: vec4<f32>) -> Deformed {
    var out: Deformed;
    out.position = position;
    out.normal = normal;
    out.tangent = tangent;
    out.det_sign = 1.0;
    if !DEFORM {
        return out;
    }
    let n = object.vertex_count;
    for (var k = 0u; k < object.morph_targets; k = k + 1u) {
        let w = morph_weights[k];
        if w != 0.0 {
            let at = (k * n + v) * 3u;
            out.position = out.position + w * morph_deltas[at].xyz;
            out.normal = out.normal + w * morph_deltas[at + 1u].xyz;
            out.tangent = vec4<f32>(out.tangent.xyz + w * morph_deltas[at + 2u].xyz, out.tangent.w);
        }
    }
    if object.skin_sets == 0u {
        return out;
    }
    var m = mat4x4<f32>(vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0));
    for (var s = 0u; s < object.skin_sets; s = s + 1u) {
        let influence = skin[s * n + v];
        // Lanes without weight (most vertices have fewer than four influences) are skipped.
        for (var lane = 0u; lane < 4u; lane = lane + 1u) {
            let w = influence.weights[lane];
            if w != 0.0 {
                m = m + joint_palette[influence.joints[lane]] * w;
            }
        }
    }
    let a = m[0].xyz;
    let b = m[1].xyz;
    let c = m[2].xyz;
    let det = dot(a, cross(b, c));
    out.det_sign = select(1.0, -1.0, det < 0.0);
    out.position = (m * vec4<f32>(out.position, 1.0)).xyz;
    let cofactor = mat3x3<f32>(cross(b, c), cross(c, a), cross(a, b));
    out.normal = safe_normalize(cofactor * out.normal * out.det_sign, out.normal);
    out.tangent = vec4<f32>(mat3x3<f32>(a, b, c) * out.tangent.xyz, out.tangent.w);
    return out;
}

fn safe_normalize(v: vec3<f32>, fallback: vec3<f32>) -> vec3<f32> {
    let len2 = dot(v, v);
    if len2 > 1e-20 {
        return v * inverseSqrt(len2);
    }
    return fallback;
}

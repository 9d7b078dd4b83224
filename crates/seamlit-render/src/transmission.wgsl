// The transmission target's mips (transmission.rs): each the one above it, filtered
// bilinearly at its texel centres (a 2 x 2 box), as WebGL's generateMipmap makes the
// Sample Viewer's.

@group(0) @binding(0) var above: texture_2d<f32>;
@group(0) @binding(1) var above_sampler: sampler;

struct Out {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
}

// One triangle that covers the target.
@vertex
fn vs_mip(@builtin(vertex_index) index: u32) -> Out {
    let p = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    var out: Out;
    out.clip = vec4<f32>(p * 2.0 - 1.0, 0.0, 1.0);
    out.uv = vec2<f32>(p.x, 1.0 - p.y);
    return out;
}

@fragment
fn fs_mip(in: Out) -> @location(0) vec4<f32> {
    return textureSampleLevel(above, above_sampler, in.uv, 0.0);
}

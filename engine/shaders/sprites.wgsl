// Sprites: textured triangles, two a sprite, built on the CPU each frame
// (there are few of them); the texture is sRGB (sampled as linear), the
// tint sRGB bytes, both straight alpha; the output premultiplied.
//
// (common.wgsl is prepended: Globals, Instance, sRGB conversions.)

@group(0) @binding(0) var<uniform> globals: Globals;
@group(1) @binding(0) var image: texture_2d<f32>;
@group(1) @binding(1) var image_sampler: sampler;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
    @location(1) tint: vec4<f32>,
};

@vertex
fn vs_main(@location(0) position: vec3<f32>, @location(1) uv: vec2<f32>, @location(2) tint: vec4<f32>) -> VertexOut {
    var out: VertexOut;
    out.clip = globals.view_proj * vec4<f32>(position, 1.0);
    out.uv = uv;
    out.tint = vec4<f32>(srgb_to_linear(tint.rgb), tint.a);
    return out;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let colour = textureSample(image, image_sampler, in.uv) * in.tint;
    return vec4<f32>(colour.rgb * colour.a, colour.a);
}

// Lines (trails, springs, rigid-body boxes and axes, a game's own lines):
// a line list with a colour per vertex, already interpolated on the CPU
// (there are few of them).
//
// (common.wgsl is prepended: Globals, Instance, sRGB conversions.)

@group(0) @binding(0) var<uniform> globals: Globals;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) colour: vec4<f32>,
};

@vertex
fn vs_main(@location(0) position: vec3<f32>, @location(1) colour: vec4<f32>) -> VertexOut {
    var out: VertexOut;
    out.clip = globals.view_proj * vec4<f32>(position, 1.0);
    out.colour = vec4<f32>(srgb_to_linear(colour.rgb), colour.a);
    return out;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    return vec4<f32>(in.colour.rgb * in.colour.a, in.colour.a);
}

// Lines (trails, springs, rigid-body boxes and axes, a game's own lines):
// a line list with a colour per vertex, already interpolated on the CPU
// (there are few of them).

struct Globals {
    view_proj: mat4x4<f32>,
    viewport: vec2<f32>,
    pixels_per_unit: f32,
    t: f32,
    min_radius_px: f32,
    _pad0: f32,
    _pad1: f32,
    _pad2: f32,
};

@group(0) @binding(0) var<uniform> globals: Globals;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) colour: vec4<f32>,
};

fn srgb_to_linear(c: vec3<f32>) -> vec3<f32> {
    let low = c / 12.92;
    let high = pow((c + 0.055) / 1.055, vec3<f32>(2.4));
    return select(high, low, c <= vec3<f32>(0.04045));
}

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

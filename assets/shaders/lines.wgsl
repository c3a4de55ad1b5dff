// Lines (trails, springs, rigid-body boxes and axes, a game's own lines):
// a line list with a colour per vertex, already interpolated on the CPU
// (there are few of them).

struct Globals {
    view_proj: mat4x4<f32>,
    // Image size in pixels.
    viewport: vec2<f32>,
    // Pixels per world unit at clip w = 1 (see Camera::matrices).
    pixels_per_unit: f32,
    // Interpolation parameter: alpha (interpolate) or 1 + alpha (extrapolate).
    t: f32,
    // Discs smaller than this radius in pixels are drawn at this radius with
    // their coverage scaled by the area ratio, so they neither vanish nor
    // shimmer.
    min_radius_px: f32,
    // Particles drawn.
    count: u32,
    // Words per row of the splat's output buffer (rows padded to 256 bytes).
    stride: u32,
    // 1 when the target is BGRA (the splat packs pixels itself).
    swap_rb: u32,
    // Clear colour, linear RGBA.
    background: vec4<f32>,
    // Clear colour as the target's packed 8-bit word.
    background_word: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
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

// Shared by every Tickwork shader: the renderer prepends this file to each
// module (WGSL has no includes), so the uniform block, the particle record
// and the colour conversions are defined once.

// Uniforms of every pass (112 bytes; `Globals` in renderer.rs).
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

// One particle, 32 bytes: previous position and radius, current position and
// colour (RGBA8, sRGB). `Instance` in renderer.rs.
struct Instance {
    previous: vec3<f32>,
    radius: f32,
    current: vec3<f32>,
    colour: u32,
};

// sRGB transfer function and its inverse (IEC 61966-2-1).
fn srgb_to_linear(c: vec3<f32>) -> vec3<f32> {
    let low = c / 12.92;
    let high = pow((c + 0.055) / 1.055, vec3<f32>(2.4));
    return select(high, low, c <= vec3<f32>(0.04045));
}

fn linear_to_srgb(c: vec3<f32>) -> vec3<f32> {
    let low = c * 12.92;
    let high = 1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(high, low, c <= vec3<f32>(0.0031308));
}

// Where particle `p` is drawn: previous + t (current - previous), the lerp of
// engine/src/interpolation.rs (t from Interpolation::parameter).
fn interpolated(p: Instance) -> vec3<f32> {
    return mix(p.previous, p.current, globals.t);
}

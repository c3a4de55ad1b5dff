// Shared by every Tickwork shader: the renderer prepends this file to each
// module (WGSL has no includes), so the uniform block, the particle record
// and the colour conversions are defined once.

// Uniforms of every pass (128 bytes; `Globals` in renderer.rs).
struct Globals {
    view_proj: mat4x4<f32>,
    // Image size in pixels.
    viewport: vec2<f32>,
    // Pixels per world unit at clip w = 1 (see Camera::matrices).
    pixels_per_unit: f32,
    // Interpolation parameter: alpha (interpolate, Hermite) or 1 + alpha
    // (extrapolate).
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
    // The fixed step in seconds (Hermite mode; 0 otherwise).
    dt: f32,
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

// A particle's velocity at the current step, 12 bytes, in a second buffer
// bound only in Hermite mode (the 32-byte record stays as it is for lerp).
// `Velocity` in renderer.rs.
struct Velocity {
    x: f32,
    y: f32,
    z: f32,
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

// Cubic Hermite through a step of dt seconds from x0 moving at v0 to x1
// moving at v1, at t in [0, 1]; exact for motion up to cubic in time:
//   x(t) = h00 x0 + h10 dt v0 + h01 x1 + h11 dt v1
//   h00 = 2t^3 - 3t^2 + 1   h10 = t^3 - 2t^2 + t   h01 = -2t^3 + 3t^2   h11 = t^3 - t^2
// The twin of `hermite` in engine/src/interpolation.rs, term for term.
fn hermite(x0: vec3<f32>, v0: vec3<f32>, x1: vec3<f32>, v1: vec3<f32>, dt: f32, t: f32) -> vec3<f32> {
    let t2 = t * t;
    let t3 = t * t * t;
    let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
    let h10 = t3 - 2.0 * t2 + t;
    let h01 = -2.0 * t3 + 3.0 * t2;
    let h11 = t3 - t2;
    return h00 * x0 + (h10 * dt) * v0 + h01 * x1 + (h11 * dt) * v1;
}

// Hermite when only the end velocity is kept (the world keeps no previous
// velocity): the start velocity v0 = 2 (x1 - x0) / dt - v1 is that of the
// constant-acceleration motion through both positions, so the curve is the
// parabola lerp(x0, x1, t) + t (1 - t) (x1 - x0 - dt v1): a projectile's
// arc when the integrator's step lies on it (velocity Verlet, leapfrog,
// Heun, midpoint, RK4), the chord for semi-implicit Euler (x1 = x0 + dt v1).
// Only where both tangents point along the step, d = x1 - x0:
// v1 . d > 0 and v0 . d = 2 |d|^2 / dt - v1 . d > 0; elsewhere a contact or
// the game turned the velocity (a bounce: the curve would dip through the
// floor) and the chord is drawn, as is a particle that did not move. The
// twin of `hermite_from_end` and `start_velocity` in
// engine/src/interpolation.rs.
fn hermite_from_end(x0: vec3<f32>, x1: vec3<f32>, v1: vec3<f32>, dt: f32, t: f32) -> vec3<f32> {
    let d = x1 - x0;
    let along = dot(d, v1);
    if !(along > 0.0 && along < 2.0 * dot(d, d) / dt) {
        return mix(x0, x1, t);
    }
    let v0 = 2.0 * d / dt - v1;
    return hermite(x0, v0, x1, v1, dt, t);
}

// Where particle `p`, ending the step at velocity `v`, is drawn in Hermite
// mode (Interpolation::Hermite).
fn interpolated_hermite(p: Instance, v: Velocity) -> vec3<f32> {
    return hermite_from_end(p.previous, p.current, vec3<f32>(v.x, v.y, v.z), globals.dt, globals.t);
}

// The compute splat path for many small particles in 2D views.
//
// Software rasterisers pay about a microsecond per primitive, so 100k
// quads cost 100+ ms a frame on lavapipe. Instead, one compute invocation per
// particle writes its disc's coverage straight into a per-pixel buffer:
// `key = coverage (8 bits) << 24 | row (24 bits)`, kept by atomicMax, so
// the most-covering particle owns the pixel (and among equal coverage the
// later row, as "over" drawing would show). A full-screen pass then
// composites each pixel's owner at its coverage. Deterministic whatever the
// order of invocations.

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

struct Instance {
    previous: vec3<f32>,
    radius: f32,
    current: vec3<f32>,
    colour: u32,
};

@group(0) @binding(0) var<uniform> globals: Globals;
@group(0) @binding(1) var<storage, read> instances: array<Instance>;
// One word per pixel (three for additive sums), rows `stride` words long
// like the output's, so the resolve can read and write four pixels at once.
@group(0) @binding(2) var<storage, read_write> owners: array<atomic<u32>>;

// Largest drawn radius in pixels the splat handles (the renderer checks).
const MAX_RADIUS: f32 = 4.0;

// Particles per invocation: a software renderer pays microseconds per
// workgroup, so fewer, longer invocations are faster.
const PER_INVOCATION: u32 = 16u;

@compute @workgroup_size(64)
fn splat(@builtin(global_invocation_id) id: vec3<u32>) {
    let first = (id.x + id.y * 65535u * 64u) * PER_INVOCATION;
    for (var index = first; index < min(first + PER_INVOCATION, globals.count); index++) {
        splat_one(index);
    }
}

fn splat_one(index: u32) {
    let particle = instances[index];
    let position = mix(particle.previous, particle.current, globals.t);
    let clip = globals.view_proj * vec4<f32>(position, 1.0);
    // Pixel coordinates with y down, pixel centres at +0.5.
    let ndc = clip.xy / clip.w;
    let centre = vec2<f32>((ndc.x * 0.5 + 0.5) * globals.viewport.x, (0.5 - ndc.y * 0.5) * globals.viewport.y);
    let radius_px = particle.radius * globals.pixels_per_unit / clip.w;
    let drawn = clamp(radius_px, globals.min_radius_px, MAX_RADIUS);
    let scale = min((radius_px * radius_px) / (drawn * drawn), 1.0);
    let size = vec2<i32>(globals.viewport);
    // Pixels whose centre (x + 0.5) lies within drawn + 0.5 of the centre:
    // the only ones with coverage.
    let low = max(vec2<i32>(ceil(centre - drawn - 1.0)), vec2<i32>(0));
    let high = min(vec2<i32>(floor(centre + drawn)), size - 1);
    // Coverage is zero beyond drawn + 0.5 from the centre: test the squared
    // distance first and take the square root only inside.
    let reach = (drawn + 0.5) * (drawn + 0.5);
    for (var y = low.y; y <= high.y; y++) {
        let dy = f32(y) + 0.5 - centre.y;
        let row = u32(y) * globals.stride;
        for (var x = low.x; x <= high.x; x++) {
            let dx = f32(x) + 0.5 - centre.x;
            let d2 = dx * dx + dy * dy;
            if d2 < reach {
                let coverage = clamp(0.5 - (sqrt(d2) - drawn), 0.0, 1.0) * scale;
                let q = u32(round(coverage * 255.0));
                if q > 0u {
                    atomicMax(&owners[row + u32(x)], (q << 24u) | index);
                }
            }
        }
    }
}

fn srgb_to_linear(c: vec3<f32>) -> vec3<f32> {
    let low = c / 12.92;
    let high = pow((c + 0.055) / 1.055, vec3<f32>(2.4));
    return select(high, low, c <= vec3<f32>(0.04045));
}

// Additive blending: colours add up, so each covered pixel gets the
// particle's linear, premultiplied colour times its coverage, in fixed point
// (1/1024), summed by atomicAdd into three channels: integer sums are
// exact and independent of order, so frames stay deterministic.
@compute @workgroup_size(64)
fn splat_additive(@builtin(global_invocation_id) id: vec3<u32>) {
    let first = (id.x + id.y * 65535u * 64u) * PER_INVOCATION;
    for (var index = first; index < min(first + PER_INVOCATION, globals.count); index++) {
        splat_additive_one(index);
    }
}

fn splat_additive_one(index: u32) {
    let particle = instances[index];
    let position = mix(particle.previous, particle.current, globals.t);
    let clip = globals.view_proj * vec4<f32>(position, 1.0);
    let ndc = clip.xy / clip.w;
    let centre = vec2<f32>((ndc.x * 0.5 + 0.5) * globals.viewport.x, (0.5 - ndc.y * 0.5) * globals.viewport.y);
    let radius_px = particle.radius * globals.pixels_per_unit / clip.w;
    let drawn = clamp(radius_px, globals.min_radius_px, MAX_RADIUS);
    let scale = min((radius_px * radius_px) / (drawn * drawn), 1.0);
    let srgb = unpack4x8unorm(particle.colour);
    let colour = srgb_to_linear(srgb.rgb) * srgb.a * scale * 1024.0;
    let size = vec2<i32>(globals.viewport);
    // Pixels whose centre (x + 0.5) lies within drawn + 0.5 of the centre:
    // the only ones with coverage.
    let low = max(vec2<i32>(ceil(centre - drawn - 1.0)), vec2<i32>(0));
    let high = min(vec2<i32>(floor(centre + drawn)), size - 1);
    for (var y = low.y; y <= high.y; y++) {
        for (var x = low.x; x <= high.x; x++) {
            let d = length(vec2<f32>(f32(x) + 0.5, f32(y) + 0.5) - centre) - drawn;
            let coverage = clamp(0.5 - d, 0.0, 1.0);
            if coverage > 0.0 {
                let add = vec3<u32>(round(colour * coverage));
                let p = 3u * (u32(y) * globals.stride + u32(x));
                atomicAdd(&owners[p], add.r);
                atomicAdd(&owners[p + 1u], add.g);
                atomicAdd(&owners[p + 2u], add.b);
            }
        }
    }
}

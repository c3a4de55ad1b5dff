// The compute splat path for many small particles in 2D views.
//
// Software rasterisers pay about a microsecond per primitive, so 100k
// quads cost 300 ms a frame on lavapipe. Instead, each compute invocation
// writes the coverage of 16 particles' discs straight into a per-pixel
// buffer: `key = coverage (8 bits) << 24 | row (24 bits)`, kept by
// atomicMax, so the most-covering particle owns the pixel (and among equal
// coverage the later row, as "over" drawing would show). The resolve
// (splat_composite.wgsl) then draws each pixel's owner at its coverage.
// Deterministic whatever the order of invocations.
//
// Each pass has a Hermite twin (`splat_hermite`, `splat_additive_hermite`)
// that places the discs by `interpolated_hermite` from the velocities,
// bound only in Hermite mode; the lerp entries do not touch them.
//
// (common.wgsl is prepended: Globals, Instance, Velocity, the interpolation
// formulas, sRGB conversions.)

@group(0) @binding(0) var<uniform> globals: Globals;
@group(0) @binding(1) var<storage, read> instances: array<Instance>;
// One word per pixel (three for additive sums), rows `stride` words long
// like the output's, so the resolve can read and write four pixels at once.
@group(0) @binding(2) var<storage, read_write> owners: array<atomic<u32>>;
// Hermite mode only: the particles' current velocities, row for row.
@group(0) @binding(3) var<storage, read> velocities: array<Velocity>;

// Largest drawn radius in pixels the splat handles (the renderer checks).
const MAX_RADIUS: f32 = 4.0;

// Particles per invocation: a software renderer pays microseconds per
// workgroup, so fewer, longer invocations are faster.
const PER_INVOCATION: u32 = 16u;

// A particle's disc in pixels: centre (y down, pixel centres at +0.5),
// drawn radius, coverage scale (area ratio below the minimum radius) and the
// pixel rectangle that can be covered.
struct Footprint {
    centre: vec2<f32>,
    drawn: f32,
    scale: f32,
    low: vec2<i32>,
    high: vec2<i32>,
};

fn footprint(particle: Instance, position: vec3<f32>) -> Footprint {
    let clip = globals.view_proj * vec4<f32>(position, 1.0);
    let ndc = clip.xy / clip.w;
    var f: Footprint;
    f.centre = vec2<f32>((ndc.x * 0.5 + 0.5) * globals.viewport.x, (0.5 - ndc.y * 0.5) * globals.viewport.y);
    let radius_px = particle.radius * globals.pixels_per_unit / clip.w;
    f.drawn = clamp(radius_px, globals.min_radius_px, MAX_RADIUS);
    f.scale = min((radius_px * radius_px) / (f.drawn * f.drawn), 1.0);
    // Pixels whose centre (x + 0.5) lies within drawn + 0.5 of the centre:
    // the only ones with coverage.
    let size = vec2<i32>(globals.viewport);
    f.low = max(vec2<i32>(ceil(f.centre - f.drawn - 1.0)), vec2<i32>(0));
    f.high = min(vec2<i32>(floor(f.centre + f.drawn)), size - 1);
    return f;
}

// Coverage of pixel (x, y) by the disc, in [0, 1]: one pixel of ramp at the
// edge. The squared distance rejects the rectangle's corners before the
// square root.
fn coverage(f: Footprint, x: i32, y: i32) -> f32 {
    let d = vec2<f32>(f32(x) + 0.5, f32(y) + 0.5) - f.centre;
    let d2 = dot(d, d);
    if d2 >= (f.drawn + 0.5) * (f.drawn + 0.5) {
        return 0.0;
    }
    return clamp(0.5 - (sqrt(d2) - f.drawn), 0.0, 1.0) * f.scale;
}

// The particles of invocation `id`: sixteen consecutive rows.
fn rows_of(id: vec3<u32>) -> vec2<u32> {
    let first = (id.x + id.y * 65535u * 64u) * PER_INVOCATION;
    return vec2<u32>(first, min(first + PER_INVOCATION, globals.count));
}

// Keeps, in each pixel that particle `index` drawn at `position` covers,
// the most-covering particle.
fn splat_one(index: u32, particle: Instance, position: vec3<f32>) {
    let f = footprint(particle, position);
    for (var y = f.low.y; y <= f.high.y; y++) {
        let row = u32(y) * globals.stride;
        for (var x = f.low.x; x <= f.high.x; x++) {
            let q = u32(round(coverage(f, x, y) * 255.0));
            if q > 0u {
                atomicMax(&owners[row + u32(x)], (q << 24u) | index);
            }
        }
    }
}

@compute @workgroup_size(64)
fn splat(@builtin(global_invocation_id) id: vec3<u32>) {
    let rows = rows_of(id);
    for (var index = rows.x; index < rows.y; index++) {
        let particle = instances[index];
        splat_one(index, particle, interpolated(particle));
    }
}

@compute @workgroup_size(64)
fn splat_hermite(@builtin(global_invocation_id) id: vec3<u32>) {
    let rows = rows_of(id);
    for (var index = rows.x; index < rows.y; index++) {
        let particle = instances[index];
        splat_one(index, particle, interpolated_hermite(particle, velocities[index]));
    }
}

// Additive blending: colours add up, so each covered pixel gets the
// particle's linear, premultiplied colour times its coverage, in fixed point
// (1/1024), summed by atomicAdd into three channels: integer sums are
// exact and independent of order, so frames stay deterministic.
fn splat_one_additive(particle: Instance, position: vec3<f32>) {
    let f = footprint(particle, position);
    let srgb = unpack4x8unorm(particle.colour);
    let colour = srgb_to_linear(srgb.rgb) * srgb.a * 1024.0;
    for (var y = f.low.y; y <= f.high.y; y++) {
        let row = u32(y) * globals.stride;
        for (var x = f.low.x; x <= f.high.x; x++) {
            let c = coverage(f, x, y);
            if c > 0.0 {
                let add = vec3<u32>(round(colour * c));
                let p = 3u * (row + u32(x));
                atomicAdd(&owners[p], add.r);
                atomicAdd(&owners[p + 1u], add.g);
                atomicAdd(&owners[p + 2u], add.b);
            }
        }
    }
}

@compute @workgroup_size(64)
fn splat_additive(@builtin(global_invocation_id) id: vec3<u32>) {
    let rows = rows_of(id);
    for (var index = rows.x; index < rows.y; index++) {
        let particle = instances[index];
        splat_one_additive(particle, interpolated(particle));
    }
}

@compute @workgroup_size(64)
fn splat_additive_hermite(@builtin(global_invocation_id) id: vec3<u32>) {
    let rows = rows_of(id);
    for (var index = rows.x; index < rows.y; index++) {
        let particle = instances[index];
        splat_one_additive(particle, interpolated_hermite(particle, velocities[index]));
    }
}

// Composite of the splat path (see splat.wgsl): each pixel's owner at its
// coverage, over what the frame has drawn so far.
//
// (The splat's own description follows.)
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
    viewport: vec2<f32>,
    pixels_per_unit: f32,
    t: f32,
    min_radius_px: f32,
    count: u32,
    _pad1: f32,
    _pad2: f32,
};

struct Instance {
    previous: vec3<f32>,
    radius: f32,
    current: vec3<f32>,
    colour: u32,
};

@group(0) @binding(0) var<uniform> globals: Globals;
@group(0) @binding(1) var<storage, read> instances: array<Instance>;
@group(0) @binding(2) var<storage, read> owners: array<u32>;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
};

@vertex
fn vs_fullscreen(@builtin(vertex_index) vertex: u32) -> VertexOut {
    // One triangle covering the screen.
    let uv = vec2<f32>(f32((vertex << 1u) & 2u), f32(vertex & 2u));
    var out: VertexOut;
    out.clip = vec4<f32>(uv * 2.0 - 1.0, 1.0, 1.0);
    return out;
}

fn srgb_to_linear(c: vec3<f32>) -> vec3<f32> {
    let low = c / 12.92;
    let high = pow((c + 0.055) / 1.055, vec3<f32>(2.4));
    return select(high, low, c <= vec3<f32>(0.04045));
}

@fragment
fn fs_composite(in: VertexOut) -> @location(0) vec4<f32> {
    let pixel = vec2<u32>(in.clip.xy);
    let key = owners[pixel.y * u32(globals.viewport.x) + pixel.x];
    if key == 0u {
        discard;
    }
    let coverage = f32(key >> 24u) / 255.0;
    let srgb = unpack4x8unorm(instances[key & 0xFFFFFFu].colour);
    let a = srgb.a * coverage;
    return vec4<f32>(srgb_to_linear(srgb.rgb) * a, a);
}

// Additive: the three fixed-point sums (see splat.wgsl), added to the frame.
@fragment
fn fs_composite_additive(in: VertexOut) -> @location(0) vec4<f32> {
    let pixel = vec2<u32>(in.clip.xy);
    let p = 3u * (pixel.y * u32(globals.viewport.x) + pixel.x);
    let sum = vec3<f32>(f32(owners[p]), f32(owners[p + 1u]), f32(owners[p + 2u])) / 1024.0;
    if all(sum == vec3<f32>(0.0)) {
        discard;
    }
    return vec4<f32>(sum, 0.0);
}

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

// ---- Resolve (compute): the final pixels, written into a buffer copied to the target.
//
// A full-screen fragment pass costs a software rasteriser about 10 ms at
// 1280x720 even when it discards everything; a compute pass over the pixels
// and a buffer-to-texture copy cost less. The owners are read here as plain
// words (this module binds them read-only): atomic loads cost a software
// renderer several times more. Used when the target
// accepts copies (off-screen targets; window surfaces that allow it).

@group(0) @binding(3) var<storage, read_write> pixels: array<u32>;

fn linear_to_srgb(c: vec3<f32>) -> vec3<f32> {
    let low = c * 12.92;
    let high = 1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(high, low, c <= vec3<f32>(0.0031308));
}

fn store(x: u32, y: u32, colour: vec4<f32>) {
    let srgb = vec4<f32>(linear_to_srgb(clamp(colour.rgb, vec3<f32>(0.0), vec3<f32>(1.0))), clamp(colour.a, 0.0, 1.0));
    let ordered = select(srgb, srgb.bgra, globals.swap_rb == 1u);
    pixels[y * globals.stride + x] = pack4x8unorm(ordered);
}

// Each invocation resolves a run of RUN pixels of one row: a software
// renderer pays per invocation as much as per pixel.
const RUN: u32 = 16u;

@compute @workgroup_size(64)
fn resolve(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(globals.viewport);
    let runs = (size.x + RUN - 1u) / RUN;
    let y = id.x / runs;
    if y >= size.y {
        return;
    }
    let x0 = (id.x % runs) * RUN;
    for (var x = x0; x < min(x0 + RUN, size.x); x++) {
        let key = owners[y * size.x + x];
        let out = y * globals.stride + x;
        if key == 0u {
            // Most pixels: the background, packed once on the CPU.
            pixels[out] = globals.background_word;
            continue;
        }
        let packed = instances[key & 0xFFFFFFu].colour;
        if (key >> 24u) == 255u && (packed >> 24u) == 255u {
            // Opaque and fully covered: the particle's own sRGB bytes.
            let srgb = unpack4x8unorm(packed);
            pixels[out] = pack4x8unorm(select(srgb, srgb.bgra, globals.swap_rb == 1u));
            continue;
        }
        // Edges and translucent particles: premultiplied "over" the
        // background, in linear light.
        let srgb = unpack4x8unorm(packed);
        let a = srgb.a * f32(key >> 24u) / 255.0;
        let colour = globals.background;
        store(x, y, vec4<f32>(srgb_to_linear(srgb.rgb) * a + colour.rgb * (1.0 - a), a + colour.a * (1.0 - a)));
    }
}

@compute @workgroup_size(64)
fn resolve_additive(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(globals.viewport);
    let runs = (size.x + RUN - 1u) / RUN;
    let y = id.x / runs;
    if y >= size.y {
        return;
    }
    let x0 = (id.x % runs) * RUN;
    for (var x = x0; x < min(x0 + RUN, size.x); x++) {
        let p = 3u * (y * size.x + x);
        let sum = vec3<f32>(f32(owners[p]), f32(owners[p + 1u]), f32(owners[p + 2u]));
        store(x, y, vec4<f32>(globals.background.rgb + sum / 1024.0, globals.background.a));
    }
}

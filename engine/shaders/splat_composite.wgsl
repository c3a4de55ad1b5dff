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
//
// (common.wgsl is prepended: Globals, Instance, sRGB conversions.)

@group(0) @binding(0) var<uniform> globals: Globals;
@group(0) @binding(1) var<storage, read> instances: array<Instance>;
// The splat's owner words (see splat.wgsl), four pixels per element.
@group(0) @binding(2) var<storage, read> owners: array<vec4<u32>>;

fn owner_word(i: u32) -> u32 {
    return owners[i / 4u][i % 4u];
}

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

@fragment
fn fs_composite(in: VertexOut) -> @location(0) vec4<f32> {
    let pixel = vec2<u32>(in.clip.xy);
    let key = owner_word(pixel.y * globals.stride + pixel.x);
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
    let p = 3u * (pixel.y * globals.stride + pixel.x);
    let sum = vec3<f32>(f32(owner_word(p)), f32(owner_word(p + 1u)), f32(owner_word(p + 2u))) / 1024.0;
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

@group(0) @binding(3) var<storage, read_write> pixels: array<vec4<u32>>;

fn encode(colour: vec4<f32>) -> u32 {
    let srgb = vec4<f32>(linear_to_srgb(clamp(colour.rgb, vec3<f32>(0.0), vec3<f32>(1.0))), clamp(colour.a, 0.0, 1.0));
    return pack4x8unorm(select(srgb, srgb.bgra, globals.swap_rb == 1u));
}

// One pixel's final word from its owner key.
fn resolve_key(key: u32) -> u32 {
    if key == 0u {
        // The background, packed once on the CPU.
        return globals.background_word;
    }
    let packed = instances[key & 0xFFFFFFu].colour;
    let srgb = unpack4x8unorm(packed);
    if (key >> 24u) == 255u && (packed >> 24u) == 255u {
        // Opaque and fully covered: the particle's own sRGB bytes.
        return pack4x8unorm(select(srgb, srgb.bgra, globals.swap_rb == 1u));
    }
    // Edges and translucent particles: premultiplied "over" the background,
    // in linear light.
    let a = srgb.a * f32(key >> 24u) / 255.0;
    let b = globals.background;
    return encode(vec4<f32>(srgb_to_linear(srgb.rgb) * a + b.rgb * (1.0 - a), a + b.a * (1.0 - a)));
}

// Rows are `stride` words, a multiple of 64, so element k of a row holds
// pixels 4k..4k+3 of it. Each invocation resolves ELEMENTS elements: a
// software renderer pays microseconds per workgroup, so fewer, longer
// invocations are faster.
const ELEMENTS: u32 = 16u;
@compute @workgroup_size(64)
fn resolve(@builtin(global_invocation_id) id: vec3<u32>) {
    let n = globals.stride / 4u * u32(globals.viewport.y);
    let first = (id.x + id.y * 65535u * 64u) * ELEMENTS;
    for (var i = first; i < min(first + ELEMENTS, n); i++) {
        let keys = owners[i];
        if all(keys == vec4<u32>(0u)) {
            pixels[i] = vec4<u32>(globals.background_word);
        } else {
            pixels[i] = vec4<u32>(resolve_key(keys.x), resolve_key(keys.y), resolve_key(keys.z), resolve_key(keys.w));
        }
    }
}

@compute @workgroup_size(64)
fn resolve_additive(@builtin(global_invocation_id) id: vec3<u32>) {
    let n = globals.stride / 4u * u32(globals.viewport.y);
    let first = (id.x + id.y * 65535u * 64u) * ELEMENTS;
    for (var i = first; i < min(first + ELEMENTS, n); i++) {
        resolve_sums(i);
    }
}

fn resolve_sums(i: u32) {
    // Pixels 4i..4i+3 have their sums in words 12i..12i+11.
    let a = owners[3u * i];
    let b = owners[3u * i + 1u];
    let c = owners[3u * i + 2u];
    let sums = array<vec3<u32>, 4>(a.xyz, vec3<u32>(a.w, b.xy), vec3<u32>(b.zw, c.x), c.yzw);
    var out = vec4<u32>(0u);
    for (var k = 0u; k < 4u; k++) {
        let sum = vec3<f32>(sums[k]) / 1024.0;
        out[k] = encode(vec4<f32>(globals.background.rgb + sum, globals.background.a));
    }
    pixels[i] = out;
}

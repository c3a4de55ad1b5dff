// Particles as anti-aliased discs, interpolated between fixed steps on the GPU.
//
// Each particle is one instance of a four-vertex triangle strip, its record
// read as per-instance vertex attributes (which WebGL2 has, where it has no
// storage buffers): the quad is the disc's bounding square in pixels plus a
// one-pixel margin for the anti-aliased edge, so tiny particles cost a few
// fragments, not a fixed-size sprite's worth.
//
// Two entry points, one per interpolation mode: `vs_main` mixes the 32-byte
// record (lerp), `vs_hermite` also reads the velocity (vertex buffer 1),
// bound only in Hermite mode, so the lerp pipeline and upload have no
// velocities at all.
//
// (common.wgsl is prepended: Globals, Instance, Velocity, the interpolation
// formulas, sRGB conversions.)

@group(0) @binding(0) var<uniform> globals: Globals;

// An `Instance` record as vertex attributes (vertex buffer 0, per instance).
struct InstanceIn {
    @location(0) previous: vec3<f32>,
    @location(1) radius: f32,
    @location(2) current: vec3<f32>,
    @location(3) colour: u32,
};

fn instance(record: InstanceIn) -> Instance {
    return Instance(record.previous, record.radius, record.current, record.colour);
}

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    // Offset from the disc's centre in pixels.
    @location(0) offset_px: vec2<f32>,
    // Radius in pixels (after the minimum) and coverage scale.
    @location(1) @interpolate(flat) radius_scale: vec2<f32>,
    // Linear, premultiplied-ready colour.
    @location(2) @interpolate(flat) colour: vec4<f32>,
};

@vertex
fn vs_main(@builtin(vertex_index) vertex: u32, record: InstanceIn) -> VertexOut {
    let particle = instance(record);
    // x(t) = x_prev + t (x - x_prev): interpolation for t in [0, 1),
    // extrapolation for t in [1, 2).
    return disc(particle, interpolated(particle), vertex);
}

@vertex
fn vs_hermite(
    @builtin(vertex_index) vertex: u32,
    record: InstanceIn,
    // Hermite mode only: the particle's current velocity (vertex buffer 1).
    @location(4) velocity: vec3<f32>,
) -> VertexOut {
    let particle = instance(record);
    return disc(particle, interpolated_hermite(particle, Velocity(velocity.x, velocity.y, velocity.z)), vertex);
}

// Corner `vertex` of the quad around `particle`'s disc drawn at `position`.
fn disc(particle: Instance, position: vec3<f32>, vertex: u32) -> VertexOut {
    let clip = globals.view_proj * vec4<f32>(position, 1.0);
    let w = max(clip.w, 1e-6);
    let radius_px = particle.radius * globals.pixels_per_unit / w;
    let drawn = max(radius_px, globals.min_radius_px);
    let scale = (radius_px * radius_px) / (drawn * drawn);
    // Strip corners (-1,-1), (1,-1), (-1,1), (1,1).
    let corner = vec2<f32>(f32(vertex & 1u), f32(vertex >> 1u)) * 2.0 - 1.0;
    let half_px = drawn + 1.0;
    let offset_px = corner * half_px;
    var out: VertexOut;
    out.clip = vec4<f32>(clip.xy + offset_px * 2.0 / globals.viewport * clip.w, clip.z, clip.w);
    // Behind the camera: collapse the quad.
    if clip.w <= 0.0 {
        out.clip = vec4<f32>(0.0, 0.0, -1.0, 1.0);
    }
    out.offset_px = offset_px;
    out.radius_scale = vec2<f32>(drawn, scale);
    let srgb = unpack4x8unorm(particle.colour);
    out.colour = vec4<f32>(srgb_to_linear(srgb.rgb), srgb.a);
    return out;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    // Signed distance to the edge in pixels; coverage ramps over one pixel.
    let distance = length(in.offset_px) - in.radius_scale.x;
    let coverage = clamp(0.5 - distance, 0.0, 1.0) * in.radius_scale.y;
    if coverage <= 0.0 {
        discard;
    }
    let a = in.colour.a * coverage;
    // Premultiplied: the blend state is (One, OneMinusSrcAlpha) or (One, One).
    return vec4<f32>(in.colour.rgb * a, a);
}

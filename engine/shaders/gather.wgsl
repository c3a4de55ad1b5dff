// A GPU world's particles into the frame's instance records: each
// particle's previous and current position, radius and colour, read from
// the world's own buffers (engine/src/gpu_step) and written after the CPU
// worlds' records, so the quads and the splat draw them as any world's;
// under Hermite interpolation its velocities too, into the velocity
// records (`gather_velocities`, a group of its own). One invocation a
// particle; nothing leaves the GPU.

struct Gather {
    // The first record written, the particles, and the workgroups along x
    // (past 65 535 they fold into y).
    first: u32,
    count: u32,
    groups_x: u32,
    pad: u32,
};

// `Instance` in common.wgsl (32 bytes).
struct Instance {
    previous: vec3<f32>,
    radius: f32,
    current: vec3<f32>,
    colour: u32,
};

@group(0) @binding(0) var<uniform> gather: Gather;
// (x, y, z, radius) a particle, before and after the last step.
@group(0) @binding(1) var<storage, read> previous: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read> current: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read> colours: array<u32>;
@group(0) @binding(4) var<storage, read_write> instances: array<Instance>;

@compute @workgroup_size(64)
fn gather_particles(@builtin(global_invocation_id) id: vec3<u32>) {
    let k = id.x + id.y * gather.groups_x * 64u;
    if (k >= gather.count) {
        return;
    }
    let p = previous[k];
    let c = current[k];
    instances[gather.first + k] = Instance(p.xyz, c.w, c.xyz, colours[k]);
}

// (x, y, z, inverse mass) a particle now, and the renderer's velocity
// records (`Velocity` in hermite.rs: three floats a particle).
@group(1) @binding(0) var<storage, read> velocities: array<vec4<f32>>;
@group(1) @binding(1) var<storage, read_write> records: array<f32>;

@compute @workgroup_size(64)
fn gather_velocities(@builtin(global_invocation_id) id: vec3<u32>) {
    let k = id.x + id.y * gather.groups_x * 64u;
    if (k >= gather.count) {
        return;
    }
    let v = velocities[k];
    let at = 3u * (gather.first + k);
    records[at] = v.x;
    records[at + 1u] = v.y;
    records[at + 2u] = v.z;
}

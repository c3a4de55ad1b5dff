// The fixed step on the GPU: one invocation a particle, the method's
// `advance` (its own file, appended below) then the colliders in their
// order, in place. The bindings and entry points are here; the colliders,
// history and n-body are in colliders.wgsl, history.wgsl and nbody.wgsl,
// concatenated with this file (kernel.rs, `COMMON`).
//
//   a(x, v) = c - b v       the world's affine forces (gravity, wind, linear drag), summed
//                           in force order on the CPU
//             - k |v| v     each quadratic drag, in force order
//             + GM d / (|d|^2 + eps^2)^(3/2), d = p - x     each attractor
//             + G sum_j m_j d_j / (|d_j|^2 + eps^2)^(3/2)    n-body, d_j = x_j - x, both
//                           at the same evaluation (see "n-body" below)
//                           (`acceleration`, written for the world and appended
//                           below); 0 for an immovable particle
//   plane (axis e, sign s, offset o, restitution e_r, friction mu), end of step:
//     gap = s x_e - o - r;  if gap < 0 and w > 0:
//       v_e = s (v_n + dv_n),  dv_n = (v_n >= 0 ? -1 : -(1 + e_r)) * (v_n < 0 ? v_n : 0),  v_n = s v_e
//       x_e = x_e - s gap
//       v_t = v_t * keep,  keep = 0 if (mu dv_n)^2 >= |v_t|^2, else max(1 - mu dv_n / |v_t|, 0)
//                          (the two tangential axes; only with friction)
//   box (min, max), end of step, at rest: a container is six planes facing in,
//     each resolved in turn (x: min then max; then y; then z) by `resolve`, the
//     CPU's general contact (engine/src/colliders/contact.rs); a solid box
//     pushes a particle inside it (grown by r) out through its shallowest face.
//
// The same operations in the same order as the CPU's f32 step
// (engine/src/colliders/plane.rs, contact_block; integrators/src/methods).
//
// n-body: a method's k-th evaluation of a particle needs every particle's
// k-th trial position. Where the world has an n-body force, a step is
// STAGES rounds of `probe` (the method run again with the sums of the
// evaluations before k known, writing each particle's k-th trial position
// and nothing else) and `nbody_sums` (the sums at those positions), then the
// step proper with every sum known. A probe's `STAGE` is a pipeline
// constant; a round whose evaluation no particle reached returns at once.
// Every particle makes the same evaluations in the same order, as the
// CPU's whole-array stages do: a method that starts particles without
// history by RK4 runs those stages for every particle while any starts
// (`some_start`), as the CPU does for a coupled force.

struct Params {
    c: vec3<f32>,
    b: f32,
    dt: f32,
    n: u32,
    // Workgroups along x: a dispatch past 65 535 of them folds into y.
    groups_x: u32,
    colliders: u32,
    // A method's step coefficients, computed on the CPU as the CPU's
    // method computes them (Forest-Ruth's drifts and kicks times h).
    drift: vec4<f32>,
    kick: vec4<f32>,
    // The n-body force's G and softening squared (unused without one).
    nbody_g: f32,
    nbody_eps2: f32,
    // +inf (WGSL has no infinite constant).
    infinity: f32,
    // Room in `touches`: a reporting collider's contact a particle.
    touch_room: u32,
}

// A plane (kind 0: axis, sign, offset; 3 moving along its normal, the
// normal in min) or a box (1 a container, 2 solid: min, max), with its
// material and its velocity (u: a kinematic collider's, zero at rest).
struct Collider {
    kind: u32,
    axis: u32,
    sign: f32,
    offset: f32,
    restitution: f32,
    friction: f32,
    min_x: f32,
    min_y: f32,
    min_z: f32,
    max_x: f32,
    max_y: f32,
    max_z: f32,
    u_x: f32,
    u_y: f32,
    u_z: f32,
    // 1: kinematic (moves); 2: reports its contacts; 4: finds them inside
    // the step (IN_STEP_FLAG, `in_step.wgsl`).
    flags: u32,
}

// A contact of a collider that reports them (the CPU's `diff_touches`,
// or one found inside the step): the collider's index, the particle's row,
// its place among the row's contacts in the step (1, 2, ...; NONE at the
// end of the step) and the fraction of the step it happened at (as bits),
// the point on its surface, the normal and (w) the normal impulse.
struct Touch {
    collider: u32,
    row: u32,
    event: u32,
    fraction: u32,
    point: vec4<f32>,
    normal: vec4<f32>,
}

struct Motion {
    x: vec3<f32>,
    v: vec3<f32>,
}

@group(0) @binding(0) var<uniform> params: Params;
// (x, y, z, radius) and (vx, vy, vz, inverse mass) of each particle.
@group(0) @binding(1) var<storage, read_write> positions: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read_write> velocities: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read> colliders: array<Collider>;
// n-body: the sums of evaluation k at [k n + row] (xyz), k < STAGES, then
// the trial positions of the evaluation being summed at [STAGES n + row].
@group(0) @binding(4) var<storage, read_write> nbody: array<vec4<f32>>;
// The methods that remember: HISTORY records a particle (a constant
// written for the method, from kernel.rs's table; 0: none), the first one's w saying whether the particle
// continues (above 0: Adams-Bashforth's count of steps) or starts afresh
// (0: new, or changed after its step). Velocity Verlet's and leapfrog's
// last end acceleration; position Verlet's position before the step;
// Beeman's a(t) and a(t - h); Adams-Bashforth's past velocities and
// accelerations.
@group(0) @binding(5) var<storage, read_write> history: array<vec4<f32>>;
// flags[0], what this step reads of the last: bit 0 every particle starts
// afresh (the CPU sets it: the first step, a new step length, rows added
// or removed); bit 1 some particle's state was changed after its step (a
// collider, the subnormal flush), which restarts velocity Verlet's and
// leapfrog's cached accelerations for every particle, as the CPU's
// history does. flags[1] collects this step's bit 1 (atomicOr: the same
// word whatever the order); `rotate` moves it into flags[0].
// Bit 2: some particle is short of history after its step (Adams-Bashforth
// in a world with n-body: the next step's RK4 starts run for everyone).
// flags[2] counts the step's contacts in `touches` (atomicAdd: their order
// is the GPU's, the CPU sorts them as it sorts its own).
// flags[3] counts the n-body evaluations whose trial positions this step
// wrote (the last probe's, atomicMax); `rotate` clears it.
@group(0) @binding(6) var<storage, read_write> flags: array<atomic<u32>, 4>;
@group(0) @binding(7) var<storage, read_write> touches: array<Touch>;

// The particle this invocation steps (for `acceleration` to read its
// n-body term).
var<private> row: u32;

@compute @workgroup_size(256)
fn step(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x + id.y * params.groups_x * 256u;
    if (i >= params.n) {
        return;
    }
    row = i;
    call = 0u;
    let p = positions[i];
    let q = velocities[i];
    let stepped = advance(p.xyz, q.xyz, q.w, params.dt);
    var moved = stepped;
    if (IN_STEP) {
        moved = in_step(p.xyz, moved, p.w, q.w);
    }
    moved = resolve_colliders(moved, p.w, q.w);
    if (HISTORY != 0u && (any(moved.x != stepped.x) || any(moved.v != stepped.v))) {
        broke(i);
    }
    positions[i] = vec4<f32>(moved.x, p.w);
    velocities[i] = vec4<f32>(moved.v, q.w);
}

// n-body, evaluation STAGE: the method run as far as that evaluation, to
// write down each particle's trial position there (see "n-body" above).
@compute @workgroup_size(256)
fn probe(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x + id.y * params.groups_x * 256u;
    if (i >= params.n || atomicLoad(&flags[3]) < STAGE) {
        // Out of rows, or the last evaluation was not reached: nor is this.
        return;
    }
    row = i;
    call = 0u;
    let p = positions[i];
    let q = velocities[i];
    _ = advance(p.xyz, q.xyz, q.w, params.dt);
}

// After each step of a method with history or with n-body: its news
// become what the next step reads.
@compute @workgroup_size(1)
fn rotate() {
    atomicStore(&flags[0], atomicLoad(&flags[1]));
    atomicStore(&flags[1], 0u);
    atomicStore(&flags[3], 0u);
}

// Subnormal velocity components become 0 (but -0 stays), as the CPU's
// step does after every 64th tick (`flush_subnormals`): a decaying
// velocity never lingers in the slow subnormal range there, and the GPU
// flushes at the same ticks so that the two stay equal.
@compute @workgroup_size(256)
fn flush(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x + id.y * params.groups_x * 256u;
    if (i >= params.n) {
        return;
    }
    var q = velocities[i];
    var flushed = false;
    for (var k = 0u; k < 3u; k++) {
        if (abs(q[k]) < bitcast<f32>(0x00800000u) && q[k] != 0.0) {
            q[k] = 0.0;
            flushed = true;
        }
    }
    velocities[i] = q;
    if (HISTORY != 0u && flushed) {
        broke(i);
    }
}

// The fixed step on the GPU: one invocation a particle, the method's
// `advance` (its own file, appended below) then the colliders in their
// order, in place.
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

// The n-body evaluation a probe writes the trial positions of; NONE in the
// step proper, which reads every evaluation's sums.
override STAGE: u32 = 4294967295u;
const NONE: u32 = 4294967295u;
// The particle's n-body evaluations so far in this pass.
var<private> call: u32;

// The n-body term of this evaluation at `x`: its sum if known; in the
// probe of this evaluation, `x` is written down for the sums.
fn nbody_term(x: vec3<f32>) -> vec3<f32> {
    let k = call;
    call = call + 1u;
    if (k < STAGE) {
        return nbody[k * params.n + row].xyz;
    }
    if (k == STAGE) {
        nbody[STAGES * params.n + row] = vec4<f32>(x, 0.0);
        atomicMax(&flags[3], STAGE + 1u);
    }
    return vec3<f32>(0.0);
}

// A method's history record `k` becomes `value`, in the step proper only
// (a probe leaves no trace).
fn remember(k: u32, value: vec4<f32>) {
    if (STAGE == NONE) {
        history[k] = value;
    }
}

// Whether some particle starts without history this step (any flag of the
// last step: a new start, a changed particle, one short of history).
fn some_start() -> bool {
    return atomicLoad(&flags[0]) != 0u;
}

// Whether every particle starts afresh this step (bit 0), or the cached
// accelerations restart (any bit: velocity Verlet, leapfrog).
fn all_start() -> bool {
    return (atomicLoad(&flags[0]) & 1u) != 0u;
}

fn accelerations_restart() -> bool {
    return atomicLoad(&flags[0]) != 0u;
}

// Particle `i`'s state was changed after its step: its history ends.
fn broke(i: u32) {
    history[i * HISTORY].w = 0.0;
    atomicOr(&flags[1], 2u);
}

// Classical RK4 from (x0, v0) with the first stage's acceleration `a1`
// given, summed in the CPU's order (integrators/src/methods/rk4.rs); the
// start of position Verlet's particles without history too, as on the CPU.
fn rk4_from(x0: vec3<f32>, v0: vec3<f32>, a1: vec3<f32>, w: f32, h: f32) -> Motion {
    let half = h * 0.5;
    var sx = v0;
    var sv = a1;
    var tx = x0 + v0 * half;
    var tv = v0 + a1 * half;
    // k2 then k3: each summed twice, and the next stage's trial point.
    for (var stage = 0u; stage < 2u; stage++) {
        var offset = half;
        if (stage == 1u) {
            offset = h;
        }
        let kx = tv;
        let kv = acceleration(tx, tv, w);
        sx = sx + kx * 2.0;
        sv = sv + kv * 2.0;
        tx = x0 + kx * offset;
        tv = v0 + kv * offset;
    }
    sx = sx + tv;
    sv = sv + acceleration(tx, tv, w);
    // 1/6 rounded to f32 (0x3e2aaaab), as the CPU's `c(1.0 / 6.0)`.
    let h6 = h * bitcast<f32>(0x3e2aaaabu);
    return Motion(x0 + sx * h6, v0 + sv * h6);
}

// `d`, rounded before it is added to anything: a choice made at run time
// (on `params.infinity`, never negative) that no compiler can fold, so
// that `x + kept(a + b)` is not reassociated into `(x + a) + b`, as
// lavapipe does to an expression WGSL cannot mark exact.
fn kept(d: vec3<f32>) -> vec3<f32> {
    return select(d, vec3<f32>(params.infinity), params.infinity < 0.0);
}

// x^2 + y^2 + z^2 summed as glam's dot product sums it.
fn length_squared(d: vec3<f32>) -> f32 {
    return (d.x * d.x + d.y * d.y) + d.z * d.z;
}

// The CPU's general contact against a surface of normal `n` at `gap`:
// restitution (none for a separating velocity, or one approaching no
// faster than `rest`: 0 but for a collider that finds its contacts inside
// the step) and friction, applied only to a movable particle inside
// (`gap < 0`), in the CPU's operations.
fn resolve(m: ptr<function, Motion>, n: vec3<f32>, gap: f32, movable: bool, c: Collider, rest: f32) {
    let x = (*m).x;
    let v = (*m).v;
    let vn = (v.x * n.x + v.y * n.y) + v.z * n.z;
    let vt = v - n * vn;
    var e = c.restitution;
    if (vn >= -rest) {
        e = 0.0;
    }
    // Rust's `vn.min(0.0)`: -0 stays -0, NaN gives 0.
    let dvn = -(1.0 + e) * select(0.0, vn, vn <= 0.0);
    let speed2 = length_squared(vt);
    let brake = c.friction * dvn;
    var keep = 0.0;
    if (!(brake * brake >= speed2)) {
        keep = max(1.0 - brake / max(sqrt(speed2), bitcast<f32>(0x00800000u)), 0.0);
    }
    if (gap < 0.0 && movable) {
        (*m).v = vt * keep + n * (vn + dvn);
        (*m).x = x - n * gap;
    }
}

// A plane whose normal is an axis (the CPU's `contact_block` and
// `contact_lanes`).
fn resolve_plane(m: ptr<function, Motion>, p: Collider, r: f32, w: f32, rest: f32) {
    var x = (*m).x;
    var v = (*m).v;
    let gap = x[p.axis] * p.sign - p.offset - r;
    let vn = v[p.axis] * p.sign;
    var factor = -(1.0 + p.restitution);
    if (vn >= -rest) {
        factor = -1.0;
    }
    // A select, as the CPU's: -0 and NaN give 0.
    let dvn = factor * select(0.0, vn, vn < 0.0);
    if (gap < 0.0 && w > 0.0) {
        if (p.friction != 0.0) {
            let t1 = (p.axis + 1u) % 3u;
            let t2 = (p.axis + 2u) % 3u;
            let speed2 = v[t1] * v[t1] + v[t2] * v[t2];
            let brake = p.friction * dvn;
            var keep = 0.0;
            if (!(brake * brake >= speed2)) {
                // f32::MIN_POSITIVE: no division by 0.
                let speed = max(sqrt(speed2), bitcast<f32>(0x00800000u));
                keep = max(1.0 - brake / speed, 0.0);
            }
            v[t1] = v[t1] * keep;
            v[t2] = v[t2] * keep;
        }
        v[p.axis] = (vn + dvn) * p.sign;
        x[p.axis] = x[p.axis] - gap * p.sign;
    }
    (*m).x = x;
    (*m).v = v;
}

// A box at rest: a container's six walls, or a solid box's shallowest face
// (`BoxCollider::walls` and `exclude`).
fn resolve_box(m: ptr<function, Motion>, b: Collider, r: f32, w: f32, rest: f32) {
    let lo = vec3<f32>(b.min_x, b.min_y, b.min_z);
    let hi = vec3<f32>(b.max_x, b.max_y, b.max_z);
    let movable = w > 0.0;
    if (b.kind == 1u) {
        for (var axis = 0u; axis < 3u; axis++) {
            var n = vec3<f32>(0.0);
            n[axis] = 1.0;
            resolve(m, n, (*m).x[axis] - lo[axis] - r, movable, b, rest);
            resolve(m, -n, hi[axis] - (*m).x[axis] - r, movable, b, rest);
        }
        return;
    }
    let below = (*m).x - (lo - vec3<f32>(r));
    let above = (hi + vec3<f32>(r)) - (*m).x;
    var best = params.infinity;
    var n = vec3<f32>(0.0);
    for (var axis = 0u; axis < 3u; axis++) {
        if (below[axis] < best) {
            best = below[axis];
            n = vec3<f32>(0.0);
            n[axis] = -1.0;
        }
        if (above[axis] < best) {
            best = above[axis];
            n = vec3<f32>(0.0);
            n[axis] = 1.0;
        }
    }
    let inside = min(min(below.x, below.y), below.z) > 0.0 && min(min(above.x, above.y), above.z) > 0.0;
    if (inside) {
        resolve(m, n, -best, movable, b, rest);
    }
}

// A plane moving along its normal (the CPU's `resolve_range` for a
// moving plane): the general contact at `n . x - offset - r`.
fn resolve_moving_plane(m: ptr<function, Motion>, p: Collider, r: f32, w: f32, rest: f32) {
    let n = vec3<f32>(p.min_x, p.min_y, p.min_z);
    let x = (*m).x;
    let gap = ((n.x * x.x + n.y * x.y) + n.z * x.z - p.offset) - r;
    resolve(m, n, gap, w > 0.0, p, rest);
}

// A reporting collider changed the particle from `before` to `after`:
// its contact, as the CPU's `diff_touches` reads it off the change.
fn report(k: u32, before: Motion, after: Motion, r: f32, w: f32) {
    if (all(bitcast<vec3<u32>>(after.x) == bitcast<vec3<u32>>(before.x))
        && all(bitcast<vec3<u32>>(after.v) == bitcast<vec3<u32>>(before.v))) {
        return;
    }
    let dx = after.x - before.x;
    let dv = after.v - before.v;
    // glam's `try_normalize`: by the reciprocal of the length, if finite
    // and above 0; dx first, then dv, else 0.
    var normal = vec3<f32>(0.0);
    let rx = 1.0 / sqrt(length_squared(dx));
    let rv = 1.0 / sqrt(length_squared(dv));
    if (rx > 0.0 && rx < params.infinity) {
        normal = dx * rx;
    } else if (rv > 0.0 && rv < params.infinity) {
        normal = dv * rv;
    }
    var impulse = 0.0;
    if (w > 0.0) {
        impulse = ((dv.x * normal.x + dv.y * normal.y) + dv.z * normal.z) / w;
    }
    // Found at the end of the step: fraction 1, no event number.
    touch(Touch(k, row, NONE, 0x3f800000u, vec4<f32>(after.x - normal * r, 0.0), vec4<f32>(normal, impulse)));
}

// A contact into the step's touches, if there is room (the CPU counts them
// all: `read_touches` refuses a step that found more than the room).
fn touch(t: Touch) {
    let slot = atomicAdd(&flags[2], 1u);
    if (slot < params.touch_room) {
        touches[slot] = t;
    }
}

fn resolve_colliders(moved: Motion, r: f32, w: f32) -> Motion {
    var m = moved;
    for (var k = 0u; k < params.colliders; k++) {
        let c = colliders[k];
        if (IN_STEP && (c.flags & IN_STEP_FLAG) != 0u) {
            // Resolved inside the step, before the others (`in_step`).
            continue;
        }
        // At rest and silent (the common case): resolved in place. Where no
        // collider of the world moves or reports (KINEMATIC and REPORTING,
        // written for the world), the rest is compiled out: a software
        // rasteriser runs both sides of a branch it cannot prove uniform.
        if ((!KINEMATIC && !REPORTING) || c.flags == 0u) {
            if (c.kind == 0u) {
                resolve_plane(&m, c, r, w, 0.0);
            } else {
                resolve_box(&m, c, r, w, 0.0);
            }
            continue;
        }
        let before = m;
        resolve_collider(&m, c, r, w, 0.0);
        if ((c.flags & 2u) != 0u) {
            report(k, before, m, r, w);
        }
    }
    return m;
}

// One collider's contact, at rest or kinematic.
fn resolve_collider(mm: ptr<function, Motion>, c: Collider, r: f32, w: f32, rest: f32) {
    var m = *mm;
    if ((c.flags & 1u) == 0u) {
        if (c.kind == 0u) {
            resolve_plane(&m, c, r, w, rest);
        } else {
            resolve_box(&m, c, r, w, rest);
        }
        *mm = m;
        return;
    }
    // Kinematic: the contact in the collider's frame, where it is at rest
    // (v - u), and the velocity back in the world's only where the contact
    // changed it, as the CPU does.
    let u = vec3<f32>(c.u_x, c.u_y, c.u_z);
    let before = m.v - u;
    var relative = Motion(m.x, before);
    if (c.kind == 3u) {
        resolve_moving_plane(&relative, c, r, w, rest);
    } else {
        resolve_box(&relative, c, r, w, rest);
    }
    m.x = relative.x;
    if (any(relative.v != before)) {
        m.v = relative.v + u;
    }
    *mm = m;
}

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

// The n-body sums of the tile loaded into workgroup memory: positions and
// masses (1 / w, 0 for an immovable particle).
var<workgroup> tile: array<vec4<f32>, 256>;
// How many evaluations' trial positions the probes wrote (read once for
// the workgroup, so that its barriers stay uniform).
var<workgroup> reached: u32;

// Each particle's n-body acceleration of evaluation STAGE at the trial
// positions the probe wrote: every other particle in row order, 256 at a
// time through workgroup memory, summed as the CPU's `NBody::row` sums
// them (then times G).
@compute @workgroup_size(256)
fn nbody_sums(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    if (lane == 0u) {
        reached = atomicLoad(&flags[3]);
    }
    if (workgroupUniformLoad(&reached) <= STAGE) {
        // No particle made this evaluation in this step.
        return;
    }
    let i = id.x + id.y * params.groups_x * 256u;
    let n = params.n;
    let trials = STAGES * n;
    let xi = nbody[trials + min(i, n - 1u)].xyz;
    var sum = vec3<f32>(0.0);
    for (var base = 0u; base < n; base += 256u) {
        let j = base + lane;
        if (j < n) {
            let w = velocities[j].w;
            tile[lane] = vec4<f32>(nbody[trials + j].xyz, select(0.0, 1.0 / w, w > 0.0));
        }
        workgroupBarrier();
        let count = min(256u, n - base);
        for (var k = 0u; k < count; k++) {
            let d = tile[k].xyz - xi;
            let r2 = length_squared(d) + params.nbody_eps2;
            let m = select(tile[k].w, 0.0, base + k == i);
            if (r2 > 0.0) {
                sum = sum + d * (m / (r2 * sqrt(r2)));
            }
        }
        workgroupBarrier();
    }
    if (i < n) {
        nbody[STAGE * n + i] = vec4<f32>(sum * params.nbody_g, 0.0);
    }
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

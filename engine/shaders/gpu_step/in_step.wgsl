// Contacts inside the step on the GPU, for the colliders that ask for them
// (IN_STEP_FLAG): the CPU's rule (engine/src/step/in_step.rs) in f32.
//
//   q(s) = x0 + b s + a s^2,  b = 2 (x - x0) - v dt,  a = v dt - (x - x0)
//                                 the step's path (the renderer's curve)
//   settled: every in-step collider finds the path certainly clear of it,
//            or resting on it (the CPU's vector tests, lane for lane)
//   else, at the first s where q meets an in-step collider's surface:
//     x_c = q(s), v_c = q'(s) / dt
//     v'  = u + bounce(v_c - u)   e = 0 if the approach <= rest_speed(); on the
//                                 step's first contact, the e that keeps the
//                                 method's own energy (kept_restitution)
//     x = x_c + v' r + a_q r^2 / 2,  v = v' + a_q r,  r = (1 - s) dt, a_q = 2 a / dt^2
//     and the rest of the step again, up to MAX_EVENTS contacts (past them,
//     the particle stays where the last one left it: the end-of-step rule
//     below resolves it, as `EndOfStep` would, and as the CPU's default
//     `ContactOverflow::EndOfStep` does)
//   then each in-step collider's end-of-step rule, approaches no faster
//   than rest_speed() resting
//
// The CPU follows the path in f64; here it is f32, so a GPU world's
// bounces match the CPU's to f32 rounding, not bit for bit. The rest of a
// step after a contact is held as coefficients formed from the way it
// moves (not from its rounded ends), so a short rest magnifies no
// rounding.

const IN_STEP_FLAG: u32 = 4u;

// A path over (the rest of) a step of `dt` seconds.
struct Path {
    start: vec3<f32>,
    b: vec3<f32>,
    a: vec3<f32>,
    dt: f32,
}

fn path_through(x0: vec3<f32>, x1: vec3<f32>, v1: vec3<f32>, dt: f32) -> Path {
    let delta = x1 - x0;
    let vdt = v1 * dt;
    return Path(x0, 2.0 * delta - vdt, vdt - delta, dt);
}

fn path_at(p: Path, s: f32) -> vec3<f32> {
    return p.start + (p.b + p.a * s) * s;
}

fn path_velocity(p: Path, s: f32) -> vec3<f32> {
    return (p.b + 2.0 * p.a * s) / p.dt;
}

fn path_acceleration(p: Path) -> vec3<f32> {
    return 2.0 * p.a / (p.dt * p.dt);
}

fn is_finite(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}

fn is_nan(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7fffffffu) > 0x7f800000u;
}

// The first s in [0, 1] where c + b s + a s^2 falls to zero from c >= 0,
// or -1 (the CPU's `first_root`).
fn first_root(a: f32, b: f32, c: f32) -> f32 {
    if (!(is_finite(a) && is_finite(b) && is_finite(c)) || c < 0.0) {
        return -1.0;
    }
    if (c + b + a >= 0.0) {
        // Clear at both ends: inside in between only for a path that dips
        // with its lowest point inside the step and below zero.
        if (a <= 0.0) {
            return -1.0;
        }
        let lowest = -b / (2.0 * a);
        if (!(lowest >= 0.0 && lowest < 1.0) || c + (b + a * lowest) * lowest >= 0.0) {
            return -1.0;
        }
    }
    var root = 0.0;
    if (a == 0.0) {
        root = -c / b;
    } else {
        // The smaller root without cancellation.
        let d = sqrt(max(b * b - 4.0 * a * c, 0.0));
        let q = -0.5 * (b + select(d, -d, (bitcast<u32>(b) & 0x80000000u) != 0u));
        let r1 = q / a;
        var r2 = 0.0;
        if (q != 0.0) {
            r2 = c / q;
        }
        root = select(min(r1, r2), max(r1, r2), min(r1, r2) < 0.0);
    }
    if (is_nan(root)) {
        return -1.0;
    }
    return clamp(root, 0.0, 1.0);
}

// The first s where the path's gap to the plane n . x = offset (at the
// step's end; moving `travel` along n over the path) less `r` reaches zero
// from above, or -1.
fn first_crossing(p: Path, n: vec3<f32>, offset: f32, travel: f32, r: f32) -> f32 {
    let c = dot(n, p.start) - (offset - travel) - r;
    return first_root(dot(n, p.a), dot(n, p.b) - travel, c);
}

// A contact found along a path: collider k (NONE: none), at fraction s,
// with the surface's normal, offset and velocity.
struct Hit {
    k: u32,
    s: f32,
    n: vec3<f32>,
    offset: f32,
    u: vec3<f32>,
}

fn no_hit() -> Hit {
    return Hit(NONE, 2.0, vec3<f32>(0.0), 0.0, vec3<f32>(0.0));
}

// Collider k's first contact along `p` (the CPU's `first_contact`).
fn first_contact(k: u32, c: Collider, p: Path, r: f32) -> Hit {
    let u = vec3<f32>(c.u_x, c.u_y, c.u_z);
    // IN_STEP_BOXES (written for the world): without in-step boxes their
    // code is compiled out (a software rasteriser runs it under a mask).
    if (!IN_STEP_BOXES || c.kind == 0u || c.kind == 3u) {
        var n = vec3<f32>(0.0);
        n[c.axis] = c.sign;
        let travel = dot(n, u) * p.dt;
        let s = first_crossing(p, n, c.offset, travel, r);
        if (s < 0.0) {
            return no_hit();
        }
        return Hit(k, s, n, c.offset, u);
    }
    // A box: each face a plane moving with it; a container's faces face
    // in, a solid box's out (a crossing counts where the path is then
    // within the face, the box grown by r).
    let lo = vec3<f32>(c.min_x, c.min_y, c.min_z);
    let hi = vec3<f32>(c.max_x, c.max_y, c.max_z);
    let inside = c.kind == 1u;
    var best = no_hit();
    for (var face = 0u; face < 6u; face++) {
        let axis = face / 2u;
        let outward = select(-1.0, 1.0, face % 2u == 1u);
        var n = vec3<f32>(0.0);
        n[axis] = select(outward, -outward, inside);
        let offset = n[axis] * select(lo[axis], hi[axis], outward > 0.0);
        let s = first_crossing(p, n, offset, dot(n, u) * p.dt, r);
        if (s < 0.0 || best.s <= s) {
            continue;
        }
        if (!inside) {
            let at = path_at(p, s) + u * (p.dt * (1.0 - s));
            var within = true;
            for (var b = 0u; b < 3u; b++) {
                if (b != axis && !(at[b] >= lo[b] - r && at[b] <= hi[b] + r)) {
                    within = false;
                }
            }
            if (!within) {
                continue;
            }
        }
        best = Hit(k, s, n, offset, u);
    }
    return best;
}

// The first contact along `p` among the in-step colliders but `skip` (the
// lower index on a tie).
fn first_hit(p: Path, r: f32, skip: u32) -> Hit {
    var best = no_hit();
    for (var k = 0u; k < params.colliders; k++) {
        let c = colliders[k];
        if ((c.flags & IN_STEP_FLAG) == 0u || k == skip) {
            continue;
        }
        let hit = first_contact(k, c, p, r);
        if (hit.k != NONE && hit.s < best.s) {
            best = hit;
        }
    }
    return best;
}

// The response to a contact on the velocity relative to the surface (the
// CPU's `bounce`).
fn bounce(v: vec3<f32>, n: vec3<f32>, e: f32, mu: f32) -> vec3<f32> {
    let vn = dot(v, n);
    let vt = v - n * vn;
    let dvn = -(1.0 + e) * min(vn, 0.0);
    let speed2 = dot(vt, vt);
    let brake = mu * dvn;
    var keep = 0.0;
    if (!(brake * brake >= speed2)) {
        keep = max(1.0 - brake / max(sqrt(speed2), bitcast<f32>(0x00800000u)), 0.0);
    }
    return vt * keep + n * (vn + dvn);
}

// The restitution that scales the method's own energy by e^2 where the
// path leaves out part of the acceleration into the surface (the CPU's
// `kept_restitution`, which derives it); negative: no bounce keeps it.
fn kept_restitution(e: f32, u: f32, forces: vec3<f32>, missing: vec3<f32>, n: vec3<f32>, s: f32, dt: f32) -> f32 {
    let into = max(-dot(forces, n), 0.0);
    let g = min(max(dot(missing, n), 0.0), into);
    var k = 0.0;
    if (!(g < 0.01 * into)) {
        k = g * dt * (0.5 - s);
    }
    if (k == 0.0 || e == 0.0) {
        return e;
    }
    // No real root (a restitution above 1 can ask for one; WGSL's sqrt
    // of a negative is not NaN): no bounce keeps the energy.
    let d = k * k + e * e * (u * u - 2.0 * k * u);
    if (!(d >= 0.0)) {
        return -1.0;
    }
    let w = -k + sqrt(d);
    if (w > 0.0) {
        return w / u;
    }
    return -1.0;
}

// The particle's contacts along its path (the CPU's `Sweep::row`):
// `(*m)` is the method's end state, changed in place.
fn follow(m: ptr<function, Motion>, x0: vec3<f32>, r: f32, w: f32, settled: bool) {
    let dt = params.dt;
    var p = path_through(x0, (*m).x, (*m).v, dt);
    var done = 0.0;
    var events = 0u;
    var resting_on = NONE;
    // Settled, or immovable: no contact is looked for.
    var going = !settled && w > 0.0;
    loop {
        if (!going) {
            break;
        }
        let hit = first_hit(p, r, resting_on);
        if (hit.k == NONE) {
            break;
        }
        events += 1u;
        if (events > MAX_EVENTS) {
            break;
        }
        let c = colliders[hit.k];
        let s = hit.s;
        let at = path_at(p, s);
        let arriving = path_velocity(p, s);
        let relative = arriving - hit.u;
        let approach = -dot(relative, hit.n);
        let resting = approach <= rest_speed();
        var e = c.restitution;
        let a = path_acceleration(p);
        if (resting) {
            e = 0.0;
        } else if (events == 1u) {
            let forces = params.c - arriving * params.b;
            e = max(kept_restitution(e, approach, forces, a - forces, hit.n, s, p.dt), 0.0);
        }
        let after = hit.u + bounce(relative, hit.n, e, c.friction);
        let fraction = done + s * (1.0 - done);
        if ((c.flags & 2u) != 0u) {
            let impulse = dot(after - arriving, hit.n) / w;
            touch(Touch(hit.k, row, events, bitcast<u32>(fraction), vec4<f32>(at - hit.n * r, 0.0), vec4<f32>(hit.n, impulse)));
        }
        // The rest of the step, from the contact, on the path's own
        // acceleration; `moved`, the way from the contact to its end, is
        // kept apart from the positions so that the next path's
        // coefficients are not the difference of two rounded ends.
        let rest = (1.0 - fraction) * dt;
        var moved = vec3<f32>(0.0);
        var velocity = after;
        if (rest > 0.0) {
            moved = after * rest + a * (rest * rest * 0.5);
            velocity = after + a * rest;
        }
        var end = at + moved;
        if (resting) {
            // On the surface, with nothing left going into it.
            let gap = dot(hit.n, end) - hit.offset - r;
            if (gap < 0.0) {
                end = end - hit.n * gap;
                moved = moved - hit.n * gap;
            }
            let into = dot(velocity - hit.u, hit.n);
            if (into < 0.0) {
                velocity = velocity - hit.n * into;
            }
        }
        (*m).x = end;
        (*m).v = velocity;
        if (!(rest > 0.0)) {
            break;
        }
        if (resting) {
            // Through the surface point it ends at, with its velocity
            // (`path_through` from `moved` rather than from the ends).
            resting_on = hit.k;
            let vdt = velocity * rest;
            p = Path(at, 2.0 * moved - vdt, vdt - moved, rest);
        } else {
            p = Path(at, after * rest, a * (rest * rest * 0.5), rest);
        }
        done = fraction;
    }
}

// The CPU's `clear_axis_lanes` on one lane: the path certainly clear of
// the plane (offset, moving `travel`) along one axis all along the step.
fn clear_axis(d0: f32, d1: f32, dv: f32, r: f32, offset: f32, travel: f32) -> bool {
    let g0 = d0 - (offset - travel) - r;
    let g1 = d1 - offset - r;
    let a = dv - (d1 - d0);
    let bound = min(g0, g1) - max(a, 0.0) * 0.25;
    let fixed = (abs(offset) + abs(travel)) * 1e-6 + bitcast<f32>(0x00800000u);
    let margin = (((abs(d0) + abs(d1)) + abs(dv)) + r) * 1e-6 + fixed;
    return bound > margin;
}

// The CPU's `resting4` on one lane: the path's speed into the surface at
// most rest_dt / dt at both ends.
fn resting(d0: f32, d1: f32, dv: f32, travel: f32, rest_dt: f32) -> bool {
    let start = travel - ((d1 - d0) * 2.0 - dv);
    let end = travel - dv;
    return start <= rest_dt && end <= rest_dt;
}

// A box's face k (axis k / 2; the max face where k is odd) as a path sees
// it: its plane's offset and travel along the face's normal, and the
// path's start, end and dt times end velocity along it.
struct Face {
    axis: u32,
    max: bool,
    offset: f32,
    travel: f32,
    d0: f32,
    d1: f32,
    dv: f32,
}

fn face_of(b: Collider, k: u32, x0: vec3<f32>, x1: vec3<f32>, v1: vec3<f32>, dt: f32) -> Face {
    let axis = k / 2u;
    let max_face = k % 2u == 1u;
    let outward = select(-1.0, 1.0, max_face);
    let sign = select(outward, -outward, b.kind == 1u);
    let lo = vec3<f32>(b.min_x, b.min_y, b.min_z);
    let hi = vec3<f32>(b.max_x, b.max_y, b.max_z);
    let u = vec3<f32>(b.u_x, b.u_y, b.u_z);
    let plane = select(lo[axis], hi[axis], max_face);
    return Face(axis, max_face, sign * plane, sign * u[axis] * dt, x0[axis] * sign, x1[axis] * sign, v1[axis] * (sign * dt));
}

// The CPU's `resting_on_face` on one lane: resting on this face of a solid
// box at rest, in its half of the box, within the other two axes' grown
// slabs all along, and no deeper through it at the end than through any
// other face.
fn resting_on_face(b: Collider, f: Face, x0: vec3<f32>, x1: vec3<f32>, v1: vec3<f32>, r: f32, dt: f32, rest_dt: f32) -> bool {
    let lo3 = vec3<f32>(b.min_x, b.min_y, b.min_z);
    let hi3 = vec3<f32>(b.max_x, b.max_y, b.max_z);
    let half = f.offset - (hi3[f.axis] - lo3[f.axis]) * 0.5;
    let bend = f.dv - (f.d1 - f.d0);
    let lowest = min(f.d0, f.d1) - max(bend, 0.0) * 0.25;
    if (!(resting(f.d0, f.d1, f.dv, 0.0, rest_dt) && lowest > half)) {
        return false;
    }
    let depth = (f.offset + r) - f.d1;
    let lo = lo3[f.axis] - r;
    let hi = hi3[f.axis] + r;
    let end = x1[f.axis];
    let opposite = select(hi - end, end - lo, f.max);
    var lane = opposite > depth;
    for (var k = 0u; k < 3u; k++) {
        if (k == f.axis) {
            continue;
        }
        let l = lo3[k] - r;
        let h = hi3[k] + r;
        let e0 = x0[k];
        let e1 = x1[k];
        let bend_k = v1[k] * dt - (e1 - e0);
        lane = lane && (min(e0, e1) - max(bend_k, 0.0) * 0.25) > l
            && (max(e0, e1) - min(bend_k, 0.0) * 0.25) < h
            && (e1 - l) > depth
            && (h - e1) > depth;
    }
    return lane;
}

// Whether in-step collider c settles the particle (the CPU's
// `settle_blocks`, one lane): certainly clear of it, or resting on it.
fn settles(c: Collider, x0: vec3<f32>, x1: vec3<f32>, v1: vec3<f32>, r: f32, dt: f32, rest_dt: f32) -> bool {
    let u = vec3<f32>(c.u_x, c.u_y, c.u_z);
    if (!IN_STEP_BOXES || c.kind == 0u || c.kind == 3u) {
        let d0 = x0[c.axis] * c.sign;
        let d1 = x1[c.axis] * c.sign;
        let dv = (v1[c.axis] * c.sign) * dt;
        // The plane's speed along its normal (u = n speed).
        let travel = (u[c.axis] * c.sign) * dt;
        return clear_axis(d0, d1, dv, r, c.offset, travel) || resting(d0, d1, dv, travel, rest_dt);
    }
    let at_rest = all(u == vec3<f32>(0.0));
    if (c.kind == 1u) {
        // A container: every wall clear, or rested on.
        for (var k = 0u; k < 6u; k++) {
            let f = face_of(c, k, x0, x1, v1, dt);
            let clear = clear_axis(f.d0, f.d1, f.dv, r, f.offset, f.travel);
            if (!(clear || (at_rest && resting(f.d0, f.d1, f.dv, 0.0, rest_dt)))) {
                return false;
            }
        }
        return true;
    }
    // A solid box: some face clear, or rested on.
    for (var k = 0u; k < 6u; k++) {
        let f = face_of(c, k, x0, x1, v1, dt);
        if (clear_axis(f.d0, f.d1, f.dv, r, f.offset, f.travel)) {
            return true;
        }
        if (at_rest && resting_on_face(c, f, x0, x1, v1, r, dt, rest_dt)) {
            return true;
        }
    }
    return false;
}

// The in-step colliders' contacts of a particle that stepped from x0 to
// `moved`: followed along its path unless settled, then each in-step
// collider's end-of-step rule (reported where the collider reports).
fn in_step(x0: vec3<f32>, moved: Motion, r: f32, w: f32) -> Motion {
    var m = moved;
    let dt = params.dt;
    let rest_dt = rest_speed() * dt;
    var settled = true;
    for (var k = 0u; k < params.colliders; k++) {
        let c = colliders[k];
        if ((c.flags & IN_STEP_FLAG) != 0u && !settles(c, x0, m.x, m.v, r, dt, rest_dt)) {
            settled = false;
            break;
        }
    }
    follow(&m, x0, r, w, settled);
    for (var k = 0u; k < params.colliders; k++) {
        let c = colliders[k];
        if ((c.flags & IN_STEP_FLAG) == 0u) {
            continue;
        }
        // At rest and silent: resolved in place, the rest compiled out
        // where nothing moves or reports (as in `resolve_colliders`).
        if ((!KINEMATIC && !REPORTING) || c.flags == IN_STEP_FLAG) {
            if (!IN_STEP_BOXES || c.kind == 0u) {
                resolve_plane(&m, c, r, w, rest_speed());
            } else {
                resolve_box(&m, c, r, w, rest_speed());
            }
            continue;
        }
        let before = m;
        resolve_collider(&m, c, r, w, rest_speed());
        if ((c.flags & 2u) != 0u) {
            report(k, before, m, r, w);
        }
    }
    return m;
}

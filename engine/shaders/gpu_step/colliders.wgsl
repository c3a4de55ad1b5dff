// The colliders' end-of-step rule on the GPU, particle by particle: the
// CPU's general contact, planes along an axis, boxes, moving planes, and
// the contacts of colliders that report them.

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

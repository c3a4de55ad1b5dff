// The methods that remember (`history` in step.wgsl): what a step reads
// of the last, and RK4 for the particles that start without history.

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

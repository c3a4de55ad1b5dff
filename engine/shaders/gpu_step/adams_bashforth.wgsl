// Adams-Bashforth of LAGS + 1 steps (2, 3 or 4: HISTORY = 2 LAGS records
// a particle, written for the method), the derivatives of the last LAGS
// steps kept (history: the past velocities, then the past accelerations,
// lag 1 first; the first record's w counts the steps of history):
//
//   x(t + h) = x + sum_j beta_j v(t - j h)
//   v(t + h) = v + sum_j beta_j a(t - j h),     j = 0 .. LAGS,  beta_j = h b_j
//
// beta_j comes computed in `params.drift` (b_j h in f64, rounded, as the
// CPU forms them). A particle with fewer than LAGS steps of history takes
// an RK4 step from a(t) instead, as on the CPU
// (integrators/src/methods/adams_bashforth.rs); with n-body, every
// particle runs those stages while any starts.

const LAGS: u32 = HISTORY / 2u;

fn advance(x0: vec3<f32>, v0: vec3<f32>, w: f32, h: f32) -> Motion {
    let base = row * HISTORY;
    let a_now = acceleration(x0, v0, w);
    var depth = history[base].w;
    if (all_start()) {
        depth = 0.0;
    }
    var m: Motion;
    if (depth < f32(LAGS) || (COUPLED && some_start())) {
        m = rk4_from(x0, v0, a_now, w, h);
    }
    if (depth >= f32(LAGS)) {
        var dx = v0 * params.drift[0];
        var dv = a_now * params.drift[0];
        for (var lag = 1u; lag <= LAGS; lag++) {
            dx = kept(dx) + history[base + lag - 1u].xyz * params.drift[lag];
            dv = kept(dv) + history[base + LAGS + lag - 1u].xyz * params.drift[lag];
        }
        m = Motion(x0 + kept(dx), v0 + kept(dv));
    }
    // The lags move one older; now's derivatives become lag 1.
    for (var j = LAGS - 1u; j > 0u; j--) {
        remember(base + j, history[base + j - 1u]);
        remember(base + LAGS + j, history[base + LAGS + j - 1u]);
    }
    remember(base, vec4<f32>(v0, min(depth + 1.0, 255.0)));
    remember(base + LAGS, vec4<f32>(a_now, 0.0));
    if (COUPLED && STAGE == NONE && depth + 1.0 < f32(LAGS)) {
        // Short of history still: the next step's starts run for everyone.
        atomicOr(&flags[1], 4u);
    }
    return m;
}

// Beeman's algorithm, predictor-corrector form, a(t) and a(t - h) kept
// (history: two records a particle):
//
//   x(t + h) = x + (h v + h^2/6 (4 a(t) - a(t - h)))
//   v~       = v + h/2 (3 a(t) - a(t - h))                (predicted, Adams-Bashforth 2)
//   a(t + h) = a(t + h, x(t + h), v~)
//   v(t + h) = v + h/6 (2 a(t + h) + 5 a(t) - a(t - h))   (corrected, Adams-Moulton 3)
//
// A particle without history starts by one RK4 step from a(t), which then
// becomes its a(t - h), as on the CPU (integrators/src/methods/beeman.rs);
// with n-body, every particle runs those stages while any starts.

fn advance(x0: vec3<f32>, v0: vec3<f32>, w: f32, h: f32) -> Motion {
    let base = row * HISTORY;
    let a = history[base].xyz;
    let ap = history[base + 1u].xyz;
    let continues = history[base].w != 0.0 && !all_start();
    // 1/6 rounded to f32, as the CPU's `c(1.0 / 6.0)`.
    let sixth = bitcast<f32>(0x3e2aaaabu);
    var x: vec3<f32>;
    var predicted: vec3<f32>;
    var kept_a = a;
    if (!continues || (COUPLED && some_start())) {
        let start = acceleration(x0, v0, w);
        let m = rk4_from(x0, v0, start, w, h);
        x = m.x;
        predicted = m.v;
        kept_a = start;
    }
    if (continues) {
        x = x0 + kept(v0 * h + (a * 4.0 - ap) * (h * h * sixth));
        predicted = v0 + (a * 3.0 - ap) * (h * 0.5);
        kept_a = a;
    }
    let end = acceleration(x, predicted, w);
    var v = predicted;
    if (continues) {
        v = v0 + (kept(end * 2.0 + a * 5.0) - ap) * (h * sixth);
    }
    // (a(t - h), a(t)) <- (a(t), a(t + h)).
    remember(base, vec4<f32>(end, 1.0));
    remember(base + 1u, vec4<f32>(kept_a, 0.0));
    return Motion(x, v);
}

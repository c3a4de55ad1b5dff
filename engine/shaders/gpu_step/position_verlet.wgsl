// Position (Stormer) Verlet, the position before the step kept (history):
//
//   x(t + h) = 2 x(t) - x(t - h) + h^2 a(t, x(t), v(t))
//   v(t + h) = (x(t + h) - x(t)) / h            (estimate, for drag and rendering)
//
// A particle without x(t - h) (new, changed after its last step, or all
// of them after a new step length) starts by one RK4 step from the same
// a(t), as on the CPU (integrators/src/methods/position_verlet.rs); with
// n-body, every particle runs those stages while any starts.

fn advance(x0: vec3<f32>, v0: vec3<f32>, w: f32, h: f32) -> Motion {
    let a = acceleration(x0, v0, w);
    let last = history[row];
    remember(row, vec4<f32>(x0, 1.0));
    let continues = last.w != 0.0 && !all_start();
    var m: Motion;
    if (!continues || (COUPLED && some_start())) {
        m = rk4_from(x0, v0, a, w, h);
    }
    if (continues) {
        let x = x0 * 2.0 - last.xyz + a * (h * h);
        m = Motion(x, (x - x0) * (1.0 / h));
    }
    return m;
}

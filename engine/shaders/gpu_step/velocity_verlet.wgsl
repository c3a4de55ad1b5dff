// Velocity Verlet, the end acceleration kept for the next step's start:
//
//   x(t + h) = x + (h v + h^2/2 a(t))
//   v~       = v + h a(t)                          (predicted end velocity, for drag)
//   a(t + h) = a(t + h, x(t + h), v~)
//   v(t + h) = v + h/2 (a(t) + a(t + h))
//
// a(t) is the last step's a(t + h) (history), evaluated afresh for every
// particle when any restarts (the CPU's rule, integrators/src/methods/velocity_verlet.rs).

fn advance(x0: vec3<f32>, v0: vec3<f32>, w: f32, h: f32) -> Motion {
    var a0 = history[row].xyz;
    if (accelerations_restart()) {
        a0 = acceleration(x0, v0, w);
    }
    let half = h * 0.5;
    let half_h2 = h * h * 0.5;
    let x = x0 + kept(v0 * h + a0 * half_h2);
    let predicted = v0 + a0 * h;
    let a1 = acceleration(x, predicted, w);
    remember(row, vec4<f32>(a1, 0.0));
    return Motion(x, v0 + (a0 + a1) * half);
}


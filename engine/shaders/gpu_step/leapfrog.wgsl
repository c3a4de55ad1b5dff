// Leapfrog, kick-drift-kick, the closing kick's acceleration kept as the
// next step's opening one:
//
//   v(t + h/2) = v(t) + h/2 a(t)                                   kick
//   x(t + h)   = x(t) + h v(t + h/2)                               drift
//   v(t + h)   = v(t + h/2) + h/2 a(t + h, x(t + h), v(t + h/2))   kick
//
// a(t) is the last step's closing acceleration (history), evaluated
// afresh for every particle when any restarts (the CPU's rule,
// integrators/src/methods/leapfrog.rs).

fn advance(x0: vec3<f32>, v0: vec3<f32>, w: f32, h: f32) -> Motion {
    var a0 = history[row].xyz;
    if (accelerations_restart()) {
        a0 = acceleration(x0, v0, w);
    }
    let half = h * 0.5;
    let kicked = v0 + a0 * half;
    let x = x0 + kicked * h;
    let a1 = acceleration(x, kicked, w);
    remember(row, vec4<f32>(a1, 0.0));
    return Motion(x, kicked + a1 * half);
}

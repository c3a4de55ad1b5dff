// Explicit (forward) Euler: both updates from the state at the start.
//
//   v(t + h) = v(t) + h a(t, x, v)
//   x(t + h) = x(t) + h v(t)

fn advance(x0: vec3<f32>, v0: vec3<f32>, w: f32, h: f32) -> Motion {
    let v = v0 + acceleration(x0, v0, w) * h;
    return Motion(x0 + v0 * h, v);
}

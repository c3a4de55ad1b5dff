// Improved Euler (Heun's method): tangents at both ends, averaged.
//
//   v1 = v + h a(t, x, v)
//   v2 = v + h a(t + h, x + h v, v1)
//   v(t + h) = (v1 + v2) / 2
//   x(t + h) = x + h (v + v1) / 2

fn advance(x0: vec3<f32>, v0: vec3<f32>, w: f32, h: f32) -> Motion {
    let half = h * 0.5;
    let a0 = acceleration(x0, v0, w);
    let end = x0 + v0 * h;
    let v1 = v0 + a0 * h;
    let v2 = v0 + acceleration(end, v1, w) * h;
    return Motion(x0 + (v0 + v1) * half, (v1 + v2) * 0.5);
}

// Semi-implicit (symplectic) Euler: the velocity first, then the position
// with the new velocity.
//
//   v(t + h) = v(t) + h a(t, x, v)
//   x(t + h) = x(t) + h v(t + h)

fn advance(x0: vec3<f32>, v0: vec3<f32>, w: f32, h: f32) -> Motion {
    let v = v0 + acceleration(x0, v0, w) * h;
    return Motion(x0 + v * h, v);
}

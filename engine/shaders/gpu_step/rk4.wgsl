// Classical fourth-order Runge-Kutta on y = (x, v), y' = (v, a(t, x, v)):
//
//   k1 = (v,            a(t,       x,            v))
//   k2 = (v + h/2 k1v,  a(t + h/2, x + h/2 k1x,  v + h/2 k1v))
//   k3 = (v + h/2 k2v,  a(t + h/2, x + h/2 k2x,  v + h/2 k2v))
//   k4 = (v + h k3v,    a(t + h,   x + h k3x,    v + h k3v))
//   y(t + h) = y + h/6 (k1 + 2 k2 + 2 k3 + k4)
//
// Summed in the CPU's order (`rk4_from` in step.wgsl).

fn advance(x0: vec3<f32>, v0: vec3<f32>, w: f32, h: f32) -> Motion {
    return rk4_from(x0, v0, acceleration(x0, v0, w), w, h);
}

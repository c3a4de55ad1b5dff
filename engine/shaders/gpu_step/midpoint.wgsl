// The explicit midpoint method: the tangent at mid-interval, applied from
// the start across the whole step.
//
//   x_m = x + h/2 v,   v_m = v + h/2 a(t, x, v)
//   x(t + h) = x + h v_m
//   v(t + h) = v + h a(t + h/2, x_m, v_m)

fn advance(x0: vec3<f32>, v0: vec3<f32>, w: f32, h: f32) -> Motion {
    let half = h * 0.5;
    let a0 = acceleration(x0, v0, w);
    let xm = x0 + v0 * half;
    let vm = v0 + a0 * half;
    let am = acceleration(xm, vm, w);
    return Motion(x0 + vm * h, v0 + am * h);
}

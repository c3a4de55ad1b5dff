// Classical fourth-order Runge-Kutta on y = (x, v), y' = (v, a(t, x, v)):
//
//   k1 = (v,            a(t,       x,            v))
//   k2 = (v + h/2 k1v,  a(t + h/2, x + h/2 k1x,  v + h/2 k1v))
//   k3 = (v + h/2 k2v,  a(t + h/2, x + h/2 k2x,  v + h/2 k2v))
//   k4 = (v + h k3v,    a(t + h,   x + h k3x,    v + h k3v))
//   y(t + h) = y + h/6 (k1 + 2 k2 + 2 k3 + k4)
//
// Summed in the CPU's order (integrators/src/methods/rk4.rs).

fn advance(x0: vec3<f32>, v0: vec3<f32>, w: f32, h: f32) -> Motion {
    let half = h * 0.5;
    let a1 = acceleration(x0, v0, w);
    var sx = v0;
    var sv = a1;
    var tx = x0 + v0 * half;
    var tv = v0 + a1 * half;
    // k2 then k3: each summed twice, and the next stage's trial point.
    for (var stage = 0u; stage < 2u; stage++) {
        var offset = half;
        if (stage == 1u) {
            offset = h;
        }
        let kx = tv;
        let kv = acceleration(tx, tv, w);
        sx = sx + kx * 2.0;
        sv = sv + kv * 2.0;
        tx = x0 + kx * offset;
        tv = v0 + kv * offset;
    }
    sx = sx + tv;
    sv = sv + acceleration(tx, tv, w);
    // 1/6 rounded to f32 (0x3e2aaaab), as the CPU's `c(1.0 / 6.0)`.
    let h6 = h * bitcast<f32>(0x3e2aaaabu);
    return Motion(x0 + sx * h6, v0 + sv * h6);
}

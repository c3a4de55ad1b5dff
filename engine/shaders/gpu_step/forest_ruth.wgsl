// Forest-Ruth: a fourth-order symplectic method, three position-Verlet
// steps of sizes theta h, (1 - 2 theta) h, theta h (Yoshida's triple jump):
//
//   theta = 1 / (2 - 2^(1/3))
//   x += theta h/2 v;        v += theta h a(x, v)
//   x += (1 - theta) h/2 v;  v += (1 - 2 theta) h a(x, v)
//   x += (1 - theta) h/2 v;  v += theta h a(x, v)
//   x += theta h/2 v
//
// The products of the weights and h come in `params.drift` and
// `params.kick`, rounded to f32 from f64 as the CPU's method rounds them.

fn advance(x0: vec3<f32>, v0: vec3<f32>, w: f32, h: f32) -> Motion {
    var x = x0;
    var v = v0;
    for (var stage = 0u; stage < 4u; stage++) {
        x = x + v * params.drift[stage];
        if (stage < 3u) {
            v = v + acceleration(x, v, w) * params.kick[stage];
        }
    }
    return Motion(x, v);
}

//! Test problems with known solutions, shared by the accuracy tests.
#![allow(dead_code)]

use tickwork_integrators::{Integrator, System};

/// `x'' = -k/m x - b/m v`, one particle in one dimension (m = 1).
#[derive(Clone, Copy, Debug)]
pub struct Oscillator {
    /// Spring stiffness.
    pub k: f64,
    /// Linear drag coefficient.
    pub b: f64,
}

impl System<f64> for Oscillator {
    fn acceleration(&mut self, _t: f64, x: &[f64], v: &[f64], out: &mut [f64]) {
        for i in 0..x.len() {
            out[i] = -self.k * x[i] - self.b * v[i];
        }
    }
    fn linear_drag(&self) -> f64 {
        self.b
    }
}

impl Oscillator {
    /// Exact (x, v) at time t from (x0, v0), underdamped.
    pub fn exact(&self, x0: f64, v0: f64, t: f64) -> (f64, f64) {
        let zeta = self.b / 2.0;
        let omega = (self.k - zeta * zeta).sqrt();
        let decay = (-zeta * t).exp();
        // x = e^{-zeta t} (A cos(w t) + B sin(w t)), A = x0, B = (v0 + zeta x0) / w
        let (a, b) = (x0, (v0 + zeta * x0) / omega);
        let (s, c) = (omega * t).sin_cos();
        let x = decay * (a * c + b * s);
        let v = decay * ((b * omega - zeta * a) * c - (a * omega + zeta * b) * s);
        (x, v)
    }
}

/// Runs `method` from `(x0, v0)` for `steps` steps of `dt`.
pub fn run(
    method: &mut dyn Integrator<f64>,
    system: &mut dyn System<f64>,
    x0: f64,
    v0: f64,
    dt: f64,
    steps: usize,
) -> (f64, f64) {
    let (mut x, mut v) = (vec![x0], vec![v0]);
    for n in 0..steps {
        method.step(n as f64 * dt, dt, &mut x, &mut v, system).expect("step");
    }
    (x[0], v[0])
}

/// Least-squares slope of log(error) against log(dt).
pub fn slope(dts: &[f64], errors: &[f64]) -> f64 {
    let xs: Vec<f64> = dts.iter().map(|d| d.ln()).collect();
    let ys: Vec<f64> = errors.iter().map(|e| e.ln()).collect();
    let n = xs.len() as f64;
    let mx = xs.iter().sum::<f64>() / n;
    let my = ys.iter().sum::<f64>() / n;
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

//! Long-run behaviour against theory: energy on the Kepler orbit, time
//! reversibility, and stability under stiff drag.
// Reference values and set-ups computed natively (never in a page): the
// platform's own functions are fine here (clippy.toml bans them in the engine).
#![allow(clippy::disallowed_methods)]

use crate::common;

use common::{Kepler, Oscillator};
use glam::DVec2;
use tickwork_integrators::{Integrator, METHODS, build};

/// Relative energy error every step of a Kepler run (e = 0.5, dt = 0.01, t = 1000).
fn kepler_energy_errors(name: &str) -> Vec<f64> {
    let mut method = build::<DVec2>(name).expect("registered");
    let (q0, p0) = Kepler::start(0.5);
    let e0 = Kepler::energy(q0, p0);
    let (mut q, mut p) = (vec![q0], vec![p0]);
    let dt = 0.01;
    (0..100_000)
        .map(|n| {
            method
                .step(n as f64 * dt, dt, &mut q, &mut p, &mut Kepler)
                .expect("step");
            ((Kepler::energy(q[0], p[0]) - e0) / e0).abs()
        })
        .collect()
}

fn window_max(errors: &[f64], from: f64, to: f64) -> f64 {
    let (a, b) = (
        (errors.len() as f64 * from) as usize,
        (errors.len() as f64 * to) as usize,
    );
    errors[a..b].iter().copied().fold(0.0, f64::max)
}

#[test]
fn symplectic_methods_keep_the_kepler_energy_error_bounded() {
    let symplectic: Vec<_> = METHODS.iter().filter(|m| m.symplectic).collect();
    assert!(
        symplectic.len() >= 5,
        "semi-implicit Euler, leapfrog, both Verlets and Forest-Ruth"
    );
    for info in symplectic {
        let errors = kepler_energy_errors(info.name);
        let first = window_max(&errors, 0.0, 0.1);
        let last = window_max(&errors, 0.9, 1.0);
        println!(
            "{:>22}: max relative energy error first 10% {first:.3e}, last 10% {last:.3e}",
            info.name
        );
        // No secular growth: the last hundred time units look like the first.
        assert!(
            last <= 1.2 * first,
            "{}: energy error grew from {first:.3e} to {last:.3e}",
            info.name
        );
        assert!(first < 0.05, "{}: energy error {first:.3e} is not small", info.name);
    }
}

#[test]
fn explicit_euler_kepler_energy_error_grows() {
    let errors = kepler_energy_errors("explicit_euler");
    // Secular drift: no tenth of the run is better than the one before (the
    // error jumps at each pericentre passage and holds in between), and the
    // orbit ends far from where it started (|E| drifts towards escape).
    let tenths: Vec<f64> = (0..10)
        .map(|k| window_max(&errors, k as f64 / 10.0, (k + 1) as f64 / 10.0))
        .collect();
    let first_orbit = window_max(&errors, 0.0, 0.0063);
    println!("explicit_euler: first orbit {first_orbit:.3e}, tenths {tenths:?}");
    assert!(
        tenths.windows(2).all(|w| w[1] >= 0.999 * w[0]),
        "drift is not monotone: {tenths:?}"
    );
    assert!(
        tenths[9] > 5.0 * first_orbit,
        "explicit Euler's energy error should grow: {first_orbit:.3e} -> {:.3e}",
        tenths[9]
    );
    assert!(tenths[9] > 0.5, "final relative energy error {:.3e}", tenths[9]);
}

#[test]
fn leapfrog_velocity_verlet_and_the_other_reversible_methods_retrace_their_path() {
    // Explicit methods to rounding (1e-10); implicit ones to their solve
    // tolerance (1e-10 per step) accumulated over 4000 steps.
    let cases = [
        ("leapfrog", 1e-10),
        ("velocity_verlet", 1e-10),
        ("forest_ruth", 1e-10),
        ("trapezoidal", 1e-7),
        ("newmark_beta", 1e-7),
    ];
    for (name, tolerance) in cases {
        assert!(
            tickwork_integrators::find(name).unwrap().reversible,
            "{name} is flagged reversible"
        );
        let mut method = build::<DVec2>(name).expect("registered");
        let (q0, p0) = Kepler::start(0.5);
        let (mut q, mut p) = (vec![q0], vec![p0]);
        let (dt, steps) = (0.01, 2000);
        for n in 0..steps {
            method
                .step(n as f64 * dt, dt, &mut q, &mut p, &mut Kepler)
                .expect("step");
        }
        assert!((q[0] - q0).length() > 0.1, "{name}: the orbit moved");
        p[0] = -p[0];
        for n in 0..steps {
            method
                .step((steps + n) as f64 * dt, dt, &mut q, &mut p, &mut Kepler)
                .expect("step");
        }
        let (dq, dp) = ((q[0] - q0).length(), (-p[0] - p0).length());
        println!("{name}: back at the start within |dq| = {dq:.2e}, |dp| = {dp:.2e}");
        assert!(
            dq < tolerance && dp < tolerance,
            "{name}: |dq| = {dq:.3e}, |dp| = {dp:.3e}"
        );
    }
}

#[test]
fn stiff_drag_is_bounded_for_implicit_exponential_and_trapezoidal_and_explicit_euler_diverges() {
    let dt = 1.0 / 60.0;
    let drag = Oscillator { k: 0.0, b: 1000.0 };
    let run = |name: &str| {
        let mut method = build::<f64>(name).expect("registered");
        let (mut x, mut v) = (vec![0.0], vec![1.0]);
        let mut system = drag;
        let mut largest: f64 = 0.0;
        for n in 0..120 {
            method
                .step(n as f64 * dt, dt, &mut x, &mut v, &mut system)
                .expect("step");
            largest = largest.max(v[0].abs());
        }
        (largest, v[0], x[0])
    };
    for name in ["implicit_euler", "exponential_euler", "trapezoidal"] {
        let (largest, v, x) = run(name);
        println!("{name}: max |v| {largest:.3e}, final v {v:.3e}, x {x:.6}");
        assert!(largest <= 1.0, "{name}: |v| reached {largest}");
        // The particle glides at most v0 / b = 1e-3 before stopping.
        assert!(x.abs() <= 1.1e-3, "{name}: x = {x}");
    }
    let (largest, _, _) = run("explicit_euler");
    println!("explicit_euler: max |v| {largest:.3e}");
    // |1 - b dt| = 15.7 per step.
    assert!(
        largest > 1e100,
        "explicit Euler should diverge, max |v| = {largest:.3e}"
    );
}

#[test]
fn exponential_euler_is_exact_for_constant_force_with_linear_drag() {
    // x'' = g - b x', from rest: v(t) = g/b (1 - e^-bt), x(t) = g/b t - g/b^2 (1 - e^-bt).
    let (g, b) = (-9.81, 0.7);
    let mut system = |_t: f64, _x: &[f64], v: &[f64], a: &mut [f64]| a[0] = g - b * v[0];
    struct WithDrag<F>(F, f64);
    impl<F: FnMut(f64, &[f64], &[f64], &mut [f64])> tickwork_integrators::System<f64> for WithDrag<F> {
        fn acceleration(&mut self, t: f64, x: &[f64], v: &[f64], out: &mut [f64]) {
            (self.0)(t, x, v, out)
        }
        fn linear_drag(&self) -> f64 {
            self.1
        }
    }
    let mut system = WithDrag(&mut system, b);
    let mut method = build::<f64>("exponential_euler").expect("registered");
    let (mut x, mut v) = (vec![0.0], vec![0.0]);
    let dt = 0.25;
    for n in 0..40 {
        method
            .step(n as f64 * dt, dt, &mut x, &mut v, &mut system)
            .expect("step");
    }
    let t: f64 = 10.0;
    let decay = 1.0 - (-b * t).exp();
    let (x_exact, v_exact) = (g / b * t - g / (b * b) * decay, g / b * decay);
    assert!((v[0] - v_exact).abs() < 1e-12 * v_exact.abs(), "{} vs {v_exact}", v[0]);
    assert!((x[0] - x_exact).abs() < 1e-12 * x_exact.abs(), "{} vs {x_exact}", x[0]);
}

#[test]
fn every_method_steps_every_vector_type() {
    // Three independent unit oscillators per particle; after t = 1 each
    // component is cos(1) times its start. f32 methods get a looser bound.
    fn check<V: tickwork_integrators::Vector>(start: V, tolerance: f64) {
        use tickwork_integrators::Real;
        for info in METHODS {
            let mut method: Box<dyn Integrator<V>> = build(info.name).expect("registered");
            let (mut x, mut v) = (vec![start; 4], vec![V::ZERO; 4]);
            let mut spring = |_t: V::Real, x: &[V], _v: &[V], a: &mut [V]| {
                for (a, x) in a.iter_mut().zip(x) {
                    *a = -*x;
                }
            };
            let dt = V::Real::from_f64(0.01);
            for n in 0..100 {
                let t = V::Real::from_f64(n as f64 * 0.01);
                method.step(t, dt, &mut x, &mut v, &mut spring).expect("step");
            }
            let expected = start * V::Real::from_f64(1f64.cos());
            let error = (x[3] - expected).length_squared().to_f64().sqrt();
            assert!(
                error < tolerance,
                "{} on {}: error {error:.3e}",
                info.name,
                core::any::type_name::<V>()
            );
        }
    }
    check(1.0f64, 1e-2);
    check(1.0f32, 1e-2);
    check(glam::Vec2::new(1.0, -2.0), 2e-2);
    check(glam::Vec3::new(1.0, -2.0, 0.5), 2e-2);
    check(glam::Vec3A::new(1.0, -2.0, 0.5), 2e-2);
    check(glam::DVec2::new(1.0, -2.0), 2e-2);
    check(glam::DVec3::new(1.0, -2.0, 0.5), 2e-2);
}

//! The trapezoidal rule and the Newmark family against closed forms: the
//! one-step map of the oscillator (at small amplitudes, where a stopping rule
//! with an absolute floor went wrong), the named members' stability limits,
//! and central difference against velocity Verlet.
// Reference values and set-ups computed natively (never in a page): the
// platform's own functions are fine here (clippy.toml bans them in the engine).
#![allow(clippy::disallowed_methods)]

use crate::common;

use common::Oscillator;
use tickwork_integrators::{Integrator, NewmarkBeta, build, find};

/// The trapezoidal rule's (and average-acceleration Newmark's) exact one-step
/// map of `x'' = -x`: `(I - h/2 A)^-1 (I + h/2 A)` with `A = [[0, 1], [-1, 0]]`,
/// a rotation (the Cayley transform), applied `steps` times.
fn cayley(x: f64, v: f64, h: f64, steps: usize) -> (f64, f64) {
    let d = 1.0 + h * h / 4.0;
    let (c, s) = ((1.0 - h * h / 4.0) / d, h / d);
    let (mut x, mut v) = (x, v);
    for _ in 0..steps {
        (x, v) = (c * x + s * v, -s * x + c * v);
    }
    (x, v)
}

#[test]
fn the_trapezoidal_rule_and_average_acceleration_follow_the_exact_one_step_map_at_small_amplitude() {
    // Amplitude 1e-6: an absolute floor of 1e-10 in the stopping rule was a
    // relative error of 1e-4 per step here.
    for name in ["trapezoidal", "newmark_beta"] {
        for h in [0.1, 0.5, 2.0] {
            let steps = 2_000;
            let mut method = build::<f64>(name).expect("registered");
            let mut spring = Oscillator { k: 1.0, b: 0.0 };
            let (mut x, mut v) = (vec![1e-6], vec![0.0]);
            for n in 0..steps {
                method.step(n as f64 * h, h, &mut x, &mut v, &mut spring).expect("step");
            }
            let (xe, ve) = cayley(1e-6, 0.0, h, steps);
            let error = ((x[0] - xe).powi(2) + (v[0] - ve).powi(2)).sqrt() / 1e-6;
            assert!(
                error < 1e-8,
                "{name}, h {h}: relative error {error:.3e} after {steps} steps"
            );
        }
    }
}

#[test]
fn the_trapezoidal_rule_neither_gains_nor_loses_energy_on_the_oscillator() {
    // The exact map is a rotation: x^2 + v^2 is invariant. Over 20 000 steps
    // at unit amplitude, h omega from 0.3 to 3, the solve's error must not
    // accumulate into growth: a one-step map growing by 8e-11 per step (the
    // absolute floor) drifts by 1.6e-6 here; the relative rule's tolerance of
    // 1e-10 leaves about 1e-12 per step.
    for h in [0.3, 1.0, 3.0] {
        let mut method = build::<f64>("trapezoidal").expect("registered");
        let mut spring = Oscillator { k: 1.0, b: 0.0 };
        let (mut x, mut v) = (vec![1.0], vec![0.0]);
        for n in 0..20_000 {
            method.step(n as f64 * h, h, &mut x, &mut v, &mut spring).expect("step");
        }
        let drift = (x[0] * x[0] + v[0] * v[0] - 1.0).abs();
        assert!(drift < 1e-7, "h {h}: x^2 + v^2 drifted by {drift:.3e}");
    }
}

#[test]
fn newmark_members_are_registered_by_name_with_their_parameters() {
    for (name, alias, beta, gamma) in [
        ("newmark_beta", "average_acceleration", 0.25, 0.5),
        ("newmark_linear_acceleration", "linear_acceleration", 1.0 / 6.0, 0.5),
        ("newmark_central_difference", "central_difference", 0.0, 0.5),
    ] {
        assert_eq!(find(alias).map(|m| m.name), Ok(name));
        let built = build::<f64>(name).expect("registered").info();
        assert_eq!(built, NewmarkBeta::<f64>::with_parameters(beta, gamma).info(), "{name}");
        assert_eq!(built.name, name);
        assert_eq!(built.order, 2);
    }
    assert_eq!(NewmarkBeta::<f64>::with_parameters(0.3, 0.6).info().order, 1);
}

/// Whether `name` keeps the oscillator bounded at step `h` over 4 000 steps.
fn bounded(name: &str, h: f64) -> bool {
    let mut method = build::<f64>(name).expect("registered");
    let mut spring = Oscillator { k: 1.0, b: 0.0 };
    let (mut x, mut v) = (vec![1.0], vec![0.0]);
    for n in 0..4_000 {
        if method.step(n as f64 * h, h, &mut x, &mut v, &mut spring).is_err() {
            return false;
        }
    }
    x[0] * x[0] + v[0] * v[0] < 4.0
}

#[test]
fn newmark_members_are_stable_up_to_their_theoretical_limits() {
    // 1 / sqrt(gamma/2 - beta): 2 sqrt 3 for linear acceleration, 2 for
    // central difference; average acceleration is unconditionally stable.
    for (name, limit) in [
        ("newmark_linear_acceleration", 2.0 * 3f64.sqrt()),
        ("newmark_central_difference", 2.0),
    ] {
        assert!(bounded(name, 0.98 * limit), "{name} at 0.98 x its limit {limit}");
        assert!(!bounded(name, 1.02 * limit), "{name} at 1.02 x its limit {limit}");
    }
    assert!(bounded("newmark_beta", 50.0));
}

#[test]
fn central_difference_is_velocity_verlet_on_position_only_forces() {
    // A Kepler orbit (e = 0.5) in 2D: same positions and velocities to
    // rounding after 2 000 steps.
    let mut gravity = |_t: f64, x: &[glam::DVec2], _v: &[glam::DVec2], a: &mut [glam::DVec2]| {
        for (a, x) in a.iter_mut().zip(x) {
            *a = -*x / x.length().powi(3);
        }
    };
    let start = (
        vec![glam::DVec2::new(0.5, 0.0)],
        vec![glam::DVec2::new(0.0, 3f64.sqrt())],
    );
    let mut central = build::<glam::DVec2>("newmark_central_difference").expect("registered");
    let mut verlet = build::<glam::DVec2>("velocity_verlet").expect("registered");
    let (mut xc, mut vc) = start.clone();
    let (mut xv, mut vv) = start;
    let h = 0.01;
    let mut evaluations = 0;
    for n in 0..2_000 {
        let t = n as f64 * h;
        evaluations += central
            .step(t, h, &mut xc, &mut vc, &mut gravity)
            .expect("step")
            .evaluations;
        verlet.step(t, h, &mut xv, &mut vv, &mut gravity).expect("step");
    }
    let (dx, dv) = ((xc[0] - xv[0]).length(), (vc[0] - vv[0]).length());
    println!("central difference vs velocity Verlet: |dx| {dx:.2e}, |dv| {dv:.2e}");
    assert!(dx < 1e-11 && dv < 1e-11, "|dx| {dx:e}, |dv| {dv:e}");
    // One Newton iteration per step: start acceleration, two residuals, one product.
    assert_eq!(evaluations, 4 * 2_000);
}

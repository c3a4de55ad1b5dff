//! Angular integration against theory: unit norm, conservation laws of the
//! free top, the intermediate-axis flip, and convergence order.

mod common;

use common::slope;
use glam::{DQuat, DVec3};
use tickwork_integrators::angular::{
    ANGULAR_METHODS, AngularIntegrator, Bodies, TorqueFree, angular_momentum, build_angular, rotational_energy,
};

const INERTIA: DVec3 = DVec3::new(1.0, 2.0, 3.0);

fn run(name: &str, w0: DVec3, dt: f64, steps: usize, mut each: impl FnMut(DQuat, DVec3)) -> (DQuat, DVec3) {
    let mut method: Box<dyn AngularIntegrator<DQuat>> = build_angular(name).expect("registered");
    let (mut q, mut w) = ([DQuat::IDENTITY], [w0]);
    for n in 0..steps {
        let bodies = Bodies {
            orientations: &mut q,
            angular_velocities: &mut w,
            inertia: &[INERTIA],
        };
        method.step(n as f64 * dt, dt, bodies, &mut TorqueFree).expect("step");
        each(q[0], w[0]);
    }
    (q[0], w[0])
}

#[test]
fn renormalised_and_exponential_methods_keep_unit_norm_over_a_hundred_thousand_steps() {
    for name in ["quaternion_euler", "exponential_map"] {
        let mut worst: f64 = 0.0;
        run(name, DVec3::new(1.0, 2.0, 3.0), 1.0 / 60.0, 100_000, |q, _| {
            worst = worst.max((q.length() - 1.0).abs())
        });
        println!("{name}: worst |q| - 1 = {worst:.2e}");
        assert!(worst < 1e-12, "{name}: norm drifted by {worst:.3e}");
    }
}

#[test]
fn the_free_top_conserves_energy_and_angular_momentum() {
    let w0 = DVec3::new(0.3, 1.0, -0.6);
    let (e0, l0) = (
        rotational_energy(DQuat::IDENTITY, w0, INERTIA),
        angular_momentum(DQuat::IDENTITY, w0, INERTIA),
    );
    // The exponential map conserves L exactly in exact arithmetic; 1e-9 allows
    // for rounding in R I R^T over 20 000 steps.
    for (name, dt, energy_tolerance, momentum_tolerance) in [
        ("angular_rk4", 1e-3, 1e-10, 1e-10),
        ("exponential_map", 1e-3, 1e-2, 1e-9),
    ] {
        let (mut de, mut dl): (f64, f64) = (0.0, 0.0);
        run(name, w0, dt, 20_000, |q, w| {
            de = de.max(((rotational_energy(q, w, INERTIA) - e0) / e0).abs());
            dl = dl.max((angular_momentum(q, w, INERTIA) - l0).length() / l0.length());
        });
        println!("{name}: max relative energy error {de:.2e}, angular momentum {dl:.2e}");
        assert!(de < energy_tolerance, "{name}: energy error {de:.3e}");
        assert!(dl < momentum_tolerance, "{name}: angular momentum error {dl:.3e}");
    }
}

#[test]
fn an_asymmetric_top_flips_about_its_intermediate_axis_only() {
    let body_w = |q: DQuat, w: DVec3| q.conjugate() * w;
    for name in ["angular_rk4", "exponential_map", "quaternion_euler"] {
        // Spin about the intermediate axis (I2 = 2) with a small perturbation.
        let mut lowest = f64::INFINITY;
        run(name, DVec3::new(1e-3, 1.0, 1e-3), 0.005, 12_000, |q, w| {
            lowest = lowest.min(body_w(q, w).y)
        });
        assert!(
            lowest < -0.9,
            "{name}: the intermediate axis did not flip (lowest w_y {lowest:.3})"
        );
        // About the major axis (I3 = 3) the same perturbation stays small.
        let mut lowest = f64::INFINITY;
        run(name, DVec3::new(1e-3, 1e-3, 1.0), 0.005, 12_000, |q, w| {
            lowest = lowest.min(body_w(q, w).z)
        });
        assert!(
            lowest > 0.99,
            "{name}: the major axis should be stable (lowest w_z {lowest:.3})"
        );
    }
}

#[test]
fn angular_methods_converge_at_their_stated_order() {
    let w0 = DVec3::new(0.3, 1.0, -0.6);
    let t_end = 2.0;
    let (_, reference) = run("angular_rk4", w0, 1e-4, 20_000, |_, _| {});
    let dts = [0.1, 0.05, 0.025, 0.0125, 0.00625];
    for info in ANGULAR_METHODS {
        let errors: Vec<f64> = dts
            .iter()
            .map(|&dt| {
                let (_, w) = run(info.name, w0, dt, (t_end / dt).round() as usize, |_, _| {});
                (w - reference).length()
            })
            .collect();
        let slope = slope(&dts, &errors);
        println!("{}: slope {slope:.3}, errors {errors:?}", info.name);
        assert!(
            (slope - f64::from(info.order)).abs() <= 0.15,
            "{}: slope {slope:.3} vs {}",
            info.name,
            info.order
        );
    }
}

#[test]
fn unknown_angular_names_and_bad_steps_are_errors() {
    let error = build_angular::<DQuat>("slerp").err().expect("unknown");
    assert!(error.to_string().starts_with("unknown integrator 'slerp'"), "{error}");
    let mut method = build_angular::<glam::Quat>("exp_map").expect("alias");
    let (mut q, mut w) = ([glam::Quat::IDENTITY], [glam::Vec3::ONE]);
    let bodies = Bodies {
        orientations: &mut q,
        angular_velocities: &mut w,
        inertia: &[],
    };
    let error = method.step(0.0, 0.1, bodies, &mut TorqueFree).expect_err("lengths");
    assert!(error.to_string().contains("1 positions but 0 velocities"), "{error}");
}

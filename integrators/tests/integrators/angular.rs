//! Angular integration against theory: unit norm, conservation laws of the
//! free top, the intermediate-axis flip, and convergence order.

use crate::common;

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

/// An independent RK4 on the free top, written here from the equations with
/// plain `[f64; 4]` quaternions `(w, x, y, z)` and a rotation matrix, sharing
/// no code with the crate: `q' = 1/2 (0, w) q`; `w' = R I^-1 (-(R^T w) x I R^T w)`,
/// where `R` is the rotation of the stage quaternion `q / |q|` (a stage of
/// RK4 is not unit length; its rotation is); the end quaternion normalised.
mod independent {
    type Quaternion = [f64; 4];
    type Vector = [f64; 3];

    fn rotation(q: Quaternion) -> [[f64; 3]; 3] {
        let n = q.iter().map(|c| c * c).sum::<f64>().sqrt();
        let [w, x, y, z] = q.map(|c| c / n);
        [
            [
                1.0 - 2.0 * (y * y + z * z),
                2.0 * (x * y - w * z),
                2.0 * (x * z + w * y),
            ],
            [
                2.0 * (x * y + w * z),
                1.0 - 2.0 * (x * x + z * z),
                2.0 * (y * z - w * x),
            ],
            [
                2.0 * (x * z - w * y),
                2.0 * (y * z + w * x),
                1.0 - 2.0 * (x * x + y * y),
            ],
        ]
    }

    fn times(m: [[f64; 3]; 3], v: Vector) -> Vector {
        [0, 1, 2].map(|r| m[r][0] * v[0] + m[r][1] * v[1] + m[r][2] * v[2])
    }

    fn transposed_times(m: [[f64; 3]; 3], v: Vector) -> Vector {
        [0, 1, 2].map(|c| m[0][c] * v[0] + m[1][c] * v[1] + m[2][c] * v[2])
    }

    fn derivative(q: Quaternion, w: Vector, inertia: Vector) -> (Quaternion, Vector) {
        // (0, w) q, halved.
        let [qw, qx, qy, qz] = q;
        let dq = [
            -(w[0] * qx + w[1] * qy + w[2] * qz),
            w[0] * qw + w[1] * qz - w[2] * qy,
            w[1] * qw + w[2] * qx - w[0] * qz,
            w[2] * qw + w[0] * qy - w[1] * qx,
        ]
        .map(|c| 0.5 * c);
        let r = rotation(q);
        let wb = transposed_times(r, w);
        let lb = [0, 1, 2].map(|k| inertia[k] * wb[k]);
        let gyro = [
            wb[1] * lb[2] - wb[2] * lb[1],
            wb[2] * lb[0] - wb[0] * lb[2],
            wb[0] * lb[1] - wb[1] * lb[0],
        ];
        let dwb = [0, 1, 2].map(|k| -gyro[k] / inertia[k]);
        (dq, times(r, dwb))
    }

    /// `steps` RK4 steps of `h` from the identity; returns (q, w) with q as (x, y, z, w).
    pub fn run(w0: Vector, inertia: Vector, h: f64, steps: usize) -> ([f64; 4], Vector) {
        let (mut q, mut w): (Quaternion, Vector) = ([1.0, 0.0, 0.0, 0.0], w0);
        let add = |a: Quaternion, b: Quaternion, s: f64| [0, 1, 2, 3].map(|k| a[k] + s * b[k]);
        let addv = |a: Vector, b: Vector, s: f64| [0, 1, 2].map(|k| a[k] + s * b[k]);
        for _ in 0..steps {
            let (k1q, k1w) = derivative(q, w, inertia);
            let (k2q, k2w) = derivative(add(q, k1q, h / 2.0), addv(w, k1w, h / 2.0), inertia);
            let (k3q, k3w) = derivative(add(q, k2q, h / 2.0), addv(w, k2w, h / 2.0), inertia);
            let (k4q, k4w) = derivative(add(q, k3q, h), addv(w, k3w, h), inertia);
            let sum_q = [0, 1, 2, 3].map(|k| k1q[k] + 2.0 * k2q[k] + 2.0 * k3q[k] + k4q[k]);
            let sum_w = [0, 1, 2].map(|k| k1w[k] + 2.0 * k2w[k] + 2.0 * k3w[k] + k4w[k]);
            q = add(q, sum_q, h / 6.0);
            let n = q.iter().map(|c| c * c).sum::<f64>().sqrt();
            q = q.map(|c| c / n);
            w = addv(w, sum_w, h / 6.0);
        }
        ([q[1], q[2], q[3], q[0]], w)
    }
}

#[test]
fn angular_rk4_is_as_accurate_as_an_independent_rk4_at_a_fixed_step() {
    // A torque-free asymmetric top, h = 0.1 to t = 10. Before the stage
    // rotations were normalised, Tickwork's error here was about 5 times the
    // independent RK4's (order 4 kept, so the slope test could not see it).
    for w0 in [DVec3::new(0.3, 1.0, -0.6), DVec3::new(1.0, 3.0, -2.0)] {
        compare_with_independent_rk4(w0);
    }
}

fn compare_with_independent_rk4(w0: DVec3) {
    let (h, steps) = (0.1, 100);
    let (q_ref, w_ref) = independent::run(w0.to_array(), INERTIA.to_array(), 1e-4, 100_000);
    let (q_ind, w_ind) = independent::run(w0.to_array(), INERTIA.to_array(), h, steps);
    let (q, w) = run("angular_rk4", w0, h, steps, |_, _| {});
    let q_ref = DQuat::from_array(q_ref);
    let orientation_error = |q: DQuat| q.angle_between(q_ref);
    let error = orientation_error(q);
    let independent_error = orientation_error(DQuat::from_array(q_ind));
    let w_error = (w - DVec3::from_array(w_ref)).length();
    let w_independent_error = (DVec3::from_array(w_ind) - DVec3::from_array(w_ref)).length();
    println!(
        "w0 {w0}: orientation error {error:.3e} (independent {independent_error:.3e}), \
         angular velocity error {w_error:.3e} (independent {w_independent_error:.3e})"
    );
    assert!(independent_error > 1e-6, "the step is too small to compare errors");
    assert!(
        (error / independent_error - 1.0).abs() < 0.01,
        "orientation error {error:.3e} vs the independent RK4's {independent_error:.3e}"
    );
    assert!(
        (w_error / w_independent_error - 1.0).abs() < 0.01,
        "angular velocity error {w_error:.3e} vs the independent RK4's {w_independent_error:.3e}"
    );
}

#[test]
fn angular_names_match_by_the_linear_registrys_rule() {
    for given in ["quaternionEuler", "Quaternion-Euler", " angular rk4 ", "EXP_MAP"] {
        assert!(build_angular::<DQuat>(given).is_ok(), "{given}");
    }
    // `rk4` and `euler` are linear methods' names, never an angular one's.
    for linear in ["rk4", "euler"] {
        assert!(build_angular::<DQuat>(linear).is_err(), "{linear}");
        assert!(tickwork_integrators::find(linear).is_ok(), "{linear}");
    }
}

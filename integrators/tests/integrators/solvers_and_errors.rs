//! The implicit solve against the lecture's closed form, and every error a
//! step can report, with its message.
// Reference values and set-ups computed natively (never in a page): the
// platform's own functions are fine here (clippy.toml bans them in the engine).
#![allow(clippy::disallowed_methods)]

use crate::common;

use common::Oscillator;
use tickwork_integrators::{DormandPrince, ImplicitEuler, Integrator, NewtonKrylovConfig, StepError, System, build};

/// Pure linear drag that also supplies its exact Jacobian-vector product.
struct DragWithJacobian {
    b: f64,
}

impl System<f64> for DragWithJacobian {
    fn acceleration(&mut self, _t: f64, _x: &[f64], v: &[f64], out: &mut [f64]) {
        for (a, v) in out.iter_mut().zip(v) {
            *a = -self.b * v;
        }
    }
    fn jacobian_product(&mut self, _t: f64, _x: &[f64], _v: &[f64], _dx: &[f64], dv: &[f64], out: &mut [f64]) -> bool {
        for (o, dv) in out.iter_mut().zip(dv) {
            *o = -self.b * dv;
        }
        true
    }
}

#[test]
fn implicit_euler_matches_the_closed_form_for_linear_drag() {
    let (b, dt) = (3.0, 0.1);
    let v0 = [1.0, -2.0, 0.5];
    // Finite-difference Jacobian (the default).
    let mut method = build::<f64>("implicit_euler").expect("registered");
    let (mut x, mut v) = (vec![0.0; 3], v0.to_vec());
    let stats = method
        .step(0.0, dt, &mut x, &mut v, &mut Oscillator { k: 0.0, b })
        .expect("converges");
    for i in 0..3 {
        let expected = v0[i] / (1.0 + b * dt);
        assert!(
            (v[i] - expected).abs() <= 1e-12 * expected.abs(),
            "v = {} vs {expected}",
            v[i]
        );
        assert!((x[i] - dt * expected).abs() <= 1e-12, "x = {}", x[i]);
    }
    assert!(stats.newton_iterations <= 2, "{stats:?}");
    // Supplied Jacobian: a linear problem is solved in one Newton iteration
    // and one Krylov iteration, exactly.
    let mut method = ImplicitEuler::<f64>::new();
    let (mut x, mut v) = (vec![0.0; 3], v0.to_vec());
    let stats = method
        .step(0.0, dt, &mut x, &mut v, &mut DragWithJacobian { b })
        .expect("converges");
    assert_eq!((stats.newton_iterations, stats.krylov_iterations), (1, 1), "{stats:?}");
    for i in 0..3 {
        let expected = v0[i] / (1.0 + b * dt);
        assert!((v[i] - expected).abs() <= 1e-15, "v = {} vs {expected}", v[i]);
    }
}

#[test]
fn implicit_methods_solve_coupled_nonlinear_springs() {
    // Two particles joined by a stiff cubic spring: the Jacobian couples them,
    // so a per-particle solve would be wrong. Check the implicit Euler residual.
    let k = 400.0;
    let mut spring = |_t: f64, x: &[f64], _v: &[f64], a: &mut [f64]| {
        let stretch = x[1] - x[0] - 1.0;
        let force = k * (stretch + stretch * stretch * stretch);
        a[0] = force;
        a[1] = -force;
    };
    let (x0, v0) = (vec![0.0, 1.5], vec![0.0, 0.0]);
    let (mut x, mut v) = (x0.clone(), v0.clone());
    let dt = 0.05;
    let stats = build::<f64>("implicit_euler")
        .unwrap()
        .step(0.0, dt, &mut x, &mut v, &mut spring)
        .expect("converges");
    let mut a = vec![0.0; 2];
    spring(dt, &x, &v, &mut a);
    for i in 0..2 {
        assert!((v[i] - v0[i] - dt * a[i]).abs() < 1e-9, "residual of particle {i}");
        assert!((x[i] - x0[i] - dt * v[i]).abs() < 1e-12);
    }
    assert!(stats.newton_iterations >= 2, "nonlinear: {stats:?}");
    // Momentum is conserved by the pairwise force.
    assert!((v[0] + v[1]).abs() < 1e-9);
}

#[test]
fn a_non_converged_implicit_solve_is_reported_and_leaves_the_state_unchanged() {
    let config = NewtonKrylovConfig {
        max_newton_iterations: 1,
        ..NewtonKrylovConfig::for_real::<f64>()
    };
    let mut method = ImplicitEuler::<f64>::with_config(config);
    // Cubic drag at a large step: one Newton iteration is not enough.
    let mut cubic = |_t: f64, _x: &[f64], v: &[f64], a: &mut [f64]| a[0] = -50.0 * v[0] * v[0] * v[0];
    let (mut x, mut v) = (vec![0.25], vec![3.0]);
    let error = method
        .step(0.0, 0.1, &mut x, &mut v, &mut cubic)
        .expect_err("must not converge");
    match &error {
        StepError::NotConverged {
            method,
            iterations,
            residual,
            tolerance,
        } => {
            assert_eq!(*method, "implicit_euler");
            assert_eq!(*iterations, 1);
            assert!(residual > tolerance);
        }
        other => panic!("wrong error {other:?}"),
    }
    let message = error.to_string();
    assert!(
        message.starts_with("implicit_euler: implicit solve did not converge after 1 Newton iterations"),
        "{message}"
    );
    assert_eq!((x[0], v[0]), (0.25, 3.0), "state left as it was");
}

#[test]
fn dormand_prince_reports_a_sub_step_limit_and_leaves_the_state_unchanged() {
    let mut method = DormandPrince::<f64>::with_tolerances(1e-14, 1e-16);
    method.max_substeps = 3;
    let (mut x, mut v) = (vec![1.0], vec![0.0]);
    let error = method
        .step(0.0, 1.0, &mut x, &mut v, &mut Oscillator { k: 100.0, b: 0.0 })
        .expect_err("limit");
    assert!(
        matches!(error, StepError::SubstepLimit { substeps: 3, .. }),
        "{error:?}"
    );
    assert!(
        error
            .to_string()
            .starts_with("dormand_prince: gave up after 3 sub-steps"),
        "{error}"
    );
    assert_eq!((x[0], v[0]), (1.0, 0.0));
}

#[test]
fn dormand_prince_meets_its_tolerance_by_sub_stepping() {
    // One fixed step of 0.5 on a stiff-ish oscillator (omega = 10): the
    // default tolerance forces many sub-steps and a small error.
    let mut method = DormandPrince::<f64>::new();
    let (mut x, mut v) = (vec![1.0], vec![0.0]);
    let mut system = Oscillator { k: 100.0, b: 0.0 };
    let mut stats = Vec::new();
    for n in 0..4 {
        stats.push(
            method
                .step(n as f64 * 0.5, 0.5, &mut x, &mut v, &mut system)
                .expect("step"),
        );
    }
    let exact = (10.0f64 * 2.0).cos();
    assert!((x[0] - exact).abs() < 1e-5, "x = {} vs {exact}", x[0]);
    assert!(stats[0].substeps > 5, "{:?}", stats[0]);
    // Later fixed steps start from the carried-over sub-step size: fewer rejections.
    assert!(stats[3].rejected_substeps <= stats[0].rejected_substeps, "{stats:?}");
}

#[test]
fn bad_time_steps_and_mismatched_slices_are_errors() {
    for info in tickwork_integrators::METHODS {
        let mut method = build::<f64>(info.name).unwrap();
        let mut system = Oscillator { k: 1.0, b: 0.0 };
        for dt in [0.0, f64::NAN, f64::INFINITY] {
            let error = method
                .step(0.0, dt, &mut [1.0], &mut [0.0], &mut system)
                .expect_err("bad dt");
            let StepError::InvalidTimeStep { method, dt: reported } = error.clone() else {
                panic!("{error:?}")
            };
            assert_eq!(method, info.name);
            assert_eq!(reported.to_bits(), dt.to_bits());
            assert!(
                error.to_string().contains("time step must be finite and non-zero"),
                "{error}"
            );
        }
        let error = method
            .step(0.0, 0.1, &mut [1.0, 2.0], &mut [0.0], &mut system)
            .expect_err("lengths");
        assert_eq!(
            error.to_string(),
            format!(
                "{}: 2 positions but 1 velocities; the slices must have the same length",
                info.name
            )
        );
    }
}

#[test]
fn registry_evaluation_counts_match_what_steps_report_on_a_linear_problem() {
    // Damped oscillator, steady state (after history and caches are warm).
    for info in tickwork_integrators::METHODS {
        let mut method = build::<f64>(info.name).unwrap();
        let (mut x, mut v) = (vec![1.0, 0.5], vec![0.0, -0.2]);
        let mut system = Oscillator { k: 1.0, b: 0.5 };
        let mut last = None;
        for n in 0..10 {
            last = Some(method.step(n as f64 * 0.01, 0.01, &mut x, &mut v, &mut system).unwrap());
        }
        let stats = last.unwrap();
        println!("{:>26}: {stats:?}", info.name);
        assert_eq!(stats.evaluations, info.evaluations, "{}: {stats:?}", info.name);
    }
}

#[test]
fn newmark_parameters_select_the_family_member() {
    use tickwork_integrators::NewmarkBeta;
    let steps = 200;
    let dt = 0.05;
    let run = |method: &mut dyn Integrator<f64>| {
        let (mut x, mut v) = (vec![1.0], vec![0.0]);
        let mut energies = Vec::new();
        for n in 0..steps {
            method
                .step(n as f64 * dt, dt, &mut x, &mut v, &mut Oscillator { k: 1.0, b: 0.0 })
                .unwrap();
            energies.push(0.5 * (x[0] * x[0] + v[0] * v[0]));
        }
        (x[0], v[0], energies)
    };
    // beta = 0, gamma = 1/2 is the explicit central difference: velocity Verlet.
    let (x_cd, v_cd, _) = run(&mut NewmarkBeta::with_parameters(0.0, 0.5));
    let (x_vv, v_vv, _) = run(build::<f64>("velocity_verlet").unwrap().as_mut());
    assert!(
        (x_cd - x_vv).abs() < 1e-9 && (v_cd - v_vv).abs() < 1e-9,
        "{x_cd} {x_vv}"
    );
    // The default (average acceleration) conserves the oscillator's energy to
    // the solver tolerance: it is the trapezoidal rule.
    let (_, _, energies) = run(&mut NewmarkBeta::new());
    assert!(
        energies.iter().all(|e| (e - 0.5).abs() < 1e-9),
        "average acceleration keeps energy"
    );
    // gamma > 1/2 damps numerically, every step, and is first order.
    let mut damped = NewmarkBeta::with_parameters(0.3025, 0.6);
    assert_eq!(damped.info().order, 1);
    assert!(!damped.info().reversible);
    let (_, _, energies) = run(&mut damped);
    assert!(energies.windows(2).all(|w| w[1] < w[0]), "numerical damping");
    // Theory for small h omega: damping ratio (gamma - 1/2) h omega / 2, so the
    // energy decays as exp(-(gamma - 1/2) h omega^2 t).
    let expected = 0.5 * (-(0.6 - 0.5) * dt * (steps as f64 * dt)).exp();
    let last = energies[steps - 1];
    assert!(
        (last - expected).abs() < 0.01 * expected,
        "damped to {last}, theory {expected}"
    );
}

#[test]
fn every_method_steps_an_empty_world_and_then_grows() {
    // A game starts with no particles and spawns them later.
    for info in tickwork_integrators::METHODS {
        let mut method = build::<f64>(info.name).unwrap();
        let mut system = Oscillator { k: 1.0, b: 0.1 };
        let (mut x, mut v): (Vec<f64>, Vec<f64>) = (Vec::new(), Vec::new());
        let stats = method.step(0.0, 0.1, &mut x, &mut v, &mut system).expect("empty step");
        assert_eq!(stats.bootstrapped, 0, "{}", info.name);
        x.push(1.0);
        v.push(0.0);
        for n in 1..11 {
            method
                .step(n as f64 * 0.1, 0.1, &mut x, &mut v, &mut system)
                .expect("step");
        }
        let (x_exact, _) = system.exact(1.0, 0.0, 1.0);
        assert!((x[0] - x_exact).abs() < 0.05, "{}: {} vs {x_exact}", info.name, x[0]);
    }
}

#[test]
fn restarted_gmres_reaches_the_same_implicit_solution() {
    // A chain of 12 particles joined by stiff springs: the Jacobian has many
    // distinct eigenvalues, so a Krylov space of 2 needs restarts.
    let k = 2500.0;
    let mut chain = |_t: f64, x: &[f64], _v: &[f64], a: &mut [f64]| {
        a.fill(0.0);
        for i in 0..x.len() - 1 {
            let force = k * (x[i + 1] - x[i] - 1.0);
            a[i] += force;
            a[i + 1] -= force;
        }
    };
    let x0: Vec<f64> = (0..12)
        .map(|i| i as f64 * 1.0 + if i % 3 == 0 { 0.2 } else { -0.1 })
        .collect();
    let solve = |restart: usize, chain: &mut dyn System<f64>| {
        let config = NewtonKrylovConfig {
            restart,
            ..NewtonKrylovConfig::for_real::<f64>()
        };
        let mut method = ImplicitEuler::<f64>::with_config(config);
        let (mut x, mut v) = (x0.clone(), vec![0.0; 12]);
        let stats = method.step(0.0, 1.0 / 30.0, &mut x, &mut v, chain).expect("converges");
        (x, stats)
    };
    let (x_full, full) = solve(30, &mut chain);
    let (x_restarted, restarted) = solve(2, &mut chain);
    assert!(
        restarted.krylov_iterations > full.krylov_iterations,
        "{restarted:?} vs {full:?}"
    );
    for (a, b) in x_full.iter().zip(&x_restarted) {
        assert!((a - b).abs() < 1e-8, "{a} vs {b}");
    }
}

/// One step of 1/60 s by `$method` of a chain of 12 particles 0.26 m apart
/// near x = 5 m, joined by springs of k/m = 40 000 s^-2 (a stiff cloth's),
/// stretched by 1%, in scalar type `$real`.
macro_rules! stiff_chain_step {
    ($real:ty, $method:expr) => {{
        let n = 12;
        let k: $real = 40_000.0;
        let mut chain = |_t: $real, x: &[$real], _v: &[$real], a: &mut [$real]| {
            a.fill(-1.0);
            for i in 0..n - 1 {
                let f = k * (x[i + 1] - x[i] - 0.26);
                a[i] += f;
                a[i + 1] -= f;
            }
        };
        let mut x: Vec<$real> = (0..n).map(|i| 5.0 + 0.2626 * i as $real).collect();
        let mut v: Vec<$real> = vec![0.0; n];
        $method.step(0.0, 1.0 / 60.0, &mut x, &mut v, &mut chain).map(|_| x)
    }};
}

#[test]
fn f32_implicit_solves_of_stiff_springs_stop_at_the_round_off_floor() {
    for name in ["implicit_euler", "newmark_beta", "trapezoidal"] {
        let mut method = build::<f32>(name).expect("registered");
        let x32 = stiff_chain_step!(f32, method).unwrap_or_else(|e| panic!("{name}: {e}"));
        let mut reference = build::<f64>(name).expect("registered");
        let x64 = stiff_chain_step!(f64, reference).expect("f64 converges");
        for (a, b) in x32.iter().zip(&x64) {
            assert!((f64::from(*a) - b).abs() < 1e-4, "{name}: f32 {a} against f64 {b}");
        }
    }
    // Without accepting stagnation, the f32 solve cannot reach 64 epsilons.
    let strict = NewtonKrylovConfig {
        stagnation_tolerance: 0.0,
        ..NewtonKrylovConfig::for_real::<f32>()
    };
    let mut method = ImplicitEuler::<f32>::with_config(strict);
    let error = stiff_chain_step!(f32, method).expect_err("round-off floor");
    assert!(matches!(error, StepError::NotConverged { .. }), "{error}");
}

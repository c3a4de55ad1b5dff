//! Empirical convergence order of every registered method against theory.
//!
//! Harmonic oscillator k = m = 1, x0 = 1, v0 = 0, integrated to t = 10 with
//! dt = 0.1 halved four times; the least-squares slope of log error against
//! log dt must be within 0.15 of the registry's order. The damped oscillator
//! (b = 0.5) checks the order under velocity-dependent forces. Velocities are
//! checked from a generic start (v0 = 1): from v0 = 0 the first-order
//! velocity error of semi-implicit Euler cancels exactly on this problem.
// Reference values and set-ups computed natively (never in a page): the
// platform's own functions are fine here (clippy.toml bans them in the engine).
#![allow(clippy::disallowed_methods)]

use crate::common;

use common::{Oscillator, run, slope};
use tickwork_integrators::{DormandPrince, Integrator, METHODS, MethodInfo, build};

const T_END: f64 = 10.0;
/// Shorter, so that first-order methods' amplitude error stays in the asymptotic range.
const T_VELOCITY: f64 = 2.0;
const DTS: [f64; 5] = [0.1, 0.05, 0.025, 0.0125, 0.00625];

fn method(info: &MethodInfo) -> Box<dyn Integrator<f64>> {
    if info.name == "dormand_prince" {
        // With the default tolerance the error follows the tolerance, not dt.
        // A tolerance loose enough for one sub-step per fixed step exposes the
        // fifth-order formula itself.
        Box::new(DormandPrince::with_tolerances(1.0, 1.0))
    } else {
        build(info.name).expect("registered")
    }
}

/// Position, velocity and state errors at `t_end` for every dt.
fn errors(info: &MethodInfo, oscillator: Oscillator, v0: f64, t_end: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let (x_exact, v_exact) = oscillator.exact(1.0, v0, t_end);
    let mut out = (Vec::new(), Vec::new(), Vec::new());
    for dt in DTS {
        let steps = (t_end / dt).round() as usize;
        let mut system = oscillator;
        let (x, v) = run(method(info).as_mut(), &mut system, 1.0, v0, dt, steps);
        out.0.push((x - x_exact).abs());
        out.1.push((v - v_exact).abs());
        out.2.push((x - x_exact).hypot(v - v_exact));
    }
    out
}

fn check(label: &str, info: &MethodInfo, stated: u32, errors: &[f64]) -> Option<String> {
    let measured = slope(&DTS, errors);
    let errors: Vec<String> = errors.iter().map(|e| format!("{e:.2e}")).collect();
    let errors = errors.join(" ");
    println!(
        "{label:>16} {:>26}: slope {measured:6.3}, stated {stated}, errors {errors}",
        info.name
    );
    let ok = (measured - f64::from(stated)).abs() <= 0.15;
    (!ok).then(|| {
        format!(
            "{} {label}: slope {measured:.3} vs stated {stated} (errors {errors})",
            info.name
        )
    })
}

#[test]
fn every_method_converges_at_its_stated_order_on_the_harmonic_oscillator() {
    let mut failures = Vec::new();
    for info in METHODS {
        let (ex, _, _) = errors(info, Oscillator { k: 1.0, b: 0.0 }, 0.0, T_END);
        failures.extend(check("position", info, info.order, &ex));
    }
    assert!(failures.is_empty(), "orders off:\n{}", failures.join("\n"));
}

#[test]
fn every_method_reports_velocities_at_its_stated_velocity_order() {
    let mut failures = Vec::new();
    for info in METHODS {
        let (_, ev, _) = errors(info, Oscillator { k: 1.0, b: 0.0 }, 1.0, T_VELOCITY);
        failures.extend(check("velocity", info, info.order_velocity, &ev));
    }
    assert!(failures.is_empty(), "orders off:\n{}", failures.join("\n"));
}

#[test]
fn every_method_converges_at_its_stated_order_under_linear_drag() {
    let mut failures = Vec::new();
    for info in METHODS {
        let (ex, ev, es) = errors(info, Oscillator { k: 1.0, b: 0.5 }, 0.0, T_END);
        check("position, drag", info, info.order_velocity_forces, &ex);
        check("velocity, drag", info, info.order_velocity_forces, &ev);
        failures.extend(check("state, drag", info, info.order_velocity_forces, &es));
    }
    assert!(failures.is_empty(), "orders off:\n{}", failures.join("\n"));
}

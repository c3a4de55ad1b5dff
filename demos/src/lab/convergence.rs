//! Convergence: error against time step, log-log, with fitted slopes.

use tickwork_integrators::METHODS;

use super::LabError;
use super::problems::{Problem, integrate, log_slope, method};

/// Errors below this are round-off, not truncation, and are left out of fits.
pub const ROUND_OFF_FLOOR: f64 = 1e-12;

/// One method on one problem at five time steps.
#[derive(Clone, Debug, PartialEq)]
pub struct Convergence {
    /// The problem.
    pub problem: Problem,
    /// The method's canonical name.
    pub method: &'static str,
    /// The order the registry states for this problem's error measure.
    pub stated: u32,
    /// `(dt, error, force evaluations)` from the coarsest step down.
    pub points: Vec<(f64, f64, u64)>,
    /// Least-squares slope of log error against log dt, over the points above
    /// the round-off floor (`None` with fewer than three).
    pub slope: Option<f64>,
}

/// Runs every method on `problem` at the coarsest step and four halvings. A
/// run whose step fails records an infinite error.
///
/// # Errors
/// [`LabError::Method`] for a method that cannot be built.
pub fn study(problem: Problem) -> Result<Vec<Convergence>, LabError> {
    let reference = problem.reference();
    let (x0, v0) = problem.start();
    METHODS
        .iter()
        .map(|info| {
            let mut points = Vec::new();
            for k in 0..5 {
                let steps = problem.coarsest_steps(info) << k;
                let mut m = method(info.name)?;
                let dt = problem.duration() / steps as f64;
                // A failed step (implicit Euler's solve as its orbit decays
                // into the singularity) is an infinite error, not an abort.
                match integrate(m.as_mut(), problem, x0, v0, steps) {
                    Ok((x, v, evaluations)) => points.push((dt, problem.error(x, v, reference), evaluations)),
                    Err(_) => points.push((dt, f64::INFINITY, 0)),
                }
            }
            let fit: Vec<(f64, f64)> = points
                .iter()
                .filter(|p| p.1.is_finite() && p.1 > ROUND_OFF_FLOOR)
                .map(|p| (p.0, p.1))
                .collect();
            let slope = (fit.len() >= 3).then(|| log_slope(&fit));
            Ok(Convergence {
                problem,
                method: info.name,
                stated: problem.expected_order(info),
                points,
                slope,
            })
        })
        .collect()
}

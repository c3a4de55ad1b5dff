//! Stability: the largest stable step, found numerically, beside theory.
//!
//! A step `h` is stable when a run of [`STEPS`] steps from a unit state does
//! not grow: the largest amplitude in the second half exceeds the largest in
//! the first half by at most [`GROWTH`]. An unstable mode grows by
//! `rho^(STEPS/2)`, which passes that once `rho - 1` exceeds about `2e-9`;
//! a stable one repeats its (possibly oscillating) amplitude, and with
//! thousands of samples per half both halves come within about `1e-7` of its
//! peak. So weak instabilities (explicit Euler's `sqrt(1 + h^2)`, midpoint's
//! `sqrt(1 + h^4/4)`) show as limits near zero, as theory says. The limit is
//! found by bisection on `log h` between [`H_MIN`] and [`H_MAX`].

use glam::DVec2;
use tickwork_integrators::{METHODS, System, math};

use super::LabError;
use super::problems::method;

/// Steps per stability probe.
pub const STEPS: usize = 20_000;
/// Smallest step probed; unstable there means "unstable for every h" (0).
pub const H_MIN: f64 = 1e-3;
/// Largest step probed; stable there means unconditionally stable (infinity).
pub const H_MAX: f64 = 100.0;
/// Relative growth between the two halves that counts as unstable.
pub const GROWTH: f64 = 1e-5;

/// The two linear test problems.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TestEquation {
    /// `x'' = -x` (omega = 1): the limit is in units of `h omega`.
    Oscillator,
    /// `x'' = -x'` (b = 1): the limit is in units of `h b`.
    Drag,
}

impl TestEquation {
    /// Name in tables and files.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Oscillator => "oscillator (h omega)",
            Self::Drag => "linear drag (h b)",
        }
    }
}

struct Linear(TestEquation);

impl System<DVec2> for Linear {
    fn acceleration(&mut self, _t: f64, x: &[DVec2], v: &[DVec2], out: &mut [DVec2]) {
        for ((a, x), v) in out.iter_mut().zip(x).zip(v) {
            *a = match self.0 {
                TestEquation::Oscillator => -*x,
                TestEquation::Drag => -*v,
            };
        }
    }
    fn linear_drag(&self) -> f64 {
        if self.0 == TestEquation::Drag { 1.0 } else { 0.0 }
    }
}

/// What theory says, in units of `h omega` / `h b`: `Some(0.0)` unstable for
/// every step, `Some(INFINITY)` unconditionally stable, `None` not derived here.
#[must_use]
pub fn theory(method: &str, equation: TestEquation) -> Option<f64> {
    use TestEquation::{Drag, Oscillator};
    let inf = f64::INFINITY;
    let value = match (method, equation) {
        // |1 + i h| > 1; |1 - h| <= 1 for h <= 2.
        ("explicit_euler", Oscillator) => 0.0,
        ("explicit_euler", Drag) => 2.0,
        // Symplectic Euler: trace 2 - h^2 in [-2, 2]; v(1 - h b).
        ("semi_implicit_euler", Oscillator | Drag) => 2.0,
        ("implicit_euler" | "trapezoidal" | "newmark_beta", _) => inf,
        // Semi-implicit Euler's trace on the oscillator; drag factor 1 / (1 + h b).
        ("implicit_drag_euler", Oscillator) => 2.0,
        ("implicit_drag_euler", Drag) => inf,
        // Newmark with gamma = 1/2: h omega < 1 / sqrt(gamma/2 - beta); on
        // drag the velocity update is the trapezoidal rule's, (1 - z/2) / (1 + z/2).
        ("newmark_linear_acceleration", Oscillator) => 2.0 * 3f64.sqrt(),
        ("newmark_central_difference", Oscillator) => 2.0,
        ("newmark_linear_acceleration" | "newmark_central_difference", Drag) => inf,
        // Positions take the corrected velocity: on the oscillator the step
        // matrix has determinant 1 - h^2 and, past h = 1, a real eigenvalue
        // 1 - h^2 - h sqrt(h^2 - 1) that reaches -1 at h = 2/sqrt 3. On drag
        // the factor is 1 - z + z^2.
        ("predictor_corrector_euler", Oscillator) => 2.0 / 3f64.sqrt(),
        ("predictor_corrector_euler", Drag) => 1.0,
        // Without drag: determinant 1 + h^2/2 > 1. Drag is integrated exactly.
        ("exponential_euler", Oscillator) => 0.0,
        ("exponential_euler", Drag) => inf,
        // Second-order Runge-Kutta: |1 + z + z^2/2| = sqrt(1 + h^4/4) on the imaginary axis.
        ("midpoint" | "heun", Oscillator) => 0.0,
        ("midpoint" | "heun", Drag) => 2.0,
        ("leapfrog" | "position_verlet" | "velocity_verlet", Oscillator) => 2.0,
        // Leapfrog's cached closing kick makes the half-step velocities
        // shrink by 1 - z; position Verlet's differences by 1 - z.
        ("leapfrog" | "position_verlet", Drag) => 2.0,
        // Velocity Verlet with its predicted end velocity: the step matrix
        // [[1 - z/2, (z^2 - z)/2], [1, -z]] has the eigenvalue -1 at z = 1.
        ("velocity_verlet", Drag) => 1.0,
        // Fourth-order Runge-Kutta: imaginary-axis limit 2 sqrt 2, real-axis 2.785.
        ("rk4", Oscillator) => 2.0 * 2f64.sqrt(),
        ("rk4", Drag) => 2.785_293_563_405_282,
        // Adams-Bashforth: AB2's region touches the imaginary axis only at 0.
        ("adams_bashforth2", Oscillator) => 0.0,
        ("adams_bashforth2", Drag) => 1.0,
        ("adams_bashforth3", Oscillator) => 0.723_6,
        ("adams_bashforth3", Drag) => 6.0 / 11.0,
        ("adams_bashforth4", Oscillator) => 0.429_5,
        ("adams_bashforth4", Drag) => 0.3,
        // Yoshida's triple jump: limited by its largest (negative) sub-step.
        ("forest_ruth", Oscillator) => 1.573_4,
        ("dormand_prince", _) => inf,
        _ => return None,
    };
    Some(value)
}

/// Whether `method` stays bounded at step `h`.
fn stable(name: &str, equation: TestEquation, h: f64) -> Result<bool, LabError> {
    let mut m = method(name)?;
    if name == "dormand_prince" {
        // Adaptive: sub-steps to its (loose) tolerance, so it cannot blow up;
        // probing it costs thousands of sub-steps per step at large h.
        m = tickwork_integrators::build::<DVec2>(name)?;
    }
    let mut system = Linear(equation);
    let (mut x, mut v) = match equation {
        TestEquation::Oscillator => ([DVec2::X], [DVec2::ZERO]),
        TestEquation::Drag => ([DVec2::ZERO], [DVec2::X]),
    };
    let amplitude = |x: DVec2, v: DVec2| match equation {
        TestEquation::Oscillator => (x.length_squared() + v.length_squared()).sqrt(),
        TestEquation::Drag => v.length(),
    };
    let steps = if name == "dormand_prince" { 200 } else { STEPS };
    let (mut first, mut second) = (amplitude(x[0], v[0]), 0.0f64);
    for n in 0..steps {
        if m.step(n as f64 * h, h, &mut x, &mut v, &mut system).is_err() {
            return Ok(false);
        }
        let a = amplitude(x[0], v[0]);
        if !a.is_finite() || a > 1e30 {
            return Ok(false);
        }
        if n < steps / 2 {
            first = first.max(a);
        } else {
            second = second.max(a);
        }
    }
    Ok(second <= first * (1.0 + GROWTH))
}

/// A measured limit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limit {
    /// The method.
    pub method: &'static str,
    /// The test equation.
    pub equation: TestEquation,
    /// Largest stable `h` found: 0 when unstable at [`H_MIN`], infinity when
    /// stable at [`H_MAX`].
    pub measured: f64,
    /// The theoretical limit, where derived.
    pub theory: Option<f64>,
}

/// Finds every method's limit on both test equations.
///
/// # Errors
/// [`LabError::Method`] for a method that cannot be built.
pub fn study() -> Result<Vec<Limit>, LabError> {
    let mut limits = Vec::new();
    for equation in [TestEquation::Oscillator, TestEquation::Drag] {
        for info in METHODS {
            let measured = if !stable(info.name, equation, H_MIN)? {
                0.0
            } else if stable(info.name, equation, H_MAX)? {
                f64::INFINITY
            } else {
                let (mut lo, mut hi) = (math::ln(H_MIN), math::ln(H_MAX));
                // 20 halvings of ln(1e5) = 11.5: the limit to 1e-5 relative.
                for _ in 0..20 {
                    let mid = 0.5 * (lo + hi);
                    if stable(info.name, equation, math::exp(mid))? {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                math::exp(lo)
            };
            limits.push(Limit {
                method: info.name,
                equation,
                measured,
                theory: theory(info.name, equation),
            });
        }
    }
    Ok(limits)
}

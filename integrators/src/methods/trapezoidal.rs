//! The (implicit) trapezoidal rule: the average of the derivatives at both ends.
//!
//! ```text
//! x(t + h) = x + h/2 (v + v(t + h))
//! v(t + h) = v + h/2 (a(t, x, v) + a(t + h, x(t + h), v(t + h)))
//! ```
//!
//! Solved for the end velocity `u` by the Newton-Krylov solver
//! ([`NewtonKrylovConfig`]), starting from the explicit Euler guess. On
//! `(x, v)` systems it coincides with Newmark-beta's average-acceleration
//! variant (`beta = 1/4, gamma = 1/2`).
//!
//! - Order 2 for positions and velocities, also with drag.
//! - Cost: variable; on a linear problem 4 evaluations per step (the start
//!   acceleration, two residuals, one finite-difference product).
//! - Stability: A-stable (every `h` is stable on drag and springs) and
//!   time-reversible, with no numerical damping on the undamped oscillator;
//!   very stiff components are not damped either (the factor tends to -1), so
//!   they ring rather than blow up.

use crate::integrator::{Integrator, MethodInfo, StepError, StepStats, check_step};
use crate::newton_krylov::{Coefficients, NewtonKrylov, NewtonKrylovConfig};
use crate::system::System;
use crate::vector::{Real, Vector, c};

/// Registry entry.
pub const INFO: MethodInfo = MethodInfo {
    name: "trapezoidal",
    aliases: &["trapezoidal_rule", "crank_nicolson"],
    title: "Trapezoidal rule",
    notes: "A-stable, no numerical damping",
    order: 2,
    order_velocity: 2,
    order_velocity_forces: 2,
    evaluations: 4,
    reversible: true,
    implicit: true,
    ..MethodInfo::SOLVED
};

/// Trapezoidal rule. See the [module documentation](self).
#[derive(Debug, Clone)]
pub struct Trapezoidal<V: Vector> {
    /// The Newton-Krylov tolerances and caps.
    pub config: NewtonKrylovConfig,
    solver: NewtonKrylov<V>,
}

impl<V: Vector> Default for Trapezoidal<V> {
    fn default() -> Self {
        Self::new()
    }
}

impl<V: Vector> Trapezoidal<V> {
    /// The trapezoidal rule with the default solver settings for `V`'s scalar type.
    #[must_use]
    pub fn new() -> Self {
        Self::with_config(NewtonKrylovConfig::for_real::<V::Real>())
    }

    /// The trapezoidal rule with the given solver settings.
    #[must_use]
    pub fn with_config(config: NewtonKrylovConfig) -> Self {
        Self {
            config,
            solver: NewtonKrylov::default(),
        }
    }
}

impl<V: Vector> Integrator<V> for Trapezoidal<V> {
    fn info(&self) -> MethodInfo {
        INFO
    }

    fn step(
        &mut self,
        t: V::Real,
        dt: V::Real,
        x: &mut [V],
        v: &mut [V],
        system: &mut dyn System<V>,
    ) -> Result<StepStats, StepError> {
        check_step(INFO.name, dt, x, v)?;
        let n = x.len();
        let s = &mut self.solver;
        s.fit(n, &self.config);
        // The start acceleration goes through `rhs` as scratch.
        system.acceleration(t, x, v, &mut s.rhs);
        let half = dt * c(0.5);
        for i in 0..n {
            let a0 = s.rhs[i];
            s.u[i] = v[i] + a0 * dt;
            s.rhs[i] = v[i] + a0 * half;
            s.base_x[i] = x[i] + v[i] * half;
        }
        s.base_v.fill(V::ZERO);
        let k = Coefficients {
            t1: t + dt,
            cx: half,
            cv: V::Real::ONE,
            ca: half,
        };
        s.solve_into(INFO.name, k, &self.config, system, x, v, 1)
    }
}

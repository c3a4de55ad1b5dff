//! Newmark-beta, the structural-dynamics family: end position and velocity
//! from a weighted blend of the start and end accelerations.
//!
//! ```text
//! x(t + h) = x + h v + h^2 ((1/2 - beta) a(t) + beta a(t + h))
//! v(t + h) = v + h ((1 - gamma) a(t) + gamma a(t + h))
//! a(t + h) = a(t + h, x(t + h), v(t + h))
//! ```
//!
//! Solved for the end acceleration by the Newton-Krylov solver
//! ([`NewtonKrylovConfig`]), starting from `a(t)`. Three members of the
//! family are registered by name:
//!
//! | name | beta | gamma | what it is | stable on the oscillator |
//! |---|---|---|---|---|
//! | `newmark_beta` (default) | 1/4 | 1/2 | average (constant) acceleration; the trapezoidal rule on `(x, v)`; no numerical damping | every `h` |
//! | `newmark_linear_acceleration` | 1/6 | 1/2 | the acceleration varies linearly over the step | `h omega < 2 sqrt 3` |
//! | `newmark_central_difference` | 0 | 1/2 | central difference: the position update is explicit; on position-only forces it is velocity Verlet | `h omega < 2` |
//!
//! Any other pair is available through [`NewmarkBeta::with_parameters`];
//! `gamma > 1/2` adds numerical damping of high frequencies at the cost of
//! first order. With `beta = 0` the end position does not depend on the
//! unknown, so the solve is only for the velocity-dependent part of the
//! forces: on position-only forces Newton converges in one iteration, to
//! velocity Verlet's `v + h/2 (a(t) + a(t + h))`.
//!
//! - Order 2 for positions and velocities when `gamma = 1/2`, else 1.
//! - Cost: variable; on a linear problem 4 evaluations per step (the start
//!   acceleration, two residuals, one finite-difference product).
//! - Stability: unconditionally stable when `2 beta >= gamma >= 1/2`;
//!   otherwise for `h omega < 1 / sqrt(gamma/2 - beta)` (when `gamma = 1/2`).

use crate::integrator::{Integrator, MethodInfo, StepError, StepStats, check_step};
use crate::newton_krylov::{Coefficients, NewtonKrylov, NewtonKrylovConfig};
use crate::system::System;
use crate::vector::{Real, Vector, c};

/// Registry entry for the default parameters, average acceleration
/// (`beta = 1/4, gamma = 1/2`).
pub const INFO: MethodInfo = MethodInfo {
    name: "newmark_beta",
    aliases: &["newmark", "average_acceleration", "newmark_average_acceleration"],
    title: "Newmark-beta (average acceleration)",
    notes: "average acceleration (beta 1/4, gamma 1/2); any beta and gamma through `NewmarkBeta::with_parameters`",
    order: 2,
    order_velocity: 2,
    order_velocity_forces: 2,
    evaluations: 4,
    reversible: true,
    implicit: true,
    ..MethodInfo::SOLVED
};

/// Registry entry for linear acceleration (`beta = 1/6, gamma = 1/2`).
pub const LINEAR_ACCELERATION: MethodInfo = MethodInfo {
    name: "newmark_linear_acceleration",
    aliases: &["linear_acceleration"],
    title: "Newmark-beta (linear acceleration)",
    notes: "Newmark with beta 1/6, gamma 1/2; stable for `h omega < 2 sqrt 3`",
    ..INFO
};

/// Registry entry for central difference (`beta = 0, gamma = 1/2`).
pub const CENTRAL_DIFFERENCE: MethodInfo = MethodInfo {
    name: "newmark_central_difference",
    aliases: &["central_difference"],
    title: "Newmark-beta (central difference)",
    notes: "Newmark with beta 0, gamma 1/2; velocity Verlet on position-only forces",
    ..INFO
};

/// The named members of the family: `(beta, gamma, entry)`.
const MEMBERS: [(f64, f64, MethodInfo); 3] = [
    (0.25, 0.5, INFO),
    (1.0 / 6.0, 0.5, LINEAR_ACCELERATION),
    (0.0, 0.5, CENTRAL_DIFFERENCE),
];

/// Newmark-beta. See the [module documentation](self).
#[derive(Debug, Clone)]
pub struct NewmarkBeta<V: Vector> {
    /// Weight of the end acceleration in the position update (default: `0.25`).
    pub beta: f64,
    /// Weight of the end acceleration in the velocity update (default: `0.5`).
    pub gamma: f64,
    /// The Newton-Krylov tolerances and caps.
    pub config: NewtonKrylovConfig,
    start_accel: Vec<V>,
    solver: NewtonKrylov<V>,
}

impl<V: Vector> Default for NewmarkBeta<V> {
    fn default() -> Self {
        Self::new()
    }
}

impl<V: Vector> NewmarkBeta<V> {
    /// The average-acceleration variant (`beta = 1/4, gamma = 1/2`).
    #[must_use]
    pub fn new() -> Self {
        Self::with_parameters(0.25, 0.5)
    }

    /// The linear-acceleration variant (`beta = 1/6, gamma = 1/2`).
    #[must_use]
    pub fn linear_acceleration() -> Self {
        Self::with_parameters(1.0 / 6.0, 0.5)
    }

    /// The central-difference variant (`beta = 0, gamma = 1/2`).
    #[must_use]
    pub fn central_difference() -> Self {
        Self::with_parameters(0.0, 0.5)
    }

    /// Newmark-beta with the given `beta` and `gamma`.
    #[must_use]
    pub fn with_parameters(beta: f64, gamma: f64) -> Self {
        Self {
            beta,
            gamma,
            config: NewtonKrylovConfig::for_real::<V::Real>(),
            start_accel: Vec::new(),
            solver: NewtonKrylov::default(),
        }
    }
}

impl<V: Vector> Integrator<V> for NewmarkBeta<V> {
    fn info(&self) -> MethodInfo {
        if let Some((_, _, info)) = MEMBERS.iter().find(|m| m.0 == self.beta && m.1 == self.gamma) {
            return *info;
        }
        let second_order = self.gamma == 0.5;
        let order = if second_order { 2 } else { 1 };
        MethodInfo {
            title: "Newmark-beta",
            notes: "Newmark-beta with its own beta and gamma",
            order,
            order_velocity: order,
            order_velocity_forces: order,
            reversible: second_order,
            ..INFO
        }
    }

    fn step(
        &mut self,
        t: V::Real,
        dt: V::Real,
        x: &mut [V],
        v: &mut [V],
        system: &mut dyn System<V>,
    ) -> Result<StepStats, StepError> {
        let name = self.info().name;
        check_step(name, dt, x, v)?;
        let n = x.len();
        let s = &mut self.solver;
        s.fit(n, &self.config);
        crate::integrator::fit(&mut self.start_accel, n);
        system.acceleration(t, x, v, &mut self.start_accel);
        let h2 = dt * dt;
        let wx: V::Real = c(0.5 - self.beta);
        let wv: V::Real = c(1.0 - self.gamma);
        for i in 0..n {
            let a0 = self.start_accel[i];
            s.base_x[i] = x[i] + v[i] * dt + a0 * (h2 * wx);
            s.base_v[i] = v[i] + a0 * (dt * wv);
            s.u[i] = a0;
        }
        s.rhs.fill(V::ZERO);
        let k = Coefficients {
            t1: t + dt,
            cx: h2 * c(self.beta),
            cv: dt * c(self.gamma),
            ca: V::Real::ONE,
        };
        s.solve_into(name, k, &self.config, system, x, v, 1)
    }
}

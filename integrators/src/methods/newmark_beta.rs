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
//! ([`NewtonKrylovConfig`]), starting from `a(t)`. The default is the
//! average-acceleration (constant-average-acceleration) variant
//! `beta = 1/4, gamma = 1/2`, which is unconditionally stable and adds no
//! numerical damping; it coincides with the trapezoidal rule on `(x, v)`.
//! `beta = 0, gamma = 1/2` is the explicit central-difference method, and
//! `gamma > 1/2` adds numerical damping of high frequencies at the cost of
//! first order.
//!
//! - Order 2 for positions and velocities when `gamma = 1/2`, else 1.
//! - Cost: variable; on a linear problem 4 evaluations per step (the start
//!   acceleration, two residuals, one finite-difference product).
//! - Stability: unconditionally stable when `2 beta >= gamma >= 1/2`;
//!   otherwise conditionally (central difference: `h omega < 2`).

use crate::integrator::{Integrator, MethodInfo, StepError, StepStats, check_step};
use crate::newton_krylov::{Coefficients, NewtonKrylov, NewtonKrylovConfig};
use crate::system::System;
use crate::vector::{Real, Vector, c};

/// Registry entry (for the default parameters).
pub const INFO: MethodInfo = MethodInfo {
    name: "newmark_beta",
    aliases: &["newmark", "average_acceleration"],
    title: "Newmark-beta (average acceleration)",
    order: 2,
    order_velocity: 2,
    order_velocity_forces: 2,
    evaluations: 4,
    symplectic: false,
    reversible: true,
    self_starting: true,
    implicit: true,
    variable_cost: true,
};

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
        let second_order = self.gamma == 0.5;
        let order = if second_order { 2 } else { 1 };
        MethodInfo {
            title: if self.beta == 0.25 && second_order {
                INFO.title
            } else {
                "Newmark-beta"
            },
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
        check_step(INFO.name, dt, x, v)?;
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
        s.solve_into(INFO.name, k, &self.config, system, x, v, 1)
    }
}

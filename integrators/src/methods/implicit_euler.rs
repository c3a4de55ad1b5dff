//! Implicit (backward) Euler: the end state is the one that, run backwards
//! with its own derivatives, lands on the start.
//!
//! ```text
//! v(t + h) = v + h a(t + h, x(t + h), v(t + h))
//! x(t + h) = x + h v(t + h)
//! ```
//!
//! For general forces this is solved for the end velocity `u`,
//! `u - v - h a(t + h, x + h u, u) = 0`, by the matrix-free Newton-Krylov solver
//! ([`NewtonKrylovConfig`]), starting from `u = v`. For pure linear drag the
//! solve reproduces the lecture's closed form `v / (1 + b h)`; a system that
//! knows its Jacobian (see [`System::jacobian_product`]) makes each Krylov
//! iteration exact and cheaper than the finite-difference default.
//!
//! - Order 1 for positions and velocities.
//! - Cost: variable; on a linear problem 3 evaluations per step (two residuals
//!   and one finite-difference product).
//! - Stability: L-stable: every `h` is stable on drag and springs, and stiff
//!   components are damped rather than amplified. The price is numerical
//!   damping: an undamped oscillator loses energy at every step, which is why
//!   the lecture recommends it for damping, not for orbits.
//!
//! A solve that does not converge is reported as
//! [`StepError::NotConverged`] and the state is
//! left unchanged.

use crate::integrator::{Integrator, MethodInfo, StepError, StepStats, check_step};
use crate::newton_krylov::{Coefficients, NewtonKrylov, NewtonKrylovConfig};
use crate::system::System;
use crate::vector::{Real, Vector};

/// Registry entry.
pub const INFO: MethodInfo = MethodInfo {
    name: "implicit_euler",
    aliases: &["backward_euler"],
    title: "Implicit (backward) Euler",
    notes: "L-stable; Newton-Krylov for any force; `v/(1 + b h)` on drag",
    order: 1,
    order_velocity: 1,
    order_velocity_forces: 1,
    evaluations: 3,
    implicit: true,
    ..MethodInfo::SOLVED
};

/// Implicit Euler. See the [module documentation](self).
#[derive(Debug, Clone)]
pub struct ImplicitEuler<V: Vector> {
    /// The Newton-Krylov tolerances and caps.
    pub config: NewtonKrylovConfig,
    solver: NewtonKrylov<V>,
}

impl<V: Vector> Default for ImplicitEuler<V> {
    fn default() -> Self {
        Self::new()
    }
}

impl<V: Vector> ImplicitEuler<V> {
    /// Implicit Euler with the default solver settings for `V`'s scalar type.
    #[must_use]
    pub fn new() -> Self {
        Self::with_config(NewtonKrylovConfig::for_real::<V::Real>())
    }

    /// Implicit Euler with the given solver settings.
    #[must_use]
    pub fn with_config(config: NewtonKrylovConfig) -> Self {
        Self {
            config,
            solver: NewtonKrylov::default(),
        }
    }
}

impl<V: Vector> Integrator<V> for ImplicitEuler<V> {
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
        let s = &mut self.solver;
        s.fit(x.len(), &self.config);
        s.base_x.copy_from_slice(x);
        s.base_v.fill(V::ZERO);
        s.rhs.copy_from_slice(v);
        s.u.copy_from_slice(v);
        let k = Coefficients {
            t1: t + dt,
            cx: dt,
            cv: V::Real::ONE,
            ca: dt,
        };
        s.solve_into(INFO.name, k, &self.config, system, x, v, 0)
    }
}

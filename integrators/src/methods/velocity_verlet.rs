//! Velocity Verlet: positions from a second-order Taylor step, velocities from
//! the average of the accelerations at both ends.
//!
//! ```text
//! x(t + h) = x + h v + h^2/2 a(t)
//! v~       = v + h a(t)                          (predicted end velocity, for drag)
//! a(t + h) = a(t + h, x(t + h), v~)
//! v(t + h) = v + h/2 (a(t) + a(t + h))
//! ```
//!
//! With velocity-independent forces this is leapfrog written with synchronous
//! velocities. The end acceleration is evaluated at the Euler-predicted
//! velocity `v~`, whose error is `O(h^2)`, so unlike leapfrog the method keeps
//! second order under drag. The end acceleration is reused as the next step's
//! start acceleration (dropped when the state was changed outside the step, a
//! particle was added or removed, or `h` changed; the time passed in is not
//! compared).
//!
//! - Order 2 for positions and velocities, also with velocity-dependent forces.
//! - Cost: 1 force evaluation per step (2 on the first step after a change).
//! - Stability: symplectic and time-reversible on velocity-independent forces;
//!   stable on the oscillator for `h omega < 2`.
//! - The cost of reuse: under linear drag the end acceleration, reused as the
//!   next start acceleration, was evaluated at the predicted velocity `v~`,
//!   not at `v(t + h)`; the step matrix then has the eigenvalue -1 at
//!   `h b = 1`, so the method is stable only for `h b <= 1`, half the limit
//!   `h b <= 2` of velocity Verlet with a fresh start evaluation (which would
//!   cost two evaluations).

use crate::history::History;
use crate::integrator::{Integrator, MethodInfo, StepError, StepStats, check_step, fit};
use crate::system::System;
use crate::vector::{Vector, c};

/// Registry entry.
pub const INFO: MethodInfo = MethodInfo {
    name: "velocity_verlet",
    aliases: &["vv"],
    title: "Velocity Verlet",
    notes: "stays second order under drag; the reused end acceleration halves its drag limit to `h b <= 1`",
    order: 2,
    order_velocity: 2,
    order_velocity_forces: 2,
    evaluations: 1,
    symplectic: true,
    reversible: true,
    splits_pointwise: false,
    ..MethodInfo::EXPLICIT
};

/// Velocity Verlet. See the [module documentation](self).
#[derive(Debug, Clone, Default)]
pub struct VelocityVerlet<V: Vector> {
    accel: Vec<V>,
    accel_end: Vec<V>,
    predicted_v: Vec<V>,
    history: History<V>,
}

impl<V: Vector> VelocityVerlet<V> {
    /// A new velocity Verlet integrator.
    #[must_use]
    pub fn new() -> Self {
        Self {
            accel: Vec::new(),
            accel_end: Vec::new(),
            predicted_v: Vec::new(),
            history: History::default(),
        }
    }
}

impl<V: Vector> Integrator<V> for VelocityVerlet<V> {
    fn visit_state(&self, vectors: &mut dyn FnMut(&[V]), bytes: &mut dyn FnMut(&[u8])) {
        vectors(&self.accel);
        self.history.visit(vectors, bytes);
    }

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
        let mut evaluations = 1;
        if self.history.sync(dt, x, v, 1) > 0 || self.accel.len() != n {
            fit(&mut self.accel, n);
            system.acceleration(t, x, v, &mut self.accel);
            evaluations += 1;
        }
        fit(&mut self.accel_end, n);
        fit(&mut self.predicted_v, n);
        let half = dt * c(0.5);
        let half_h2 = dt * dt * c(0.5);
        for i in 0..n {
            x[i] += v[i] * dt + self.accel[i] * half_h2;
            self.predicted_v[i] = v[i] + self.accel[i] * dt;
        }
        system.acceleration(t + dt, x, &self.predicted_v, &mut self.accel_end);
        for i in 0..n {
            v[i] += (self.accel[i] + self.accel_end[i]) * half;
            self.history.note(i, x[i], v[i]);
        }
        core::mem::swap(&mut self.accel, &mut self.accel_end);
        self.history.close(dt);
        Ok(StepStats::single(evaluations))
    }

    fn swap_remove(&mut self, index: usize, rows: usize) {
        self.history.swap_remove(index, rows);
    }

    fn reset(&mut self) {
        self.history.reset();
    }
}

//! Leapfrog in kick-drift-kick form: velocities "leap" over positions at half
//! steps, as in the lecture's `p(1) = p(0) + v(0.5) dt`, synchronised at the
//! end of every step so that games and renderers see `v(t + h)`.
//!
//! ```text
//! v(t + h/2) = v(t) + h/2 a(t, x(t), v(t))              kick
//! x(t + h)   = x(t) + h v(t + h/2)                      drift
//! v(t + h)   = v(t + h/2) + h/2 a(t + h, x(t + h), v(t + h/2))   kick
//! ```
//!
//! The closing kick's acceleration is the opening kick's of the next step
//! (first same as last), so a step costs one force evaluation, "the same cost
//! as Euler's method". The cache is dropped when the state was changed outside
//! the step, a particle was added or removed, or `h` changed (the time passed
//! in is not compared: see the history rules in the crate's `history` module).
//!
//! With velocity-dependent forces the closing kick sees the half-step velocity
//! `v(t + h/2)` rather than `v(t + h)`; that is what keeps it at one evaluation,
//! and it drops the method to first order under drag (use
//! [`VelocityVerlet`](crate::VelocityVerlet) to keep second order there).
//!
//! - Order 2 for positions and velocities; 1 with velocity-dependent forces.
//! - Cost: 1 force evaluation per step (2 on the first step after a change).
//! - Stability: symplectic and time-reversible: bounded energy error on
//!   conservative forces; stable on the oscillator for `h omega < 2`.
//! - The cost of reuse: under linear drag the reused closing-kick
//!   acceleration was evaluated at the half-step velocity, so the half-step
//!   velocities shrink by `1 - h b` per step and the method is stable only
//!   for `h b <= 2`, half the limit `h b <= 4` of leapfrog with a fresh
//!   evaluation at the end velocity (which would cost two evaluations).

use crate::history::History;
use crate::integrator::{Integrator, MethodInfo, StepError, StepStats, check_step, fit};
use crate::system::System;
use crate::vector::{Vector, c};

/// Registry entry.
pub const INFO: MethodInfo = MethodInfo {
    name: "leapfrog",
    aliases: &["kdk", "kick_drift_kick"],
    title: "Leapfrog (kick-drift-kick)",
    notes: "kick-drift-kick, one evaluation per step; the reused kick halves its drag limit to `h b <= 2`",
    order: 2,
    order_velocity: 2,
    order_velocity_forces: 1,
    evaluations: 1,
    symplectic: true,
    reversible: true,
    splits_pointwise: false,
    ..MethodInfo::EXPLICIT
};

/// Leapfrog. See the [module documentation](self).
#[derive(Debug, Clone, Default)]
pub struct Leapfrog<V: Vector> {
    accel: Vec<V>,
    history: History<V>,
}

impl<V: Vector> Leapfrog<V> {
    /// A new leapfrog integrator.
    #[must_use]
    pub fn new() -> Self {
        Self {
            accel: Vec::new(),
            history: History::default(),
        }
    }
}

impl<V: Vector> Integrator<V> for Leapfrog<V> {
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
        let half = dt * c(0.5);
        for i in 0..n {
            v[i] += self.accel[i] * half;
            x[i] += v[i] * dt;
        }
        system.acceleration(t + dt, x, v, &mut self.accel);
        for i in 0..n {
            v[i] += self.accel[i] * half;
            self.history.note(i, x[i], v[i]);
        }
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

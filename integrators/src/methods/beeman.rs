//! Beeman's algorithm in its predictor-corrector form, which handles
//! velocity-dependent forces.
//!
//! ```text
//! x(t + h) = x + h v + h^2/6 (4 a(t) - a(t - h))
//! v~       = v + h/2 (3 a(t) - a(t - h))                (predicted, Adams-Bashforth 2)
//! a(t + h) = a(t + h, x(t + h), v~)
//! v(t + h) = v + h/6 (2 a(t + h) + 5 a(t) - a(t - h))   (corrected, Adams-Moulton 3)
//! ```
//!
//! Positions are those of Verlet; velocities are more accurate than Verlet's
//! difference estimate. `a(t + h)` becomes the next step's `a(t)`, so a step
//! costs one evaluation, and `a(t)`, `a(t - h)` are per-particle history.
//!
//! Start: a particle with no history (first step, new particle, or one whose
//! state was changed outside the step) takes one RK4 step instead; its start
//! acceleration becomes `a(t - h)` and the end evaluation `a(t)`. RK4 was
//! chosen over the common "set `a(t - h) = a(t)`" start because it keeps the
//! start's error below the method's own.
//!
//! - Order 2 for positions and velocities (velocity errors are smaller than
//!   Verlet's), also with velocity-dependent forces.
//! - Cost: 1 force evaluation per step (5 on a step where a particle starts).
//! - Stability: stable on the oscillator for `h omega < 2`, like Verlet; not
//!   symplectic (the velocity corrector is not), energy drift is small.

use crate::history::{History, swap_remove_in};
use crate::integrator::{Integrator, MethodInfo, StepError, StepStats, check_step, fit};
use crate::methods::rk4::Rk4Stages;
use crate::system::System;
use crate::vector::{Vector, c};

/// Registry entry.
pub const INFO: MethodInfo = MethodInfo {
    name: "beeman",
    aliases: &["beeman_schofield"],
    title: "Beeman",
    notes: "predictor-corrector form; RK4 start",
    order: 2,
    order_velocity: 2,
    order_velocity_forces: 2,
    evaluations: 1,
    ..MethodInfo::WITH_HISTORY
};

/// Beeman. See the [module documentation](self).
#[derive(Debug, Clone, Default)]
pub struct Beeman<V: Vector> {
    /// `a(t)` per particle.
    accel: Vec<V>,
    /// `a(t - h)` per particle.
    accel_previous: Vec<V>,
    /// `a(t + h)`, then rotated into `accel`.
    accel_end: Vec<V>,
    start_v: Vec<V>,
    predicted_v: Vec<V>,
    bootstrap: Rk4Stages<V>,
    history: History<V>,
}

impl<V: Vector> Beeman<V> {
    /// A new Beeman integrator.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }
}

impl<V: Vector> Integrator<V> for Beeman<V> {
    fn visit_state(&self, vectors: &mut dyn FnMut(&[V]), bytes: &mut dyn FnMut(&[u8])) {
        vectors(&self.accel);
        vectors(&self.accel_previous);
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
        for buffer in [
            &mut self.accel,
            &mut self.accel_previous,
            &mut self.accel_end,
            &mut self.start_v,
            &mut self.predicted_v,
        ] {
            fit(buffer, n);
        }
        let starting = self.history.sync(dt, x, v, 1);
        let mut evaluations = 1;
        if starting > 0 {
            // `accel_end` is free until the end evaluation: use it for a(t).
            Rk4Stages::first_stage(t, x, v, &mut self.accel_end, system, self.history.starting(1));
            let runs = self.history.starting(1);
            self.bootstrap.run_starting(t, dt, x, v, &self.accel_end, system, runs);
            evaluations += 4;
        }
        let h2_6 = dt * dt * c(1.0 / 6.0);
        let h_2 = dt * c(0.5);
        for i in 0..n {
            self.start_v[i] = v[i];
            if self.history.has(i, 1) {
                let (a, a_prev) = (self.accel[i], self.accel_previous[i]);
                x[i] += v[i] * dt + (a * c(4.0) - a_prev) * h2_6;
                self.predicted_v[i] = v[i] + (a * c(3.0) - a_prev) * h_2;
            } else {
                let (new_x, new_v) = self.bootstrap.result(i, x[i], v[i]);
                x[i] = new_x;
                self.predicted_v[i] = new_v;
                // After the rotation below this start acceleration is a(t - h).
                self.accel[i] = self.accel_end[i];
            }
        }
        system.acceleration(t + dt, x, &self.predicted_v, &mut self.accel_end);
        let h_6 = dt * c(1.0 / 6.0);
        for i in 0..n {
            v[i] = if self.history.has(i, 1) {
                self.start_v[i] + (self.accel_end[i] * c(2.0) + self.accel[i] * c(5.0) - self.accel_previous[i]) * h_6
            } else {
                self.predicted_v[i]
            };
            self.history.note(i, x[i], v[i]);
        }
        // (previous, current, end) <- (current, end, free)
        core::mem::swap(&mut self.accel_previous, &mut self.accel);
        core::mem::swap(&mut self.accel, &mut self.accel_end);
        self.history.close(dt);
        Ok(StepStats {
            bootstrapped: starting as u32,
            ..StepStats::single(evaluations)
        })
    }

    fn swap_remove(&mut self, index: usize, rows: usize) {
        if self.history.swap_remove(index, rows) {
            swap_remove_in(&mut self.accel, index);
            swap_remove_in(&mut self.accel_previous, index);
        }
    }

    fn reset(&mut self) {
        self.history.reset();
    }
}

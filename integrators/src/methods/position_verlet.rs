//! Position (Stormer) Verlet: the lecture's velocity-free update from the sum
//! of the Taylor expansions forward and backward in time.
//!
//! ```text
//! x(t + h) = 2 x(t) - x(t - h) + h^2 a(t, x(t), v(t))
//! v(t + h) = (x(t + h) - x(t)) / h            (estimate, for drag and rendering)
//! ```
//!
//! The previous position `x(t - h)` is per-particle history. A particle with
//! none (the first step, a new particle, or one whose state was changed outside
//! the step) is started by one RK4 step, as the lecture suggests ("usually
//! obtained from one step of Euler's or RK4 method"); RK4 keeps the start from
//! spoiling second order.
//!
//! The velocity is estimated by the backward difference of the last two
//! positions, the form Verlet game engines use: it is available at the start
//! of the next step for velocity-dependent forces, needs no extra storage, and
//! is exactly the velocity the position update implies. It is first-order
//! accurate (it lags the true velocity by `h/2 a`), which is why the lecture
//! calls drag "difficult" for Verlet.
//!
//! - Order 2 for positions, 1 for the estimated velocities; 1 for positions
//!   with velocity-dependent forces.
//! - Cost: 1 force evaluation per step (4 on a step where a particle starts).
//! - Stability: symplectic and time-reversible on velocity-independent forces
//!   (as a map of the last two positions: swapping them runs it backwards;
//!   negating the estimated velocity does not, because the estimate lags by
//!   half a step); stable on the oscillator for `h omega < 2`.

use crate::history::{History, swap_remove_in};
use crate::integrator::{Integrator, MethodInfo, StepError, StepStats, check_step, fit};
use crate::methods::rk4::Rk4Stages;
use crate::system::System;
use crate::vector::{Real, Vector};

/// Registry entry.
pub const INFO: MethodInfo = MethodInfo {
    name: "position_verlet",
    aliases: &["verlet", "stormer_verlet", "stoermer_verlet"],
    title: "Position (Stormer) Verlet",
    notes: "Stormer; RK4 start; velocity by backward difference",
    order: 2,
    order_velocity: 1,
    order_velocity_forces: 1,
    evaluations: 1,
    symplectic: true,
    reversible: true,
    ..MethodInfo::WITH_HISTORY
};

/// Position Verlet. See the [module documentation](self).
#[derive(Debug, Clone, Default)]
pub struct PositionVerlet<V: Vector> {
    previous_x: Vec<V>,
    accel: Vec<V>,
    bootstrap: Rk4Stages<V>,
    history: History<V>,
}

impl<V: Vector> PositionVerlet<V> {
    /// A new position Verlet integrator.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }
}

impl<V: Vector> Integrator<V> for PositionVerlet<V> {
    fn visit_state(&self, vectors: &mut dyn FnMut(&[V]), bytes: &mut dyn FnMut(&[u8])) {
        vectors(&self.previous_x);
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
        fit(&mut self.accel, n);
        fit(&mut self.previous_x, n);
        let starting = self.history.sync(dt, x, v, 1);
        system.acceleration(t, x, v, &mut self.accel);
        let mut evaluations = 1;
        if starting > 0 {
            self.bootstrap
                .run_starting(t, dt, x, v, &self.accel, system, self.history.starting(1));
            evaluations += 3;
        }
        let h2 = dt * dt;
        let inv_h = V::Real::ONE / dt;
        for i in 0..n {
            let (new_x, new_v) = if self.history.has(i, 1) {
                let new_x = x[i] * V::Real::from_f64(2.0) - self.previous_x[i] + self.accel[i] * h2;
                (new_x, (new_x - x[i]) * inv_h)
            } else {
                self.bootstrap.result(i, x[i], v[i])
            };
            self.previous_x[i] = x[i];
            x[i] = new_x;
            v[i] = new_v;
            self.history.note(i, new_x, new_v);
        }
        self.history.close(dt);
        Ok(StepStats {
            bootstrapped: starting as u32,
            ..StepStats::single(evaluations)
        })
    }

    fn swap_remove(&mut self, index: usize, rows: usize) {
        if self.history.swap_remove(index, rows) {
            swap_remove_in(&mut self.previous_x, index);
        }
    }

    fn reset(&mut self) {
        self.history.reset();
    }
}

//! The lecture's predictor-corrector backward Euler, for games that do not
//! know their forces in closed form.
//!
//! ```text
//! predict:  x~ = x + h v,            v~ = v + h a(t, x, v)      (explicit Euler)
//! correct:  v(t + h) = v + h a(t + h, x~, v~)                   (backward Euler, a at the predicted end)
//!           x(t + h) = x + h v(t + h)
//! ```
//!
//! - Order 1 for positions and velocities.
//! - Cost: 2 force evaluations per step ("twice the amount of computation").
//! - Stability: the corrector evaluates forces at the predicted end of the step,
//!   which damps like backward Euler for small `h` but, being one fixed-point
//!   iteration rather than a solve, is not unconditionally stable: on linear drag
//!   `b` the factor is `1 - h b + (h b)^2`, stable for `h b < 1`. For truly stiff
//!   forces use [`ImplicitEuler`](crate::ImplicitEuler).

use crate::chunks::for_each_chunk;
use crate::integrator::{Integrator, MethodInfo, StepError, StepStats, check_step, fit};
use crate::system::System;
use crate::vector::Vector;

/// Registry entry.
pub const INFO: MethodInfo = MethodInfo {
    name: "predictor_corrector_euler",
    aliases: &["backward_euler_pc", "pc_euler"],
    title: "Predictor-corrector backward Euler",
    notes: "the lecture's backward Euler without a solve",
    order: 1,
    order_velocity: 1,
    order_velocity_forces: 1,
    evaluations: 2,
    ..MethodInfo::EXPLICIT
};

/// Predictor-corrector backward Euler. See the [module documentation](self).
#[derive(Debug, Clone, Default)]
pub struct PredictorCorrectorEuler<V: Vector> {
    accel: Vec<V>,
    predicted_x: Vec<V>,
    predicted_v: Vec<V>,
}

impl<V: Vector> PredictorCorrectorEuler<V> {
    /// A new predictor-corrector Euler integrator.
    #[must_use]
    pub fn new() -> Self {
        Self {
            accel: Vec::new(),
            predicted_x: Vec::new(),
            predicted_v: Vec::new(),
        }
    }
}

impl<V: Vector> Integrator<V> for PredictorCorrectorEuler<V> {
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
        let Self {
            accel,
            predicted_x,
            predicted_v,
        } = self;
        for_each_chunk(x, v, system, |x, v, system| {
            let n = x.len();
            fit(accel, n);
            fit(predicted_x, n);
            fit(predicted_v, n);
            system.acceleration(t, x, v, accel);
            for i in 0..n {
                predicted_x[i] = x[i] + v[i] * dt;
                predicted_v[i] = v[i] + accel[i] * dt;
            }
            system.acceleration(t + dt, predicted_x, predicted_v, accel);
            for i in 0..n {
                v[i] += accel[i] * dt;
                x[i] += v[i] * dt;
            }
        });
        Ok(StepStats::single(2))
    }
}

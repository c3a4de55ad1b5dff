//! Improved Euler (Heun's method), exactly as the lecture writes it: tangents
//! at both ends of the interval, averaged.
//!
//! ```text
//! v1 = v + h a(t, x, v)                  (Euler's prediction)
//! v2 = v + h a(t + h, x + h v, v1)       (correction, at the predicted end)
//! v(t + h) = (v1 + v2) / 2
//! x(t + h) = ((x + h v) + (x + h v1)) / 2 = x + h (v + v1) / 2
//! ```
//!
//! "Compute position similarly with v1, v2": the position's two tangents are
//! the start velocity and the predicted velocity `v1`. This is Heun's method
//! (the explicit trapezoidal rule) on the system `(x, v)`.
//!
//! - Order 2 for positions and velocities, with or without drag.
//! - Cost: 2 force evaluations per step.
//! - Stability: the same amplification factor as the midpoint method on linear
//!   problems: slow energy growth on the undamped oscillator, `h b <= 2` on drag.

use crate::chunks::for_each_chunk;
use crate::integrator::{Integrator, MethodInfo, StepError, StepStats, check_step, fit};
use crate::system::System;
use crate::vector::{Vector, c};

/// Registry entry.
pub const INFO: MethodInfo = MethodInfo {
    name: "heun",
    aliases: &["improved_euler", "explicit_trapezoidal"],
    title: "Improved Euler (Heun)",
    notes: "improved Euler, as the lecture writes it",
    order: 2,
    order_velocity: 2,
    order_velocity_forces: 2,
    evaluations: 2,
    ..MethodInfo::EXPLICIT
};

/// Improved Euler (Heun). See the [module documentation](self).
#[derive(Debug, Clone, Default)]
pub struct Heun<V: Vector> {
    accel: Vec<V>,
    end_x: Vec<V>,
    v1: Vec<V>,
}

impl<V: Vector> Heun<V> {
    /// A new Heun integrator.
    #[must_use]
    pub fn new() -> Self {
        Self {
            accel: Vec::new(),
            end_x: Vec::new(),
            v1: Vec::new(),
        }
    }
}

impl<V: Vector> Integrator<V> for Heun<V> {
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
        let half = dt * c(0.5);
        let Self { accel, end_x, v1 } = self;
        for_each_chunk(x, v, system, |x, v, system| {
            let n = x.len();
            fit(accel, n);
            fit(end_x, n);
            fit(v1, n);
            system.acceleration(t, x, v, accel);
            for i in 0..n {
                end_x[i] = x[i] + v[i] * dt;
                v1[i] = v[i] + accel[i] * dt;
            }
            system.acceleration(t + dt, end_x, v1, accel);
            for i in 0..n {
                let v2 = v[i] + accel[i] * dt;
                x[i] += (v[i] + v1[i]) * half;
                v[i] = (v1[i] + v2) * c(0.5);
            }
        });
        Ok(StepStats::single(2))
    }
}

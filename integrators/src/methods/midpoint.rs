//! The explicit midpoint method: the lecture's half step to estimate the
//! tangent in mid-interval, applied from the start across the whole step.
//!
//! ```text
//! x_m = x + h/2 v,   v_m = v + h/2 a(t, x, v)
//! x(t + h) = x + h v_m
//! v(t + h) = v + h a(t + h/2, x_m, v_m)
//! ```
//!
//! - Order 2 for positions and velocities, with or without drag.
//! - Cost: 2 force evaluations per step.
//! - Stability: on the undamped oscillator the squared amplification factor is
//!   `1 + (h omega)^4 / 4`, so energy creeps up by that factor every step, for
//!   every `h`; on linear drag stable for `h b <= 2`.

use crate::chunks::for_each_chunk;
use crate::integrator::{Integrator, MethodInfo, StepError, StepStats, check_step, fit};
use crate::system::System;
use crate::vector::{Vector, c};

/// Registry entry.
pub const INFO: MethodInfo = MethodInfo {
    name: "midpoint",
    aliases: &["explicit_midpoint", "rk2"],
    title: "Midpoint",
    notes: "",
    order: 2,
    order_velocity: 2,
    order_velocity_forces: 2,
    evaluations: 2,
    ..MethodInfo::EXPLICIT
};

/// Explicit midpoint. See the [module documentation](self).
#[derive(Debug, Clone, Default)]
pub struct Midpoint<V: Vector> {
    accel: Vec<V>,
    mid_x: Vec<V>,
    mid_v: Vec<V>,
}

impl<V: Vector> Midpoint<V> {
    /// A new midpoint integrator.
    #[must_use]
    pub fn new() -> Self {
        Self {
            accel: Vec::new(),
            mid_x: Vec::new(),
            mid_v: Vec::new(),
        }
    }
}

impl<V: Vector> Integrator<V> for Midpoint<V> {
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
        let Self { accel, mid_x, mid_v } = self;
        for_each_chunk(x, v, system, |x, v, system| {
            let n = x.len();
            fit(accel, n);
            fit(mid_x, n);
            fit(mid_v, n);
            system.acceleration(t, x, v, accel);
            for i in 0..n {
                mid_x[i] = x[i] + v[i] * half;
                mid_v[i] = v[i] + accel[i] * half;
            }
            system.acceleration(t + half, mid_x, mid_v, accel);
            for i in 0..n {
                x[i] += mid_v[i] * dt;
                v[i] += accel[i] * dt;
            }
        });
        Ok(StepStats::single(2))
    }
}

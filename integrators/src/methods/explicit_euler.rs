//! Explicit (forward) Euler: both updates use the state at the start of the step.
//!
//! ```text
//! v(t + h) = v(t) + h a(t, x, v)
//! x(t + h) = x(t) + h v(t)
//! ```
//!
//! - Order 1 for positions and velocities.
//! - Cost: 1 force evaluation per step.
//! - Stability: unstable for every `h` on the undamped oscillator (the energy
//!   grows by the factor `1 + (h omega)^2` per step); on linear drag `b` it is
//!   stable only for `h b <= 2`. The lecture's baseline, kept to show why games
//!   avoid it.

use crate::chunks::for_each_chunk;
use crate::integrator::{Integrator, MethodInfo, StepError, StepStats, check_step, fit};
use crate::system::System;
use crate::vector::Vector;

/// Registry entry.
pub const INFO: MethodInfo = MethodInfo {
    name: "explicit_euler",
    aliases: &["euler", "forward_euler"],
    title: "Explicit Euler",
    notes: "the lecture's baseline; unstable on any undamped oscillator",
    order: 1,
    order_velocity: 1,
    order_velocity_forces: 1,
    evaluations: 1,
    ..MethodInfo::EXPLICIT
};

/// Explicit Euler. See the [module documentation](self).
#[derive(Debug, Clone, Default)]
pub struct ExplicitEuler<V: Vector> {
    accel: Vec<V>,
}

impl<V: Vector> ExplicitEuler<V> {
    /// A new explicit Euler integrator.
    #[must_use]
    pub fn new() -> Self {
        Self { accel: Vec::new() }
    }
}

impl<V: Vector> Integrator<V> for ExplicitEuler<V> {
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
        let accel = &mut self.accel;
        for_each_chunk(x, v, system, |x, v, system| {
            fit(accel, x.len());
            system.acceleration(t, x, v, accel);
            for ((x, v), a) in x.iter_mut().zip(v.iter_mut()).zip(accel.iter()) {
                *x += *v * dt;
                *v += *a * dt;
            }
        });
        Ok(StepStats::single(1))
    }
}

//! Forward Euler on orientations, renormalised: the lecture's angular update.
//!
//! ```text
//! q(t + h) = normalize(q + h/2 (0, w) q)
//! w(t + h) = w + h dw/dt(q, w)            (Euler's equations, world frame)
//! ```
//!
//! - Order 1.
//! - Cost: 1 torque evaluation per step.
//! - Stability: the unnormalised update grows the norm by `sqrt(1 + (h|w|/2)^2)`
//!   every step, which renormalising removes; the rotation angle per step is
//!   then slightly less than `h |w|`. Kinetic energy of a free top drifts.

use super::{
    AngularIntegrator, AngularMethodInfo, Bodies, Rotation, Torque, angular_acceleration, check_bodies,
    orientation_rate,
};
use crate::integrator::{StepError, fit};
use crate::vector::Vector;

/// Registry entry.
pub const INFO: AngularMethodInfo = AngularMethodInfo {
    name: "quaternion_euler",
    aliases: &["quat_euler", "renormalized_euler"],
    title: "Quaternion Euler, renormalised",
    order: 1,
    evaluations: 1,
};

/// Forward Euler with renormalisation. See the [module documentation](self).
#[derive(Debug, Clone, Default)]
pub struct QuaternionEuler<Q: Rotation> {
    torque: Vec<Q::Vector>,
}

impl<Q: Rotation> QuaternionEuler<Q> {
    /// A new quaternion Euler integrator.
    #[must_use]
    pub fn new() -> Self {
        Self { torque: Vec::new() }
    }
}

impl<Q: Rotation> AngularIntegrator<Q> for QuaternionEuler<Q> {
    fn info(&self) -> AngularMethodInfo {
        INFO
    }

    fn step(
        &mut self,
        t: <Q::Vector as Vector>::Real,
        dt: <Q::Vector as Vector>::Real,
        bodies: Bodies<'_, Q>,
        torque: &mut dyn Torque<Q>,
    ) -> Result<(), StepError> {
        check_bodies(INFO.name, dt, &bodies)?;
        fit(&mut self.torque, bodies.orientations.len());
        torque.torque(t, bodies.orientations, bodies.angular_velocities, &mut self.torque);
        for i in 0..bodies.orientations.len() {
            let (q, w) = (bodies.orientations[i], bodies.angular_velocities[i]);
            let alpha = angular_acceleration(q, w, bodies.inertia[i], self.torque[i]);
            bodies.orientations[i] = (q + orientation_rate(q, w).scaled(dt)).normalized();
            bodies.angular_velocities[i] = w + alpha * dt;
        }
        Ok(())
    }
}

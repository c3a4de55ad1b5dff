//! Classical RK4 on orientation and angular velocity together, renormalised.
//!
//! ```text
//! y = (q, w),   y' = (1/2 (0, w) q,  dw/dt(q, w))
//! k1..k4 as in the linear RK4; y(t + h) = y + h/6 (k1 + 2 k2 + 2 k3 + k4)
//! q(t + h) <- normalize(q(t + h))
//! ```
//!
//! The stage quaternions `q + c h k` are not unit length (their norm is
//! `1 + O(h^2)`). The orientation rate `1/2 (0, w) q` is linear in `q` and is
//! evaluated on the stage quaternion as it is, but the angular acceleration
//! and the torque see the stage's *rotation*, `q / |q|`: rotating a vector by
//! a quaternion that is not unit length scales and distorts it, and feeding
//! that to Euler's equations made the method about 5 times less accurate
//! (order 4 kept, so only a comparison at fixed `h` shows it). RK4 does not
//! keep the norm of the result either (its error is `O(h^5)` per step), so
//! the end orientation is renormalised, which does not lower the order.
//!
//! - Order 4 for orientation and angular velocity.
//! - Cost: 4 torque evaluations per step.
//! - Stability: energy and angular momentum of a free top are conserved to
//!   `O(h^4)`, drifting very slowly over long runs.

use super::{
    AngularIntegrator, AngularMethodInfo, Bodies, Rotation, Torque, angular_acceleration, check_bodies,
    orientation_rate,
};
use crate::integrator::{StepError, fit};
use crate::vector::{Real, Vector};

/// Registry entry.
pub const INFO: AngularMethodInfo = AngularMethodInfo {
    name: "angular_rk4",
    aliases: &["rk4_angular", "quaternion_rk4"],
    title: "RK4 on quaternions, renormalised",
    order: 4,
    evaluations: 4,
};

/// RK4 for orientations. See the [module documentation](self).
#[derive(Debug, Clone)]
pub struct AngularRk4<Q: Rotation> {
    trial_q: Vec<Q>,
    /// `trial_q` normalised: the rotation the torque and Euler's equations see.
    trial_rotation: Vec<Q>,
    trial_w: Vec<Q::Vector>,
    sum_q: Vec<Q>,
    sum_w: Vec<Q::Vector>,
    torque: Vec<Q::Vector>,
}

impl<Q: Rotation> Default for AngularRk4<Q> {
    fn default() -> Self {
        Self::new()
    }
}

impl<Q: Rotation> AngularRk4<Q> {
    /// A new angular RK4 integrator.
    #[must_use]
    pub fn new() -> Self {
        Self {
            trial_q: Vec::new(),
            trial_rotation: Vec::new(),
            trial_w: Vec::new(),
            sum_q: Vec::new(),
            sum_w: Vec::new(),
            torque: Vec::new(),
        }
    }
}

impl<Q: Rotation> AngularIntegrator<Q> for AngularRk4<Q> {
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
        let n = bodies.orientations.len();
        self.trial_q.resize(n, Q::IDENTITY);
        self.trial_rotation.resize(n, Q::IDENTITY);
        self.sum_q.resize(n, Q::IDENTITY);
        fit(&mut self.trial_w, n);
        fit(&mut self.sum_w, n);
        fit(&mut self.torque, n);
        let r = <<Q::Vector as Vector>::Real as Real>::from_f64;
        self.trial_q.copy_from_slice(bodies.orientations);
        self.trial_rotation.copy_from_slice(bodies.orientations);
        self.trial_w.copy_from_slice(bodies.angular_velocities);
        // Stage s: evaluate at the trial state; weight 1, 2, 2, 1; next trial offset h/2, h/2, h.
        for (stage, (weight, offset)) in [(1.0, 0.5), (2.0, 0.5), (2.0, 1.0), (1.0, 0.0)].into_iter().enumerate() {
            let t_stage = t + dt * r([0.0, 0.5, 0.5, 1.0][stage]);
            torque.torque(t_stage, &self.trial_rotation, &self.trial_w, &mut self.torque);
            for i in 0..n {
                let (q, w) = (self.trial_q[i], self.trial_w[i]);
                let dq = orientation_rate(q, w);
                let dw = angular_acceleration(self.trial_rotation[i], w, bodies.inertia[i], self.torque[i]);
                if stage == 0 {
                    self.sum_q[i] = dq;
                    self.sum_w[i] = dw;
                } else {
                    self.sum_q[i] = self.sum_q[i] + dq.scaled(r(weight));
                    self.sum_w[i] += dw * r(weight);
                }
                if stage < 3 {
                    let step = dt * r(offset);
                    self.trial_q[i] = bodies.orientations[i] + dq.scaled(step);
                    self.trial_rotation[i] = self.trial_q[i].normalized();
                    self.trial_w[i] = bodies.angular_velocities[i] + dw * step;
                }
            }
        }
        let sixth = dt * r(1.0 / 6.0);
        for i in 0..n {
            bodies.orientations[i] = (bodies.orientations[i] + self.sum_q[i].scaled(sixth)).normalized();
            bodies.angular_velocities[i] += self.sum_w[i] * sixth;
        }
        Ok(())
    }
}

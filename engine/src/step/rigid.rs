//! Rigid bodies: orientations and angular velocities, after the particles.

use tickwork_integrators::angular::{Bodies, TorqueFree};

use super::{NonFiniteCause, SimulationError};
use crate::world::World;

impl World {
    pub(super) fn step_rigid_bodies(&mut self, t: f32, dt: f32, tick: u64) -> Result<(), SimulationError> {
        if self.rigid.is_empty() {
            return Ok(());
        }
        let r = &mut self.rigid;
        r.previous_orientation.copy_from_slice(&r.orientation);
        let bodies = Bodies {
            orientations: &mut r.orientation,
            angular_velocities: &mut r.angular_velocity,
            inertia: &r.inertia,
        };
        self.angular
            .step(t, dt, bodies, &mut TorqueFree)
            .map_err(|error| SimulationError::Integrator { tick, error })?;
        if let Some(k) = r
            .orientation
            .iter()
            .zip(&r.angular_velocity)
            .position(|(q, w)| !q.is_finite() || !w.is_finite())
        {
            let row = r.owner[k] as usize;
            return Err(SimulationError::NonFinite {
                tick,
                entity: self.entities.rows()[row],
                field: "angular_velocity",
                value: r.angular_velocity[k],
                cause: NonFiniteCause::Step,
            });
        }
        Ok(())
    }
}

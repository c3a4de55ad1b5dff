//! Which particle and which cause made a step non-finite.

use glam::Vec3A;

use super::{NonFiniteCause, SimulationError};
use crate::forces::ForceField;
use crate::layout::Vec3Column;
use crate::world::World;

impl World {
    /// The error for row `row`'s non-finite position or velocity.
    pub(super) fn non_finite(&self, tick: u64, row: usize, cause: NonFiniteCause) -> SimulationError {
        let p = &self.particles;
        let (x, v) = (p.position.row(row), p.velocity.row(row));
        let (field, value) = if x.is_finite() {
            ("velocity", v)
        } else {
            ("position", x)
        };
        SimulationError::NonFinite {
            tick,
            entity: self.entities.rows()[row],
            field,
            value: value.into(),
            cause,
        }
    }

    /// After a failed integrator step: the first particle whose state, or
    /// whose acceleration at that state, is not finite (so a NaN force is
    /// named, not reported as a solve that "did not converge"). Only on the
    /// error path, so its scratch buffer may allocate.
    pub(super) fn diagnose(&self, t: f32, tick: u64) -> Option<SimulationError> {
        let p = &self.particles;
        if let Some(row) = Vec3Column::first_non_finite(p.position.blocks(), p.velocity.blocks(), p.len(), 0) {
            return Some(self.non_finite(tick, row, NonFiniteCause::Start));
        }
        let (mut x, mut v) = (Vec::new(), Vec::new());
        p.position.gather_into(&mut x, false);
        p.velocity.gather_into(&mut v, false);
        let mut accelerations = vec![Vec3A::ZERO; p.len()];
        let mut field = ForceField::new(&self.forces, &p.inverse_mass, 0);
        tickwork_integrators::System::acceleration(&mut field, t, &x, &v, &mut accelerations);
        let row = accelerations.iter().position(|a| !a.is_finite())?;
        Some(SimulationError::NonFinite {
            tick,
            entity: self.entities.rows()[row],
            field: "acceleration",
            value: accelerations[row].into(),
            cause: NonFiniteCause::Force,
        })
    }
}

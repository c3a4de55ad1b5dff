//! Energy bookkeeping for diagnostics: how well a method conserves what it should.

use glam::Vec3;
use tickwork_integrators::angular::rotational_energy;

use crate::SimulationError;
use crate::forces::mass_of;
use crate::world::World;

/// The world's mechanical energy, in joules (f64 sums of f32 state).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Energy {
    /// Translational `sum m v^2 / 2` plus rotational `sum w . I w / 2`.
    pub kinetic: f64,
    /// Sum of the conservative forces' potentials (gravity, springs,
    /// attractors, n-body); drag and wind have none.
    pub potential: f64,
}

impl Energy {
    /// Kinetic plus potential.
    #[must_use]
    pub fn total(&self) -> f64 {
        self.kinetic + self.potential
    }
}

impl World {
    /// The energy now. Takes `&mut self` because spring forces refresh their
    /// entity rows first.
    ///
    /// # Errors
    /// [`SimulationError::PairLimit`] where a force's potential would visit
    /// more pairs of particles than
    /// [`WorldConfig::max_pairs`](crate::WorldConfig) allows (n-body among
    /// too many particles): refused before any pair is visited, as the step
    /// refuses that force.
    pub fn energy(&mut self) -> Result<Energy, SimulationError> {
        self.check_force_pairs(self.tick())?;
        for force in &mut self.forces {
            force.prepare(&self.entities);
        }
        let p = &self.particles;
        p.position.gather_into(&mut self.gathered.x, false);
        let mut kinetic: f64 = p
            .velocity
            .iter()
            .zip(&p.inverse_mass)
            .map(|(v, &w)| 0.5 * mass_of(w) * Vec3::from(v).as_dvec3().length_squared())
            .sum();
        let r = &self.rigid;
        for ((q, w), inertia) in r.orientation.iter().zip(&r.angular_velocity).zip(&r.inertia) {
            kinetic += f64::from(rotational_energy(*q, *w, *inertia));
        }
        let potential = self
            .forces
            .iter()
            .map(|f| f.potential_energy(&self.gathered.x, &p.inverse_mass))
            .sum();
        Ok(Energy { kinetic, potential })
    }
}

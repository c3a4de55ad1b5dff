//! What moves the world's particles: its forces, its emitters and its
//! integrators (linear and angular), added, switched and inspected.

use glam::{Quat, Vec3A};
use tickwork_integrators::angular::{AngularIntegrator, build_angular};
use tickwork_integrators::{Integrator, UnknownMethod, build};

use super::{SpawnError, World};
use crate::emitter::Emitter;
use crate::forces::Force;

impl World {
    /// Adds a force generator.
    pub fn add_force(&mut self, force: impl Force + 'static) {
        self.forces.push(Box::new(force));
    }

    /// The force generators, to inspect, change or remove.
    pub fn forces_mut(&mut self) -> &mut Vec<Box<dyn Force>> {
        &mut self.forces
    }

    /// The force generators.
    #[must_use]
    pub fn forces(&self) -> &[Box<dyn Force>] {
        &self.forces
    }

    /// The first force of type `T`, to change between steps without
    /// replacing it (a game's thrust, a wind gust).
    pub fn force_mut<T: Force + 'static>(&mut self) -> Option<&mut T> {
        self.forces.iter_mut().find_map(|f| f.as_any_mut().downcast_mut::<T>())
    }

    /// Adds an emitter.
    ///
    /// # Errors
    /// [`SpawnError`] naming the invalid setting; nothing is added.
    pub fn add_emitter(&mut self, emitter: Emitter) -> Result<(), SpawnError> {
        emitter.validate()?;
        self.emitters.push(emitter);
        Ok(())
    }

    /// The emitters, to move or change (particles from an emitter changed to
    /// an invalid setting are refused at the step with an error).
    pub fn emitters_mut(&mut self) -> &mut Vec<Emitter> {
        &mut self.emitters
    }

    /// Switches the integrator by name. History starts afresh: multi-step
    /// methods bootstrap again.
    ///
    /// # Errors
    /// [`UnknownMethod`] listing the valid names; the integrator is unchanged.
    pub fn set_integrator(&mut self, name: &str) -> Result<(), UnknownMethod> {
        self.integrator = build::<Vec3A>(name)?;
        self.lanes.clear();
        self.config.integrator = self.integrator.info().name.to_owned();
        Ok(())
    }

    /// The integrator in use.
    #[must_use]
    pub fn integrator(&self) -> &dyn Integrator<Vec3A> {
        self.integrator.as_ref()
    }

    /// Switches the angular integrator by name.
    ///
    /// # Errors
    /// [`UnknownMethod`] listing the valid names; the method is unchanged.
    pub fn set_angular_integrator(&mut self, name: &str) -> Result<(), UnknownMethod> {
        self.angular = build_angular::<Quat>(name)?;
        self.config.angular_integrator = self.angular.info().name.to_owned();
        Ok(())
    }

    /// The angular integrator in use.
    #[must_use]
    pub fn angular_integrator(&self) -> &dyn AngularIntegrator<Quat> {
        self.angular.as_ref()
    }
}

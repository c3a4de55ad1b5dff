//! 2D headings and visibility: an entity's angle about the z axis and how
//! fast it turns, stepped by the world and interpolated when drawn (a
//! ship's nose, a rock's spin), and whether its particle is drawn (a
//! collision proxy, a ship between lives).
//!
//! ```text
//! each step:   previous = angle,  angle = angle + spin dt   (both then moved
//!              by the same multiple of 2 pi, so angle stays in [-pi, pi))
//! drawn at alpha:  previous + alpha (angle - previous)
//! ```
//!
//! Both live in columns the world adds when first asked (`set_heading`,
//! `set_visible`), so worlds without them cost and hash as before.

use core::f32::consts::{PI, TAU};

use super::{Entity, SpawnError, World, WorldError};

/// A 2D entity's heading: its angle about the z axis (radians,
/// counter-clockwise from +x) and its spin (radians per second).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Heading {
    /// Angle in radians, in `[-pi, pi)` after each step.
    pub angle: f32,
    /// Turning rate in radians per second (counter-clockwise positive).
    pub spin: f32,
    /// The angle at the start of the last step, unwrapped so that
    /// interpolating from it to `angle` turns the short way the spin went.
    previous: f32,
}

impl Heading {
    /// A heading at `angle`, turning at `spin` (its previous angle is
    /// `angle`: set as by a teleport, not swept from the old one).
    #[must_use]
    pub fn new(angle: f32, spin: f32) -> Self {
        Self {
            angle,
            spin,
            previous: angle,
        }
    }

    /// The angle a frame `alpha` of the way from the last step's start to
    /// its end shows (not wrapped: `sin` and `cos` of it are what a game
    /// draws with).
    #[must_use]
    pub fn interpolated(&self, alpha: f32) -> f32 {
        self.previous + (self.angle - self.previous) * alpha
    }

    /// The unit vector the heading points along (`(cos, sin)` of the
    /// angle, the same bits on every platform).
    #[must_use]
    pub fn direction(&self) -> glam::Vec2 {
        glam::Vec2::new(crate::math::cos(self.angle), crate::math::sin(self.angle))
    }

    /// One step of `dt` seconds.
    fn turn(&mut self, dt: f32) {
        let turned = self.angle + self.spin * dt;
        // Back into [-pi, pi), the previous angle by the same amount.
        let wraps = ((turned + PI) / TAU).floor();
        self.previous = self.angle - wraps * TAU;
        self.angle = turned - wraps * TAU;
    }
}

/// Whether a particle is left out of drawing (default false: drawn).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Hidden(pub bool);

impl World {
    /// Whether any entity has a heading (what the GPU step refuses).
    #[cfg(feature = "render")]
    pub(crate) fn has_headings(&self) -> bool {
        self.columns.get::<Heading>().is_some()
    }

    /// Sets `entity`'s heading (a ship's nose, a rock's spin), stepped from
    /// the next step on. The first call adds a heading column to the world
    /// (every other entity gets `Heading::default()`: angle 0, no spin).
    ///
    /// # Errors
    /// [`WorldError`] for a dead handle, or an angle or spin that is not
    /// finite (naming the field).
    pub fn set_heading(&mut self, entity: Entity, heading: Heading) -> Result<(), WorldError> {
        self.row(entity)?;
        for (field, value) in [("heading.angle", heading.angle), ("heading.spin", heading.spin)] {
            if !value.is_finite() {
                return Err(WorldError::Invalid {
                    entity,
                    error: SpawnError::invalid(field, value, "a finite number"),
                });
            }
        }
        self.register::<Heading>();
        self.insert(entity, heading)
    }

    /// `entity`'s heading (angle 0, no spin for an entity never given one).
    ///
    /// # Errors
    /// [`WorldError`] for a dead handle.
    pub fn heading(&self, entity: Entity) -> Result<Heading, WorldError> {
        let row = self.row(entity)?;
        Ok(self.columns.get::<Heading>().map_or_else(Heading::default, |c| c[row]))
    }

    /// Whether `entity`'s particle is drawn (default true). The first call
    /// adds a visibility column to the world.
    ///
    /// # Errors
    /// [`WorldError`] for a dead handle.
    pub fn set_visible(&mut self, entity: Entity, visible: bool) -> Result<(), WorldError> {
        self.row(entity)?;
        self.register::<Hidden>();
        self.insert(entity, Hidden(!visible))?;
        // Drawn differently: the renderer uploads again.
        self.revision += 1;
        Ok(())
    }

    /// Whether `entity`'s particle is drawn.
    ///
    /// # Errors
    /// [`WorldError`] for a dead handle.
    pub fn is_visible(&self, entity: Entity) -> Result<bool, WorldError> {
        let row = self.row(entity)?;
        Ok(!self.columns.get::<Hidden>().is_some_and(|c| c[row].0))
    }

    /// The rows left out of drawing, if any entity was ever hidden.
    pub(crate) fn hidden_rows(&self) -> Option<&[Hidden]> {
        self.columns.get::<Hidden>().map(Vec::as_slice)
    }

    /// Turns every heading by its spin over a step of `dt` seconds.
    pub(crate) fn turn_headings(&mut self, dt: f32) {
        if let Some(headings) = self.columns.get_mut::<Heading>() {
            for heading in headings {
                heading.turn(dt);
            }
        }
    }

    /// The headings and visibility, for the state hash: `None` where the
    /// world has neither (so its hash is what it was without them).
    pub(crate) fn heading_state(&self) -> Option<(&[Heading], &[Hidden])> {
        let headings = self.columns.get::<Heading>().map(Vec::as_slice);
        let hidden = self.hidden_rows();
        (headings.is_some() || hidden.is_some()).then(|| (headings.unwrap_or_default(), hidden.unwrap_or_default()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_heading_wraps_and_interpolates_the_way_it_turned() {
        let mut h = Heading::new(3.0, 2.0);
        h.turn(0.1);
        // 3.2 rad is past pi: wrapped to 3.2 - 2 pi, the previous with it.
        assert!((h.angle - (3.2 - TAU)).abs() < 1e-5, "{}", h.angle);
        assert!((h.interpolated(0.0) - (3.0 - TAU)).abs() < 1e-5);
        assert!(
            (h.interpolated(0.5) - (3.1 - TAU)).abs() < 1e-5,
            "halfway, the short way"
        );
        assert!((-PI..PI).contains(&h.angle));
        // A teleport: no sweep from the old angle.
        let set = Heading::new(1.0, 0.0);
        assert_eq!(set.interpolated(0.3), 1.0);
    }
}

//! Emitters: sources that spawn particles at a steady rate.

use glam::{Quat, Vec3};
use rand::RngExt;
use rand_pcg::Pcg32;

use crate::layout::{Colour, Particle, SpawnError};
use crate::math;

/// Spawns `rate` particles per second from a point, in a cone around
/// `direction`, with the world's seeded generator (so runs are reproducible).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Emitter {
    /// Where particles appear.
    pub position: Vec3,
    /// Axis of the cone of launch directions (normalised on use; default: `+y`).
    pub direction: Vec3,
    /// Half-angle of the cone, radians (default: `0.3`).
    pub spread: f32,
    /// Launch speed, m/s (default: `5.0`).
    pub speed: f32,
    /// Relative random variation of the speed, in `[0, 1]` (default: `0.2`).
    pub speed_jitter: f32,
    /// Particles per second (default: `100.0`).
    pub rate: f32,
    /// Seconds each particle lives (default: `3.0`).
    pub lifetime: f32,
    /// Colour of the particles (default: a warm orange).
    pub colour: Colour,
    /// Radius of the particles, m (default: `0.03`).
    pub radius: f32,
    /// Mass of the particles, kg (default: `0.01`).
    pub mass: f32,
    /// Fraction of a particle owed from previous steps, in `[0, 1)` (state,
    /// kept so a rate of 90/s at 60 Hz alternates 1 and 2 particles; default: `0.0`).
    pub owed: f32,
}

impl Default for Emitter {
    fn default() -> Self {
        Self {
            position: Vec3::ZERO,
            direction: Vec3::Y,
            spread: 0.3,
            speed: 5.0,
            speed_jitter: 0.2,
            rate: 100.0,
            lifetime: 3.0,
            colour: [255, 160, 60, 255],
            radius: 0.03,
            mass: 0.01,
            owed: 0.0,
        }
    }
}

impl Emitter {
    /// Checks every setting.
    ///
    /// # Errors
    /// [`SpawnError`] naming the field (`emitter.rate`, ...): non-finite
    /// vectors, a negative or non-finite rate, speed, spread or radius, a
    /// jitter outside `[0, 1]`, a lifetime or mass that is not above zero,
    /// an `owed` outside `[0, 1)`.
    pub fn validate(&self) -> Result<(), SpawnError> {
        let check = |field: &'static str, value: f32, ok: bool, expected: &'static str| {
            if ok {
                Ok(())
            } else {
                Err(SpawnError::invalid(field, value, expected))
            }
        };
        for (field, v) in [
            ("emitter.position", self.position),
            ("emitter.direction", self.direction),
        ] {
            for value in v.to_array() {
                check(field, value, value.is_finite(), "finite coordinates")?;
            }
        }
        // A zero (or overflowing) direction once became +y silently.
        check(
            "emitter.direction",
            self.direction.length(),
            self.direction.try_normalize().is_some(),
            "a direction of non-zero, finite length",
        )?;
        let non_negative = |v: f32| v.is_finite() && v >= 0.0;
        let positive = |v: f32| v.is_finite() && v > 0.0;
        check(
            "emitter.rate",
            self.rate,
            non_negative(self.rate),
            "particles per second, finite, not negative",
        )?;
        check(
            "emitter.speed",
            self.speed,
            non_negative(self.speed),
            "a finite speed, not negative",
        )?;
        check(
            "emitter.spread",
            self.spread,
            non_negative(self.spread),
            "a finite angle, not negative",
        )?;
        check(
            "emitter.speed_jitter",
            self.speed_jitter,
            (0.0..=1.0).contains(&self.speed_jitter),
            "0 to 1",
        )?;
        // The fastest particle, speed (1 + jitter), must be finite too (a
        // speed of 3e38 once gave infinite velocities).
        check(
            "emitter.speed",
            self.speed,
            (self.speed * (1.0 + self.speed_jitter)).is_finite(),
            "a speed whose jittered maximum, speed (1 + speed_jitter), is finite",
        )?;
        check(
            "emitter.lifetime",
            self.lifetime,
            positive(self.lifetime),
            "finite seconds above zero",
        )?;
        check(
            "emitter.mass",
            self.mass,
            positive(self.mass),
            "a finite mass above zero",
        )?;
        check(
            "emitter.radius",
            self.radius,
            non_negative(self.radius),
            "a finite radius, not negative",
        )?;
        check(
            "emitter.owed",
            self.owed,
            (0.0..1.0).contains(&self.owed),
            "a fraction of a particle in [0, 1) (state the step keeps: leave it as the step left it)",
        )
    }

    /// The particles due in a step of `dt`: `rate * dt` plus what was owed,
    /// rounded down; the remainder is owed to the next step.
    pub(crate) fn due(&mut self, dt: f32) -> f32 {
        let whole = self.peek_due(dt);
        self.owed = (self.owed + self.rate * dt) - whole;
        whole
    }

    /// The whole particles [`due`](Self::due) would give, without taking them.
    pub(crate) fn peek_due(&self, dt: f32) -> f32 {
        (self.owed + self.rate * dt).floor()
    }

    /// One particle with a random direction in the cone (uniform over the
    /// cap's solid angle) and a jittered speed.
    pub(crate) fn particle(&self, rng: &mut Pcg32) -> Particle {
        let axis = self.direction.try_normalize().unwrap_or(Vec3::Y);
        let cos_max = math::cos(self.spread);
        let cos_theta = 1.0 - rng.random::<f32>() * (1.0 - cos_max);
        let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
        let phi = rng.random::<f32>() * core::f32::consts::TAU;
        let local = Vec3::new(sin_theta * math::cos(phi), cos_theta, sin_theta * math::sin(phi));
        let direction = Quat::from_rotation_arc(Vec3::Y, axis) * local;
        let speed = self.speed * (1.0 + self.speed_jitter * (2.0 * rng.random::<f32>() - 1.0));
        Particle {
            position: self.position,
            velocity: direction * speed,
            mass: self.mass,
            immovable: false,
            radius: self.radius,
            colour: self.colour,
            lifetime: Some(self.lifetime),
        }
    }
}

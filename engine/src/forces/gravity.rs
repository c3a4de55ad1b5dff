//! Uniform gravity: `a = g` for every movable particle.

use glam::{Vec3, Vec3A};

use super::{Force, mass_of};

/// A uniform gravitational field.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gravity {
    /// The acceleration, m/s^2 (default: Earth's, `(0, -9.81, 0)`).
    pub acceleration: Vec3,
}

impl Gravity {
    /// Earth's gravity along -y.
    pub const EARTH: Self = Self {
        acceleration: Vec3::new(0.0, -9.81, 0.0),
    };
}

impl Default for Gravity {
    /// [`Gravity::EARTH`].
    fn default() -> Self {
        Self::EARTH
    }
}

impl Force for Gravity {
    fn name(&self) -> &'static str {
        "gravity"
    }

    fn affine_in_velocity(&self) -> Option<(Vec3A, f32)> {
        Some((self.acceleration.into(), 0.0))
    }

    fn accumulate(&self, _t: f32, _first: usize, _x: &[Vec3A], _v: &[Vec3A], _w: &[f32], out: &mut [Vec3A]) {
        let g = Vec3A::from(self.acceleration);
        for a in out {
            *a += g;
        }
    }

    /// `U = -sum m g . x`.
    fn potential_energy(&self, x: &[Vec3A], inverse_mass: &[f32]) -> f64 {
        let g = self.acceleration.as_dvec3();
        x.iter()
            .zip(inverse_mass)
            .map(|(x, &w)| -mass_of(w) * g.dot(Vec3::from(*x).as_dvec3()))
            .sum()
    }
}

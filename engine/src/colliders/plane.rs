//! An infinite plane: particles stay on the side its normal points to.

use glam::{Vec3, Vec3A};

use super::contact::{Material, resolve};
use super::{Collider, ContactColumns};

/// The half-space `n . x >= offset` is free; a particle of radius `r` touches
/// the plane when `n . x - offset - r < 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// Unit normal pointing into the free side (a floor: `(0, 1, 0)`).
    pub normal: Vec3,
    /// Signed distance of the plane from the origin along the normal.
    pub offset: f32,
    /// Bounce and friction.
    pub material: Material,
}

impl Plane {
    /// A floor at height `y`.
    #[must_use]
    pub fn floor(y: f32, material: Material) -> Self {
        Self {
            normal: Vec3::Y,
            offset: y,
            material,
        }
    }
}

impl Collider for Plane {
    fn name(&self) -> &'static str {
        "plane"
    }

    fn resolve_range(&self, c: ContactColumns<'_>) {
        let n = Vec3A::from(self.normal);
        for (((x, v), &r), &w) in c
            .position
            .iter_mut()
            .zip(c.velocity.iter_mut())
            .zip(c.radius)
            .zip(c.inverse_mass)
        {
            let gap = n.dot(*x) - self.offset - r;
            resolve(x, v, n, gap, w > 0.0, self.material);
        }
    }
}

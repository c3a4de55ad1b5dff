//! Contact events: which entity touched which collider or entity in the
//! last step, where, and how hard.
//!
//! A collider reports contacts once it is asked to
//! ([`World::report_contacts`](crate::World::report_contacts)); the others
//! keep their fast paths (a floor under a million particles has no use for a
//! million events a step). A pointwise collider's contacts are found by
//! comparing each particle's state before and after the collider ran, so
//! reporting changes no bit of the physics and every collider, a game's own
//! included, reports without writing a line for it:
//!
//! ```text
//! contact    <=>  x or v changed (bits)
//! normal  n  =  (x' - x) / |x' - x|      (or (v' - v) / |v' - v| if x' = x)
//! impulse J  =  m (v' - v) . n  =  ((v' - v) . n) / w       (w = 1/m)
//! point      =  x' - r n                 (the particle's surface, on the collider)
//! ```
//!
//! Sphere-sphere collisions report the pair instead ([`Touched::Entity`]).
//! The list is in a fixed order whatever the threads and the step's path:
//! by collider (in the order they were added), then by the entity's row,
//! then by the other entity's row.

use core::fmt;

use glam::{Vec3, Vec3A};

use crate::layout::Entity;

/// A collider's handle, from [`World::add_collider`](crate::World::add_collider):
/// stable while the collider is in its world (removing others does not
/// change it), never reused within that world.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ColliderId(pub(crate) u64);

impl ColliderId {
    /// A handle to no collider, for a game's fields before set-up (every
    /// lookup with it is an error naming it): also [`ColliderId::default`].
    pub const PLACEHOLDER: Self = Self(u64::MAX);
}

impl Default for ColliderId {
    fn default() -> Self {
        Self::PLACEHOLDER
    }
}

impl fmt::Display for ColliderId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "collider #{}", self.0)
    }
}

/// What an entity touched.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Touched {
    /// A collider (a plane, a box, a game's own).
    Collider(ColliderId),
    /// Another entity (sphere-sphere collisions), reported once per pair
    /// with the lower row as [`Contact::entity`].
    Entity(Entity),
}

/// One contact of the last step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// The entity that was moved or bounced.
    pub entity: Entity,
    /// What it touched.
    pub touched: Touched,
    /// Where, on the entity's surface (world space, metres).
    pub point: Vec3,
    /// Unit normal of the contact, pointing towards `entity` (the way it
    /// was pushed).
    pub normal: Vec3,
    /// The normal impulse the entity received, `m dv . n`, in kg m/s: 0 for
    /// a particle pushed out without bouncing (resting), large for a fast hit.
    pub impulse: f32,
    /// When, as the fraction of the step in `[0, 1]`: the instant of
    /// contact for a collider that finds contacts inside the step
    /// ([`ContactRule::InStep`](super::ContactRule)), so an effect, a sound
    /// or a score lands where it happened; 1 (the step's end) for contacts
    /// found at the end of the step.
    pub fraction: f32,
}

/// A contact as the step finds it, by row and collider index: turned into a
/// [`Contact`] once the step knows every row's entity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct RowTouch {
    /// Index of the collider in the world's list.
    pub collider: u32,
    /// The row of the entity.
    pub row: u32,
    /// The other entity's row, or `u32::MAX` for the collider itself.
    pub other: u32,
    pub point: Vec3A,
    pub normal: Vec3A,
    pub impulse: f32,
    /// The fraction of the step it happened at (1: the end).
    pub fraction: f32,
    /// Its place among the row's contacts in the step: the in-step
    /// contacts count 1, 2, ...; one found at the end of the step is
    /// `u32::MAX`. With the instant it makes every key unique.
    pub event: u32,
}

impl RowTouch {
    /// The canonical order: collider, row, other row, instant (a fraction
    /// in `[0, 1]`, whose bits sort as it does), event.
    pub fn key(&self) -> (u32, u32, u32, u32, u32) {
        (self.collider, self.row, self.other, self.fraction.to_bits(), self.event)
    }
}

/// A pair contact reported by a collider that resolves pairs of particles
/// ([`Collider::resolve_world_reporting`](super::Collider::resolve_world_reporting)),
/// by row in the columns it was given.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairTouch {
    /// The row of one particle.
    pub a: usize,
    /// The row of the other.
    pub b: usize,
    /// The contact point (world space).
    pub point: Vec3A,
    /// Unit normal pointing towards `a`.
    pub normal: Vec3A,
    /// The normal impulse `a` received (kg m/s); `b` received its opposite.
    pub impulse: f32,
    /// When, as the fraction of the step (1: found at its end).
    pub fraction: f32,
}

/// Appends a touch for every row whose position or velocity a collider
/// changed (the formulas of the module docs). `first_row` is the global row
/// of row 0 of the slices.
#[allow(clippy::too_many_arguments)]
pub(crate) fn diff_touches(
    collider: u32,
    first_row: usize,
    before_x: &[Vec3A],
    before_v: &[Vec3A],
    x: &[Vec3A],
    v: &[Vec3A],
    radius: &[f32],
    inverse_mass: &[f32],
    out: &mut Vec<RowTouch>,
) {
    let bits = |a: Vec3A| a.to_array().map(f32::to_bits);
    for k in 0..x.len() {
        if bits(x[k]) == bits(before_x[k]) && bits(v[k]) == bits(before_v[k]) {
            continue;
        }
        let (dx, dv) = (x[k] - before_x[k], v[k] - before_v[k]);
        let normal = dx.try_normalize().or_else(|| dv.try_normalize()).unwrap_or(Vec3A::ZERO);
        let w = inverse_mass[k];
        let impulse = if w > 0.0 { dv.dot(normal) / w } else { 0.0 };
        out.push(RowTouch {
            collider,
            row: (first_row + k) as u32,
            other: u32::MAX,
            point: x[k] - normal * radius[k],
            normal,
            impulse,
            fraction: 1.0,
            event: u32::MAX,
        });
    }
}

//! The particle columns (struct of arrays) and the lifetimes kept beside
//! them.

use glam::{Vec3, Vec3A};

use super::facts::ChunkFacts;
use crate::layout::{Colour, Particle, Vec3Column};

/// The particle columns: one `Vec` per field, all the same length, row `i`
/// of each belonging to the entity in row `i` of [`Entities`](super::Entities).
///
/// Hot columns (read or written by every step) come first and are kept small:
/// a [`Vec3Column`] for vectors (read and written by row), `f32` for scalars.
#[derive(Debug, Default, PartialEq)]
pub struct Particles {
    /// Positions now.
    pub position: Vec3Column,
    /// Velocities now.
    pub velocity: Vec3Column,
    /// Positions at the start of the last step, for interpolation.
    pub previous_position: Vec3Column,
    /// `1 / mass`; 0 = immovable.
    pub inverse_mass: Vec<f32>,
    /// Radius in metres.
    pub radius: Vec<f32>,
    /// The world's lived time (the sum of its steps, see
    /// [`World::age`](super::World::age)) when each particle spawned: its
    /// age is `lived - born`. A birth time rather than an age, so that a step
    /// need not touch every particle to age it.
    pub born: Vec<f64>,
    /// Seconds to live; `f32::INFINITY` = forever.
    pub lifetime: Vec<f32>,
    /// sRGB colour with alpha.
    pub colour: Vec<Colour>,
    /// The tick at which the particle was last teleported (`u64::MAX` = never),
    /// so interpolation and trails do not streak across the jump.
    pub teleported_at: Vec<u64>,
    /// Row in the rigid-body table, or `u32::MAX` for a plain particle.
    pub(crate) rigid_row: Vec<u32>,
    /// The lived time and the earliest death, for expiry without a pass.
    pub(crate) lifetimes: Lifetimes,
    /// What holds for whole chunks (all movable, all points), for the
    /// fused step's shorter kernels.
    pub(crate) facts: ChunkFacts,
}

/// The world's lived time and a lower bound on the next death.
///
/// A particle dies when `lived >= born + lifetime` (in f64, so hours of
/// game time keep sub-microsecond ages). `next_death` is at most the
/// smallest `born + lifetime` of the live particles: a spawn lowers it, a
/// despawn leaves it (still a lower bound), and only a step that reaches it
/// scans the particles (collecting the dead, recomputing the bound). Worlds
/// without lifetimes never scan; before this, every step aged every
/// particle (12 bytes read and written each, 10% of a step in cache).
///
/// A lifetime of a whole number of steps (3 s at 60 Hz) ends on that step
/// or the next, as the sums round (`born` and `lived` are sums of f64 `dt`s,
/// so which one depends on the spawn tick); the same run always gives the
/// same step. The old f32 age rounded too, the other way: 0.2 s lasted 12
/// steps at 60 Hz, 13 now (0.2 as f32 is 0.20000000298).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Lifetimes {
    /// Sum of the steps' `dt` since the world began, seconds.
    pub lived: f64,
    /// No live particle dies before this (`-inf`: unknown, scan at the next step).
    pub next_death: f64,
}

impl Default for Lifetimes {
    fn default() -> Self {
        Self {
            lived: 0.0,
            next_death: f64::INFINITY,
        }
    }
}

/// Only the lived time is state; the bound depends on the world's history.
impl PartialEq for Lifetimes {
    fn eq(&self, other: &Self) -> bool {
        self.lived.to_bits() == other.lived.to_bits()
    }
}

impl Particles {
    /// Where row `row` is at `t` steps past the previous one, by
    /// [`lerp`](crate::interpolation::lerp) (the vertex shader's default
    /// formula), for a game that draws a particle's position itself (the
    /// renderer's own CPU-side lines go through
    /// [`Interpolation::position`](crate::interpolation::Interpolation::position),
    /// which follows its mode).
    #[must_use]
    pub fn interpolated(&self, row: usize, t: f32) -> Vec3 {
        let (from, to) = (self.previous_position.row(row), self.position.row(row));
        crate::interpolation::lerp(from.into(), to.into(), t)
    }

    /// Number of rows.
    #[must_use]
    pub fn len(&self) -> usize {
        self.position.len()
    }

    /// Whether there are no rows.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }

    /// Adds `dt` to the lived time; if that reaches the next death, appends
    /// the rows whose lifetime ran out (`lived >= born + lifetime`, rows
    /// ascending) to `expired` and recomputes the bound from the others.
    /// A NaN lifetime (written through `particles_mut`) never expires.
    pub(crate) fn age(&mut self, dt: f64, expired: &mut Vec<u32>) {
        let l = &mut self.lifetimes;
        l.lived += dt;
        if l.lived < l.next_death {
            return;
        }
        let mut next_death = f64::INFINITY;
        for (row, (&born, &lifetime)) in self.born.iter().zip(&self.lifetime).enumerate() {
            let death = born + f64::from(lifetime);
            if l.lived >= death {
                expired.push(row as u32);
            } else {
                next_death = next_death.min(death);
            }
        }
        l.next_death = next_death;
    }

    /// Seconds since row `row` spawned.
    pub(crate) fn age_of(&self, row: usize) -> f32 {
        (self.lifetimes.lived - self.born[row]) as f32
    }

    /// After an edit through `particles_mut` (lifetimes, masses, radii may
    /// have changed): the next step rescans lifetimes and chunk facts.
    pub(crate) fn forget_derived(&mut self) {
        self.lifetimes.next_death = f64::NEG_INFINITY;
        self.facts.touch(0);
    }

    pub(crate) fn push(&mut self, p: &Particle) {
        let x = Vec3A::from(p.position);
        self.position.push(x);
        self.velocity.push(Vec3A::from(p.velocity));
        self.previous_position.push(x);
        self.inverse_mass.push(p.inverse_mass());
        self.radius.push(p.radius);
        let lifetime = p.lifetime.unwrap_or(f32::INFINITY);
        let lived = self.lifetimes.lived;
        self.facts.touch(self.born.len());
        self.born.push(lived);
        self.lifetime.push(lifetime);
        let death = lived + f64::from(lifetime);
        self.lifetimes.next_death = self.lifetimes.next_death.min(death);
        self.colour.push(p.colour);
        self.teleported_at.push(u64::MAX);
        self.rigid_row.push(u32::MAX);
    }

    pub(crate) fn swap_remove(&mut self, row: usize) {
        self.position.swap_remove(row);
        self.velocity.swap_remove(row);
        self.previous_position.swap_remove(row);
        self.inverse_mass.swap_remove(row);
        self.radius.swap_remove(row);
        self.born.swap_remove(row);
        self.facts.touch(row);
        self.lifetime.swap_remove(row);
        self.colour.swap_remove(row);
        self.teleported_at.swap_remove(row);
        self.rigid_row.swap_remove(row);
    }
}

clone_fields!(Particles {
    position,
    velocity,
    previous_position,
    inverse_mass,
    radius,
    born,
    lifetime,
    colour,
    teleported_at,
    rigid_row,
    lifetimes,
    facts,
});

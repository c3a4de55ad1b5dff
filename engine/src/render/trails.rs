//! Trails: the recent path of chosen entities, kept in a ring buffer per
//! entity and drawn as a fading line strip.
//!
//! Points are recorded once per fixed step, not per frame, so a trail looks
//! the same at any display rate; the newest segment runs to the entity's
//! interpolated position, so the trail stays attached to it.

use glam::Vec3;

use crate::world::{Entity, World};

/// One entity's trail.
#[derive(Clone, Debug)]
struct Trail {
    entity: Entity,
    colour: [u8; 4],
    /// Ring buffer of positions, oldest at `start`.
    points: Vec<Vec3>,
    start: usize,
}

/// Trails of chosen entities, each up to a fixed number of points.
#[derive(Clone, Debug)]
pub struct Trails {
    length: usize,
    trails: Vec<Trail>,
}

impl Trails {
    /// Trails of up to `length` points (at least 2) each.
    #[must_use]
    pub fn new(length: usize) -> Self {
        Self {
            length: length.max(2),
            trails: Vec::new(),
        }
    }

    /// Follows `entity`, drawing its trail in `colour` (sRGB RGBA; the
    /// alpha fades to zero along the trail).
    pub fn follow(&mut self, entity: Entity, colour: [u8; 4]) {
        self.trails.push(Trail {
            entity,
            colour,
            points: Vec::with_capacity(self.length),
            start: 0,
        });
    }

    /// The entities followed.
    pub fn entities(&self) -> impl Iterator<Item = Entity> + '_ {
        self.trails.iter().map(|t| t.entity)
    }

    /// The recorded points of `entity`'s trail, oldest first (none if it is
    /// not followed).
    pub fn points(&self, entity: Entity) -> impl Iterator<Item = Vec3> + '_ {
        let trail = self.trails.iter().find(|t| t.entity == entity);
        let n = trail.map_or(0, |t| t.points.len());
        (0..n).filter_map(move |k| trail.map(|t| t.points[(t.start + k) % n]))
    }

    /// Forgets every recorded point (after a reset or teleport).
    pub fn clear_points(&mut self) {
        for trail in &mut self.trails {
            trail.points.clear();
            trail.start = 0;
        }
    }

    /// Records the current position of every followed entity; call after
    /// each fixed step. Despawned entities' trails are dropped.
    pub fn record(&mut self, world: &World) {
        self.trails.retain(|t| world.contains(t.entity));
        for trail in &mut self.trails {
            let Ok(position) = world.position(trail.entity) else {
                continue;
            };
            if trail.points.len() < self.length {
                trail.points.push(position);
            } else {
                trail.points[trail.start] = position;
                trail.start = (trail.start + 1) % self.length;
            }
        }
    }

    /// Emits the trails' segments, oldest first, fading in; the last one
    /// ends at the entity's drawn position, `at(row)`.
    pub(crate) fn lines(&self, world: &World, at: impl Fn(usize) -> Vec3, push: &mut impl FnMut(Vec3, Vec3, [u8; 4])) {
        for trail in &self.trails {
            let n = trail.points.len();
            if n == 0 {
                continue;
            }
            let point = |k: usize| trail.points[(trail.start + k) % n];
            let fade = |k: usize| {
                let mut colour = trail.colour;
                colour[3] = ((u32::from(colour[3]) * (k as u32 + 1)) / (n as u32 + 1)) as u8;
                colour
            };
            // The ring's newest point is the current step's position, which
            // the interpolated head has not reached yet: end at the head.
            for k in 0..n.saturating_sub(2) {
                push(point(k), point(k + 1), fade(k + 1));
            }
            if let Ok(row) = world.row(trail.entity) {
                let head = at(row);
                let from = if n >= 2 { point(n - 2) } else { point(0) };
                push(from, head, fade(n));
            }
        }
    }
}

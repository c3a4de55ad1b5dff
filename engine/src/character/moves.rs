//! One step of one character: the sweeps of an upright box against the
//! world's planes and boxes, and the rules of [the module](super) on top.
//!
//! A box of half size `h` centred at `c` meets a solid box where its centre
//! meets the solid box grown by `h` (their Minkowski sum), and a plane
//! `n . x >= offset` where `n . c - (|n.x| h.x + |n.y| h.y) = offset` (its
//! corner deepest along `-n` on the plane). A move along one axis is then
//! a distance to a face: the least over the solids, less the skin.

use glam::Vec2;

use super::{Character, Ground, Touch};
use crate::colliders::{Collider, ColliderId, GpuCollider};

/// A collider as a character meets it, in the z = 0 plane.
#[derive(Clone, Copy, Debug)]
enum Solid {
    /// Keeps the character out of `min..max`.
    Block { min: Vec2, max: Vec2, velocity: Vec2 },
    /// Keeps the character inside `min..max` (a container).
    Room { min: Vec2, max: Vec2, velocity: Vec2 },
    /// Keeps it on the side `n . x >= offset`.
    Plane { n: Vec2, offset: f32, velocity: Vec2 },
}

/// What a collider is to a character: a box whose z range holds 0, or a
/// plane not facing along z; else nothing.
fn solid(collider: &dyn Collider) -> Option<Solid> {
    match collider.gpu_form() {
        GpuCollider::Box {
            min,
            max,
            inside,
            velocity,
            ..
        } if min.z <= 0.0 && max.z >= 0.0 => {
            let (min, max, velocity) = (min.truncate(), max.truncate(), velocity.truncate());
            Some(if inside {
                Solid::Room { min, max, velocity }
            } else {
                Solid::Block { min, max, velocity }
            })
        }
        GpuCollider::Plane {
            normal, offset, speed, ..
        } => {
            let n = normal.truncate();
            (n.length_squared() >= 0.25).then_some(Solid::Plane {
                n,
                offset,
                velocity: n * speed,
            })
        }
        _ => None,
    }
}

/// What stopped a move.
#[derive(Clone, Copy, Debug)]
struct Hit {
    /// The collider's index in the world's list.
    index: usize,
    /// The surface's normal, towards the character.
    normal: Vec2,
    velocity: Vec2,
    /// A block's top (what a step up climbs onto); a plane's is none.
    top: Option<f32>,
}

/// The world's colliders with their handles, as a step sees them.
pub(crate) struct Solids<'a> {
    pub colliders: &'a [Box<dyn Collider>],
    pub ids: &'a [ColliderId],
}

impl Solids<'_> {
    fn each(&self, skip: Option<usize>) -> impl Iterator<Item = (usize, Solid)> + '_ {
        self.colliders
            .iter()
            .enumerate()
            .filter(move |(k, _)| Some(*k) != skip)
            .filter_map(|(k, c)| Some((k, solid(c.as_ref())?)))
    }

    /// How far a box of half size `h` at `c` moves along `axis` (0: x, 1: y)
    /// towards `d` (signed) before it comes within `skin` of a solid
    /// (`skip` aside), and what stops it.
    fn sweep(&self, c: Vec2, h: Vec2, axis: usize, d: f32, skin: f32, skip: Option<usize>) -> (f32, Option<Hit>) {
        let s = if d < 0.0 { -1.0 } else { 1.0 };
        let other = 1 - axis;
        let mut travel = d.abs();
        let mut hit = None;
        let mut unit = Vec2::ZERO;
        unit[axis] = 1.0;
        for (index, solid) in self.each(skip) {
            let (gap, normal, velocity, top) = match solid {
                Solid::Block { min, max, velocity } => {
                    let (lo, hi) = (min - h, max + h);
                    // Beside it on the other axis (level with a box top it
                    // stands on, a skin above it, is beside it).
                    if !(c[other] > lo[other] && c[other] < hi[other]) {
                        continue;
                    }
                    // Only a face ahead: from inside, a box lets it out.
                    let centre = (lo[axis] + hi[axis]) / 2.0;
                    if s > 0.0 && c[axis] < centre {
                        (lo[axis] - c[axis], -unit, velocity, Some(max.y))
                    } else if s < 0.0 && c[axis] > centre {
                        (c[axis] - hi[axis], unit, velocity, Some(max.y))
                    } else {
                        continue;
                    }
                }
                Solid::Room { min, max, velocity } => {
                    // Only from inside (beside or above it, it is not in the way).
                    let inside = |a: usize| c[a] >= min[a] + h[a] && c[a] <= max[a] - h[a];
                    if !(inside(axis) && inside(other)) {
                        continue;
                    }
                    if s > 0.0 {
                        (max[axis] - h[axis] - c[axis], -unit, velocity, None)
                    } else {
                        (c[axis] - (min[axis] + h[axis]), unit, velocity, None)
                    }
                }
                Solid::Plane { n, offset, velocity } => {
                    let rate = n[axis] * s;
                    if rate >= 0.0 {
                        continue;
                    }
                    let f = n.dot(c) - (n.x.abs() * h.x + n.y.abs() * h.y) - offset;
                    (f / -rate, n * n.length_squared().sqrt().recip(), velocity, None)
                }
            };
            let allowed = (gap - skin).max(0.0);
            if allowed < travel {
                travel = allowed;
                hit = Some(Hit {
                    index,
                    normal,
                    velocity,
                    top,
                });
            }
        }
        (s * travel, hit)
    }

    /// Moves `c` out of every solid it overlaps (a platform that moved into
    /// it), each in turn along its shortest way out, to a skin away.
    fn push_out(&self, c: &mut Vec2, h: Vec2, skin: f32) {
        for (_, solid) in self.each(None) {
            match solid {
                Solid::Block { min, max, .. } => {
                    let (lo, hi) = (min - h, max + h);
                    if !(c.x > lo.x && c.x < hi.x && c.y > lo.y && c.y < hi.y) {
                        continue;
                    }
                    let ways = [
                        (c.x - lo.x, Vec2::new(lo.x - skin, c.y)),
                        (hi.x - c.x, Vec2::new(hi.x + skin, c.y)),
                        (c.y - lo.y, Vec2::new(c.x, lo.y - skin)),
                        (hi.y - c.y, Vec2::new(c.x, hi.y + skin)),
                    ];
                    // The least, the first of equals (up last: a tie goes up).
                    let mut best = ways[3];
                    for way in ways {
                        if way.0 < best.0 {
                            best = way;
                        }
                    }
                    *c = best.1;
                }
                Solid::Room { min, max, .. } => {
                    if c.x >= min.x && c.x <= max.x && c.y >= min.y && c.y <= max.y {
                        let (lo, hi) = (min + h + skin, max - h - skin);
                        if lo.x <= hi.x && lo.y <= hi.y {
                            *c = c.clamp(lo, hi);
                        }
                    }
                }
                Solid::Plane { n, offset, .. } => {
                    let f = n.dot(*c) - (n.x.abs() * h.x + n.y.abs() * h.y) - offset;
                    if f < 0.0 {
                        *c += n * ((skin - f) / n.length_squared());
                    }
                }
            }
        }
    }

    fn id(&self, index: usize) -> ColliderId {
        self.ids[index]
    }
}

/// One step of `dt` seconds of `character` among `solids`.
pub(crate) fn step_character(character: &mut Character, solids: &Solids<'_>, dt: f32) {
    let config = character.config;
    let (h, skin) = (config.half_extents, config.skin);
    character.jumped = false;
    character.wall = None;
    character.ceiling = None;
    let mut c = character.position;
    character.previous = c;
    // 1. Carried by the ground's own move this step (it moved first).
    if let Some(ground) = character.ground
        // Ids ascend with the list (as `ColliderSet::index` finds them).
        && let Ok(index) = solids.ids.binary_search(&ground.collider)
        && let Some(solid) = solids.colliders.get(index).and_then(|c| solid(c.as_ref()))
    {
        let velocity = match solid {
            Solid::Block { velocity, .. } | Solid::Room { velocity, .. } | Solid::Plane { velocity, .. } => velocity,
        };
        let carry = velocity * dt;
        if carry != Vec2::ZERO {
            c.x += solids.sweep(c, h, 0, carry.x, skin, Some(index)).0;
            c.y += solids.sweep(c, h, 1, carry.y, skin, Some(index)).0;
        }
    }
    // 2. Out of whatever moved into it.
    solids.push_out(&mut c, h, skin);
    // 3. A buffered jump, taken standing or in coyote time.
    let had_ground = character.ground.is_some();
    if let Some((speed, left)) = character.jump {
        if character.ground.is_some() || character.coyote > 0 {
            character.velocity.y = speed;
            character.jumped = true;
            character.jump = None;
            character.coyote = 0;
        } else {
            character.jump = (left > 1).then_some((speed, left - 1));
        }
    }
    let stood = character.ground.is_some() && !character.jumped;
    character.ground = None;
    // 4. Falling.
    character.velocity += config.gravity * dt;
    // 5. Across, stepping up an edge low enough, then up or down.
    let d = character.velocity * dt;
    let (across, mut wall) = solids.sweep(c, h, 0, d.x, skin, None);
    let mut moved = Vec2::new(c.x + across, c.y);
    if let Some(hit) = wall
        && stood
        && let Some(top) = hit.top
    {
        let rise = top - (c.y - h.y);
        if rise > 0.0 && rise <= config.step_height {
            let lift = rise + skin;
            let (up, blocked) = solids.sweep(c, h, 1, lift, skin, None);
            if blocked.is_none() {
                let lifted = Vec2::new(c.x, c.y + up);
                let (further, wall_up) = solids.sweep(lifted, h, 0, d.x, skin, None);
                if further.abs() > across.abs() {
                    let (down, _) = solids.sweep(Vec2::new(lifted.x + further, lifted.y), h, 1, -lift, skin, None);
                    moved = Vec2::new(lifted.x + further, lifted.y + down);
                    wall = wall_up;
                }
            }
        }
    }
    if let Some(hit) = wall {
        character.velocity.x = 0.0;
        character.wall = Some(Touch {
            collider: solids.id(hit.index),
            normal: hit.normal,
        });
    }
    c = moved;
    let (vertical, stop) = solids.sweep(c, h, 1, d.y, skin, None);
    c.y += vertical;
    if let Some(hit) = stop {
        if hit.normal.y >= config.min_ground_normal {
            character.ground = Some(Ground {
                collider: solids.id(hit.index),
                normal: hit.normal,
                velocity: hit.velocity,
            });
            character.velocity.y = character.velocity.y.max(0.0);
        } else if hit.normal.y < 0.0 {
            character.ceiling = Some(Touch {
                collider: solids.id(hit.index),
                normal: hit.normal,
            });
            character.velocity.y = character.velocity.y.min(0.0);
        } else {
            // A slope too steep to stand on: the fall into it stops.
            character.velocity.y = 0.0;
        }
    }
    // 6. Snapped down onto ground just below, if it stood and did not jump.
    if stood && character.ground.is_none() && character.velocity.y <= 0.0 && config.snap_distance > 0.0 {
        let (down, below) = solids.sweep(c, h, 1, -config.snap_distance, skin, None);
        if let Some(hit) = below
            && hit.normal.y >= config.min_ground_normal
        {
            c.y += down;
            character.velocity.y = 0.0;
            character.ground = Some(Ground {
                collider: solids.id(hit.index),
                normal: hit.normal,
                velocity: hit.velocity,
            });
        }
    }
    // Coyote time counts the steps that start in the air: after leaving
    // the ground, `coyote_ticks` of them may still jump.
    if character.ground.is_some() {
        character.coyote = config.coyote_ticks;
    } else if !had_ground {
        character.coyote = character.coyote.saturating_sub(1);
    }
    character.position = c;
}

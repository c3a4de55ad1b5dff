//! The lines the renderer builds from a world on the CPU: springs (from the
//! world's [`Springs`] force), rigid bodies' boxes and axes, and trails,
//! all placed by the particles' formula ([`Interpolation::position`](crate::interpolation::Interpolation::position)).

use glam::{Mat4, Vec3};

use super::config::RendererConfig;
use super::frame_view::WorldView;
use crate::forces::{SpringEnd, Springs};
use crate::world::Colour;

/// Adds the lines of `shown` at interpolation parameter `t` through `push`.
pub(super) fn world_lines(
    config: &RendererConfig,
    shown: &WorldView<'_>,
    t: f32,
    push: &mut impl FnMut(Vec3, Vec3, Colour),
) {
    let world = shown.world;
    let particles = world.particles();
    // Where the particle shaders draw row `row` (lerp, or Hermite in that
    // mode), so lines stay attached to the discs.
    let at = |row: usize| {
        config.interpolation.position(
            particles.previous_position.row(row).into(),
            particles.position.row(row).into(),
            particles.velocity.row(row).into(),
            t,
        )
    };
    if config.springs {
        for force in world.forces() {
            let Some(springs) = force.as_any().downcast_ref::<Springs>() else {
                continue;
            };
            for spring in springs.springs() {
                let end = |end: SpringEnd| match end {
                    SpringEnd::Anchor(p) => Some(p),
                    SpringEnd::Entity(e) => world.row(e).ok().map(at),
                };
                if let (Some(a), Some(b)) = (end(spring.a), end(spring.b)) {
                    push(a, b, config.spring_colour);
                }
            }
        }
    }
    if config.rigid_bodies {
        let rigid = world.rigid_bodies();
        for body in 0..rigid.len() {
            let row = rigid.owner[body] as usize;
            let centre = at(row);
            let q = crate::interpolation::slerp(rigid.previous_orientation[body], rigid.orientation[body], t);
            let transform = Mat4::from_rotation_translation(q, centre);
            let h = rigid.half_extents[body];
            let corner = |i: usize| transform.transform_point3(h * Vec3::new(sign(i & 1), sign(i & 2), sign(i & 4)));
            let colour = particles.colour[row];
            for (i, j) in BOX_EDGES {
                push(corner(i), corner(j), colour);
            }
            for (axis, colour) in [
                (Vec3::X, [230, 80, 70, 255]),
                (Vec3::Y, [90, 210, 90, 255]),
                (Vec3::Z, [80, 140, 240, 255]),
            ] {
                let tip = transform.transform_point3(axis * (1.6 * h.max_element()));
                push(centre, tip, colour);
            }
        }
    }
    if let Some(trails) = shown.trails {
        trails.lines(world, at, push);
    }
}

/// Corner pairs of a box's 12 edges, corners numbered by the sign bits of
/// x (1), y (2) and z (4).
const BOX_EDGES: [(usize, usize); 12] = [
    (0, 1),
    (2, 3),
    (4, 5),
    (6, 7),
    (0, 2),
    (1, 3),
    (4, 6),
    (5, 7),
    (0, 4),
    (1, 5),
    (2, 6),
    (3, 7),
];

fn sign(bit: usize) -> f32 {
    if bit == 0 { -1.0 } else { 1.0 }
}

//! Seams between flush boxes: where two solid boxes meet with their faces
//! flush (a floor of tiles, a wall of stacked blocks), a particle sliding
//! across the joint must not catch on the edge of the next box's face.
//!
//! A particle of radius `r` meets a solid box where its centre meets the
//! box grown by `r` (square-edged). Sliding along box A's top, its centre
//! runs along the top of A's grown box, level with the top edge of the
//! next box B's grown side face: the step finds a hit on that face and
//! stops it, though the surface it slides on goes on flat. As Box2D's
//! chain shapes and Rapier's internal-edge handling do, that hit is
//! refused as internal when, at the hit:
//!
//! - the particle's centre is within [`SEAM_TOLERANCE`] of an edge of B's
//!   grown face (the joint, not the middle of a wall), and
//! - another solid box A has its grown face on the same side of that edge
//!   flush with B's (within the tolerance) and covers the centre on every
//!   other axis (the surface continues across the joint).
//!
//! A real wall, a step higher than the tolerance, or a box standing on
//! another still stops it. Both boxes may move (a kinematic box level with
//! the ground within the tolerance: a ferry docked at a quay). A particle
//! that then dips into B by less than the tolerance is put back on top by
//! B's end-of-step rule (its shortest way out). The GPU step does not
//! apply this (its boxes keep square seams).

use glam::DVec3;

use super::sweep::{StepPath, SweptHit};
use super::{Collider, GpuCollider};

/// How far from flush two boxes' faces may be and still meet at a seam a
/// particle slides over, metres (5 mm: a kinematic box drifting at 1 mm/s
/// for a few seconds is still flush; a 2 cm step is a step).
pub const SEAM_TOLERANCE: f32 = 0.005;

/// A solid box's corners and velocity, if `collider` is one.
fn solid_box(collider: &dyn Collider) -> Option<(DVec3, DVec3, DVec3)> {
    match collider.gpu_form() {
        GpuCollider::Box {
            min,
            max,
            inside: false,
            velocity,
            ..
        } => Some((min.as_dvec3(), max.as_dvec3(), velocity.as_dvec3())),
        _ => None,
    }
}

/// Whether `hit`, a hit of collider `k` along `path` for a particle of
/// `radius`, is at a seam with a flush box among `colliders` (see the
/// module), and so not a contact.
pub(crate) fn at_seam(colliders: &[Box<dyn Collider>], k: usize, hit: &SweptHit, path: &StepPath, radius: f32) -> bool {
    let Some((min, max, u)) = colliders.get(k).and_then(|c| solid_box(c.as_ref())) else {
        return false;
    };
    let Some(axis) = (0..3).find(|&a| hit.normal[a] != 0.0) else {
        return false;
    };
    let (r, tol) = (f64::from(radius), f64::from(SEAM_TOLERANCE));
    // Where the centre is at the hit, in each box's frame at the step's end.
    let centre = path.at(hit.fraction);
    let rest = path.dt * (1.0 - hit.fraction);
    let p = centre + u * rest;
    for edge_axis in (0..3).filter(|&a| a != axis) {
        for high in [false, true] {
            let edge = if high { max[edge_axis] + r } else { min[edge_axis] - r };
            if (p[edge_axis] - edge).abs() > tol {
                continue;
            }
            let continues = colliders.iter().enumerate().any(|(j, other)| {
                let Some((lo, hi, w)) = (j != k).then(|| solid_box(other.as_ref())).flatten() else {
                    return false;
                };
                let q = centre + w * rest;
                let flush = if high { hi[edge_axis] + r } else { lo[edge_axis] - r };
                (flush - edge).abs() <= tol
                    && (0..3)
                        .filter(|&a| a != edge_axis)
                        .all(|a| q[a] >= lo[a] - r - tol && q[a] <= hi[a] + r + tol)
            });
            if continues {
                return true;
            }
        }
    }
    false
}

//! Colliders on rows: the ones without a block kernel, and the ones that
//! report contacts (found by comparing each row's state before and after).

use glam::Vec3A;
use tickwork_integrators::Vec3x4;

use crate::colliders::{Collider, ContactColumns, PairTouch, RowTouch, diff_touches};
use crate::layout::{Rows, gather, scatter};

/// Where a reporting collider's contacts go: its index, the global row of
/// the first row it is given, and the list.
pub(super) struct Reporting<'a> {
    pub(super) collider: u32,
    pub(super) first_row: usize,
    pub(super) out: &'a mut Vec<RowTouch>,
}

/// A collider without a block kernel (or one that reports contacts), on a
/// chunk's rows: gathered into scratch, resolved (contacts slower than
/// `rest_speed` resting), written back.
#[allow(clippy::too_many_arguments)]
pub(super) fn resolve_rows(
    collider: &dyn Collider,
    x: &mut [Vec3x4],
    v: &mut [Vec3x4],
    radius: &[f32],
    inverse_mass: &[f32],
    rest_speed: f32,
    scratch: &mut Rows,
    reporting: Option<Reporting<'_>>,
) {
    gather(x, radius.len(), &mut scratch.x, false);
    gather(v, radius.len(), &mut scratch.v, false);
    if reporting.is_some() {
        scratch.before_x.clone_from(&scratch.x);
        scratch.before_v.clone_from(&scratch.v);
    }
    collider.resolve_range(ContactColumns {
        position: &mut scratch.x,
        velocity: &mut scratch.v,
        radius,
        inverse_mass,
        parallel: false,
        // A chunk of pointwise contacts: no pairs to count.
        max_pairs: u64::MAX,
        start: None,
        rest_speed,
    });
    if let Some(r) = reporting {
        let s = &*scratch;
        diff_touches(
            r.collider,
            r.first_row,
            &s.before_x,
            &s.before_v,
            &s.x,
            &s.v,
            radius,
            inverse_mass,
            r.out,
        );
    }
    scatter(&scratch.x, x, false);
    scatter(&scratch.v, v, false);
}

/// A reporting collider over the whole world: its own pair reports if it
/// makes them, else the contacts found by comparing states.
pub(super) fn resolve_world_reporting(
    collider: &mut dyn Collider,
    index: u32,
    c: ContactColumns<'_>,
    before_x: &mut Vec<Vec3A>,
    before_v: &mut Vec<Vec3A>,
    out: &mut Vec<RowTouch>,
) {
    let (radius, inverse_mass) = (c.radius, c.inverse_mass);
    if !collider.is_pointwise() {
        let mut report = |pair: PairTouch| {
            // One per pair, under the lower row, the normal towards it.
            let (row, other, normal) = if pair.a <= pair.b {
                (pair.a, pair.b, pair.normal)
            } else {
                (pair.b, pair.a, -pair.normal)
            };
            out.push(RowTouch {
                collider: index,
                row: row as u32,
                other: other as u32,
                point: pair.point,
                normal,
                impulse: pair.impulse,
                fraction: pair.fraction,
                event: u32::MAX,
            });
        };
        let reborrow = ContactColumns {
            position: &mut *c.position,
            velocity: &mut *c.velocity,
            radius,
            inverse_mass,
            parallel: false,
            max_pairs: c.max_pairs,
            start: c.start,
            rest_speed: c.rest_speed,
        };
        if collider.resolve_world_reporting(reborrow, &mut report) {
            return;
        }
    }
    before_x.clear();
    before_x.extend_from_slice(c.position);
    before_v.clear();
    before_v.extend_from_slice(c.velocity);
    collider.resolve_world(ContactColumns {
        position: &mut *c.position,
        velocity: &mut *c.velocity,
        ..c
    });
    diff_touches(
        index,
        0,
        before_x,
        before_v,
        c.position,
        c.velocity,
        radius,
        inverse_mass,
        out,
    );
}

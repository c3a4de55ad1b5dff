//! One lane of the fused step: integrate, collide and check its chunks of
//! [`CHUNK`] particles while each sits in L1.

use tickwork_integrators::{StepError, Vec3x4};

use super::chunk::Chunk;
use super::in_step::Sweep;
use super::reporting::{Reporting, resolve_rows};
use crate::colliders::{BlockColumns, Collider, EventOverflow};
use crate::forces::{BlockField, Force, ForceField};
use crate::layout::{CHUNK, LANES, Vec3Column};
use crate::world::Lane;
use crate::world::facts::Facts;

/// The particle columns one lane steps: `previous` holds the positions at
/// the start of the step (read), `x` receives the new ones; the vectors in
/// blocks of four particles per axis, the scalars one per particle (`rows`
/// real particles; the last block may hold padding lanes), and the facts of
/// each of the lane's chunks.
pub(super) struct LaneColumns<'a> {
    pub(super) x: &'a mut [Vec3x4],
    pub(super) v: &'a mut [Vec3x4],
    pub(super) previous: &'a [Vec3x4],
    pub(super) radius: &'a [f32],
    pub(super) inverse_mass: &'a [f32],
    pub(super) facts: &'a [Facts],
}

#[derive(Clone, Copy, Debug, Default)]
pub(super) struct LaneOutcome {
    pub(super) evaluations: u32,
    pub(super) first_bad: Option<usize>,
    /// The first row (by row) that met more in-step contacts than allowed.
    pub(super) overflow: Option<EventOverflow>,
}

pub(super) fn merge(
    a: Result<LaneOutcome, StepError>,
    b: Result<LaneOutcome, StepError>,
) -> Result<LaneOutcome, StepError> {
    let (a, b) = (a?, b?);
    Ok(LaneOutcome {
        evaluations: a.evaluations.max(b.evaluations),
        first_bad: match (a.first_bad, b.first_bad) {
            (Some(x), Some(y)) => Some(x.min(y)),
            (x, y) => x.or(y),
        },
        overflow: match (a.overflow, b.overflow) {
            (Some(x), Some(y)) => Some(if x.row <= y.row { x } else { y }),
            (x, y) => x.or(y),
        },
    })
}

/// Integrate (from `previous` into `x`), collide and check one lane, chunk
/// by chunk of [`CHUNK`] particles ([`CHUNK`] / 4 blocks). Colliders that
/// `report` contacts add them to the lane's list.
#[allow(clippy::too_many_arguments)]
pub(super) fn step_lane(
    lane: &mut Lane,
    forces: &[Box<dyn Force>],
    colliders: &[Box<dyn Collider>],
    report: &[bool],
    sweep: Option<Sweep<'_>>,
    t: f32,
    dt: f32,
    offset: usize,
    c: LaneColumns<'_>,
) -> Result<LaneOutcome, StepError> {
    let mut outcome = LaneOutcome::default();
    lane.touches.clear();
    let n = c.radius.len();
    // The force sums are the same for every chunk: made once per lane.
    let whole = ForceField::new(forces, c.inverse_mass, offset);
    let mut start = 0;
    while start < n {
        let end = (start + CHUNK).min(n);
        let (rows, blocks) = (start..end, start / LANES..end.div_ceil(LANES));
        let facts = c.facts[start / CHUNK];
        let (x, v) = (&mut c.x[blocks.clone()], &mut c.v[blocks.clone()]);
        let mut field = BlockField {
            field: whole.window(start, end - start),
            rows: end - start,
            movable: facts.movable,
            scratch: &mut lane.rows,
        };
        let stats = lane
            .method
            .step_from(t, dt, &c.previous[blocks.clone()], x, v, &mut field)?;
        outcome.evaluations = outcome.evaluations.max(stats.evaluations);
        if let Some(sweep) = sweep {
            // Contacts inside the step first: their colliders settle what
            // is clear or resting (one vector test a block), follow the
            // other particles' paths and resolve what is left at the end.
            let chunk = Chunk {
                x: &mut *x,
                v: &mut *v,
                radius: &c.radius[rows.clone()],
                inverse_mass: &c.inverse_mass[rows.clone()],
                movable: facts.movable,
                point: facts.point,
            };
            let overflow = sweep.resolve_chunk(
                offset + start,
                &c.previous[blocks.clone()],
                chunk,
                &mut lane.rows,
                &mut lane.settled,
                &mut lane.touches,
            );
            outcome.overflow = outcome.overflow.or(overflow);
        }
        // Then the end-of-step rule of the others, in order.
        for (k, collider) in colliders.iter().enumerate().filter(|(_, c)| !c.in_step()) {
            let (radius, inverse_mass) = (&c.radius[rows.clone()], &c.inverse_mass[rows.clone()]);
            if report[k] {
                let touches = Reporting {
                    collider: k as u32,
                    first_row: offset + start,
                    out: &mut lane.touches,
                };
                resolve_rows(
                    collider.as_ref(),
                    x,
                    v,
                    radius,
                    inverse_mass,
                    0.0,
                    &mut lane.rows,
                    Some(touches),
                );
                continue;
            }
            let blocks = BlockColumns {
                position: x,
                velocity: v,
                radius: &c.radius[rows.clone()],
                inverse_mass: &c.inverse_mass[rows.clone()],
                rows: end - start,
                movable: facts.movable,
                point: facts.point,
                rest_speed: 0.0,
            };
            if !collider.resolve_blocks(blocks) {
                resolve_rows(collider.as_ref(), x, v, radius, inverse_mass, 0.0, &mut lane.rows, None);
            }
        }
        if outcome.first_bad.is_none() {
            outcome.first_bad = Vec3Column::first_non_finite(x, v, end - start, offset + start);
        }
        start = end;
    }
    Ok(outcome)
}

//! An infinite plane: particles stay on the side its normal points to; at
//! rest, or kinematic (moved along its normal each step: a piston, a
//! rising floor).

use glam::{Vec3, Vec3A, Vec4};
use tickwork_integrators::Vec3x4;

use super::contact::{ContactRule, Material, resolve};
use super::sweep::{StepPath, SweptHit};
use super::{BlockColumns, Collider, ContactColumns};

/// The half-space `n . x >= offset` is free; a particle of radius `r` touches
/// the plane when `n . x - offset - r < 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// Unit normal pointing into the free side (default `(0, 1, 0)`: a floor).
    pub normal: Vec3,
    /// Signed distance of the plane from the origin along the normal
    /// (default `0.0`).
    pub offset: f32,
    /// Bounce and friction (default [`Material::default`]).
    pub material: Material,
    /// Speed along the normal in m/s (default zero: at rest; moving along
    /// itself would change nothing). Each step first moves the plane,
    /// `offset += speed dt`, then resolves contacts in its frame, where it
    /// is at rest: `v' = u + response(v - u)` with `u = speed n`.
    pub speed: f32,
    /// When contacts are found (default [`ContactRule::InStep`]).
    pub contact: ContactRule,
}

impl Default for Plane {
    /// A floor at height 0, at rest, of the default material: so a struct
    /// literal names only what it changes (`Plane { normal: Vec3::X,
    /// ..Plane::default() }`).
    fn default() -> Self {
        Self::floor(0.0, Material::default())
    }
}

impl Plane {
    /// A floor at height `y`, at rest.
    #[must_use]
    pub fn floor(y: f32, material: Material) -> Self {
        Self {
            normal: Vec3::Y,
            offset: y,
            material,
            speed: 0.0,
            contact: ContactRule::InStep,
        }
    }

    /// The offset a frame `alpha` steps past the last one shows a moving
    /// plane at: between its last two steps (as particles are drawn).
    #[must_use]
    pub fn interpolated_offset(&self, alpha: f32, dt: f32) -> f32 {
        self.offset - self.speed * dt * (1.0 - alpha)
    }
}

/// A plane at rest whose normal is an axis, `n = ±e_axis` (a floor, a
/// wall, a ceiling), as [`Collider::axis_plane`] describes it: the free
/// side is `n . x >= offset`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisPlane {
    /// The axis of the normal: 0 (x), 1 (y) or 2 (z).
    pub axis: usize,
    /// Whether the normal is `-e_axis` (a ceiling, for axis 1).
    pub negative: bool,
    /// The plane's offset along its normal.
    pub offset: f32,
    /// Its bounce and friction.
    pub material: Material,
}

impl AxisPlane {
    /// The plane's end-of-step rule on one block of four particles (radii
    /// `r`, inverse masses `w`; approaches no faster than `rest` m/s rest):
    /// the same bits as [`Plane::resolve_blocks`] on that block.
    #[inline]
    pub(crate) fn resolve_block<const AXIS: usize>(&self, x: &mut Vec3x4, v: &mut Vec3x4, r: Vec4, w: Vec4, rest: f32) {
        let mut normal = Vec3::ZERO;
        normal[AXIS] = if self.negative { -1.0 } else { 1.0 };
        let plane = Plane {
            normal,
            offset: self.offset,
            material: self.material,
            speed: 0.0,
            contact: ContactRule::InStep,
        };
        if self.negative {
            plane.contact_block::<AXIS, true>(x, v, r, w, rest);
        } else {
            plane.contact_block::<AXIS, false>(x, v, r, w, rest);
        }
    }
}

/// `(axis, sign)` when the normal is `sign * e_axis` exactly.
fn axis_of(n: Vec3) -> Option<(usize, f32)> {
    let a = n.to_array();
    let axis = a.iter().position(|c| c.abs() == 1.0)?;
    let others_zero = a.iter().enumerate().all(|(k, c)| k == axis || *c == 0.0);
    others_zero.then_some((axis, a[axis]))
}

impl Collider for Plane {
    fn name(&self) -> &'static str {
        "plane"
    }

    fn in_step(&self) -> bool {
        self.contact == ContactRule::InStep
    }

    fn settle_blocks(&self, start: &[Vec3x4], c: BlockColumns<'_>, dt: f32, resolve: bool, settled: &mut [u8]) -> bool {
        let rest_dt = c.rest_speed * dt;
        if resolve && self.speed == 0.0 {
            match axis_of(self.normal) {
                Some((0, sign)) if sign < 0.0 => self.settle_axis_blocks::<0, true>(start, c, dt, rest_dt, settled),
                Some((0, _)) => self.settle_axis_blocks::<0, false>(start, c, dt, rest_dt, settled),
                Some((1, sign)) if sign < 0.0 => self.settle_axis_blocks::<1, true>(start, c, dt, rest_dt, settled),
                Some((1, _)) => self.settle_axis_blocks::<1, false>(start, c, dt, rest_dt, settled),
                Some((_, sign)) if sign < 0.0 => self.settle_axis_blocks::<2, true>(start, c, dt, rest_dt, settled),
                Some((_, _)) => self.settle_axis_blocks::<2, false>(start, c, dt, rest_dt, settled),
                None => {
                    self.settle(start, &c, dt, rest_dt, settled);
                    return false;
                }
            }
            return true;
        }
        self.settle(start, &c, dt, rest_dt, settled);
        false
    }

    fn gpu_form(&self) -> super::GpuCollider {
        super::GpuCollider::Plane {
            normal: self.normal,
            offset: self.offset,
            speed: self.speed,
            material: self.material,
        }
    }

    fn axis_plane(&self) -> Option<AxisPlane> {
        if self.contact != ContactRule::InStep || self.speed != 0.0 {
            return None;
        }
        let (axis, sign) = axis_of(self.normal)?;
        Some(AxisPlane {
            axis,
            negative: sign < 0.0,
            offset: self.offset,
            material: self.material,
        })
    }

    fn first_contact(&self, path: &StepPath, radius: f32) -> Option<SweptHit> {
        let n = self.normal.as_dvec3();
        let speed = f64::from(self.speed);
        let offset = f64::from(self.offset);
        let fraction = path.first_crossing(n, offset, speed * path.dt, f64::from(radius))?;
        Some(SweptHit {
            fraction,
            normal: n,
            offset,
            velocity: n * speed,
            material: self.material,
        })
    }

    fn resolve_blocks(&self, c: BlockColumns<'_>) -> bool {
        if self.speed != 0.0 {
            return false;
        }
        match axis_of(self.normal) {
            Some((0, sign)) if sign < 0.0 => self.resolve_axis_blocks::<0, true>(c),
            Some((0, _)) => self.resolve_axis_blocks::<0, false>(c),
            Some((1, sign)) if sign < 0.0 => self.resolve_axis_blocks::<1, true>(c),
            Some((1, _)) => self.resolve_axis_blocks::<1, false>(c),
            Some((_, sign)) if sign < 0.0 => self.resolve_axis_blocks::<2, true>(c),
            Some((_, _)) => self.resolve_axis_blocks::<2, false>(c),
            None => return false,
        }
        true
    }

    fn resolve_range(&self, mut c: ContactColumns<'_>) {
        let n = Vec3A::from(self.normal);
        let rest = c.rest_speed;
        if self.speed != 0.0 {
            // Moving: the contact in the plane's frame, where it is at rest.
            let u = n * self.speed;
            for (x, v, r, w) in c.rows() {
                let gap = n.dot(*x) - self.offset - r;
                let mut relative = *v - u;
                let before = relative;
                resolve(x, &mut relative, n, gap, w > 0.0, self.material, rest);
                if relative != before {
                    *v = relative + u;
                }
            }
            return;
        }
        // Floors and walls are usually axis-aligned: their contact needs no
        // dot products, which halves the collider's cost (measured).
        let frictionless = self.material.friction == 0.0;
        match axis_of(self.normal) {
            Some((0, sign)) if frictionless => self.resolve_axis_frictionless::<0>(c, sign),
            Some((1, sign)) if frictionless => self.resolve_axis_frictionless::<1>(c, sign),
            Some((_, sign)) if frictionless => self.resolve_axis_frictionless::<2>(c, sign),
            Some((0, sign)) => self.resolve_axis::<0>(c, sign),
            Some((1, sign)) => self.resolve_axis::<1>(c, sign),
            Some((_, sign)) => self.resolve_axis::<2>(c, sign),
            None => {
                for (x, v, r, w) in c.rows() {
                    let gap = n.dot(*x) - self.offset - r;
                    resolve(x, v, n, gap, w > 0.0, self.material, rest);
                }
            }
        }
    }

    fn advance(&mut self, dt: f32) {
        if self.speed != 0.0 {
            self.offset += self.speed * dt;
        }
    }
}
mod axis;
mod settle;
#[cfg(test)]
mod tests;

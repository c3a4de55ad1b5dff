//! Damped springs between particles or to fixed anchors (Hooke's law with
//! damping along the spring):
//! `F_a = [k (|d| - L) + c (v_b - v_a) . u] u`, `d = x_b - x_a`, `u = d / |d|`,
//! and `F_b = -F_a`.

use glam::{Vec3, Vec3A};

use super::Force;
use crate::layout::{Entities, Entity};

/// One end of a spring.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SpringEnd {
    /// A particle.
    Entity(Entity),
    /// A fixed point in space.
    Anchor(Vec3),
}

/// A spring between two ends (at least one a particle).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spring {
    /// First end.
    pub a: SpringEnd,
    /// Second end.
    pub b: SpringEnd,
    /// Stiffness `k`, N/m.
    pub stiffness: f32,
    /// Rest length `L`, m.
    pub rest_length: f32,
    /// Damping `c` along the spring, N s/m.
    pub damping: f32,
}

const ANCHOR: u32 = u32::MAX;

/// A set of springs, evaluated as one force. Springs whose particle was
/// despawned are dropped at the next step.
#[derive(Debug, Default, PartialEq)]
pub struct Springs {
    springs: Vec<Spring>,
    /// Rows of both ends (`ANCHOR` for an anchor), refreshed by `prepare`.
    rows: Vec<[u32; 2]>,
}

impl Clone for Springs {
    fn clone(&self) -> Self {
        Self {
            springs: self.springs.clone(),
            rows: self.rows.clone(),
        }
    }
    fn clone_from(&mut self, source: &Self) {
        self.springs.clone_from(&source.springs);
        self.rows.clone_from(&source.rows);
    }
}

impl Springs {
    /// A set of `springs`.
    #[must_use]
    pub fn new(springs: Vec<Spring>) -> Self {
        Self {
            springs,
            rows: Vec::new(),
        }
    }

    /// Adds a spring.
    pub fn push(&mut self, spring: Spring) {
        self.springs.push(spring);
    }

    /// The springs.
    #[must_use]
    pub fn springs(&self) -> &[Spring] {
        &self.springs
    }

    fn end(&self, row: u32, end: SpringEnd, x: &[Vec3A], v: &[Vec3A]) -> (Vec3A, Vec3A) {
        match end {
            SpringEnd::Anchor(p) => (Vec3A::from(p), Vec3A::ZERO),
            SpringEnd::Entity(_) => (x[row as usize], v[row as usize]),
        }
    }
}

impl Force for Springs {
    fn name(&self) -> &'static str {
        "springs"
    }

    fn is_pointwise(&self) -> bool {
        false
    }

    fn prepare(&mut self, entities: &Entities) {
        let row_of = |end: SpringEnd| match end {
            SpringEnd::Anchor(_) => Some(ANCHOR),
            SpringEnd::Entity(e) => entities.row(e).ok().map(|r| r as u32),
        };
        let mut kept = 0;
        self.rows.clear();
        for k in 0..self.springs.len() {
            let s = self.springs[k];
            if let (Some(a), Some(b)) = (row_of(s.a), row_of(s.b)) {
                self.springs[kept] = s;
                self.rows.push([a, b]);
                kept += 1;
            }
        }
        self.springs.truncate(kept);
    }

    fn accumulate(&self, _t: f32, _first: usize, x: &[Vec3A], v: &[Vec3A], w: &[f32], out: &mut [Vec3A]) {
        for (s, &[ra, rb]) in self.springs.iter().zip(&self.rows) {
            let (xa, va) = self.end(ra, s.a, x, v);
            let (xb, vb) = self.end(rb, s.b, x, v);
            let d = xb - xa;
            let length = d.length();
            if length <= f32::EPSILON {
                continue;
            }
            let u = d / length;
            let f = u * (s.stiffness * (length - s.rest_length) + s.damping * (vb - va).dot(u));
            if ra != ANCHOR {
                out[ra as usize] += f * w[ra as usize];
            }
            if rb != ANCHOR {
                out[rb as usize] -= f * w[rb as usize];
            }
        }
    }

    /// `U = sum k (|d| - L)^2 / 2`.
    fn potential_energy(&self, x: &[Vec3A], _w: &[f32]) -> f64 {
        self.springs
            .iter()
            .zip(&self.rows)
            .map(|(s, &[ra, rb])| {
                let pa = match s.a {
                    SpringEnd::Anchor(p) => p,
                    SpringEnd::Entity(_) => Vec3::from(x[ra as usize]),
                };
                let pb = match s.b {
                    SpringEnd::Anchor(p) => p,
                    SpringEnd::Entity(_) => Vec3::from(x[rb as usize]),
                };
                let stretch = (pb - pa).as_dvec3().length() - f64::from(s.rest_length);
                0.5 * f64::from(s.stiffness) * stretch * stretch
            })
            .sum()
    }
}

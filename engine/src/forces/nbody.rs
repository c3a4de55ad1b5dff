//! All-pairs gravity between particles:
//! `a_i = G sum_j m_j (x_j - x_i) / (|x_j - x_i|^2 + eps^2)^(3/2)`.

use glam::{Vec3, Vec3A};
use rayon::prelude::*;

use super::{Force, GpuForce, mass_of};

/// Mutual gravity of every pair of movable particles, O(N^2), with Plummer
/// softening. Each particle's sum runs over `j` in row order on one thread,
/// so results are bit-identical whatever the number of threads; above
/// `parallel_threshold` particles the rows are spread over rayon's threads.
/// Immovable particles (infinite mass) are no source: use an [`Attractor`](super::Attractor).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NBody {
    /// The gravitational constant in the scene's units (default SI's,
    /// [`NBody::G_SI`]).
    pub g: f32,
    /// Softening length `eps`, m (default `0.0`: exact Newtonian).
    pub softening: f32,
    /// Particle count from which rows are evaluated in parallel (default: 512).
    pub parallel_threshold: usize,
}

impl Default for NBody {
    /// SI's gravitational constant, no softening.
    fn default() -> Self {
        Self::new(Self::G_SI, 0.0)
    }
}

impl NBody {
    /// The gravitational constant in SI units, m^3 / (kg s^2).
    pub const G_SI: f32 = 6.674e-11;

    /// Mutual gravity with constant `g` and softening `softening`.
    #[must_use]
    pub fn new(g: f32, softening: f32) -> Self {
        Self {
            g,
            softening,
            parallel_threshold: 512,
        }
    }

    fn row(&self, i: usize, x: &[Vec3A], inverse_mass: &[f32]) -> Vec3A {
        let eps2 = self.softening * self.softening;
        let xi = x[i];
        let mut sum = Vec3A::ZERO;
        for (j, (xj, &w)) in x.iter().zip(inverse_mass).enumerate() {
            let d = *xj - xi;
            let r2 = d.length_squared() + eps2;
            let m = if w > 0.0 && j != i { 1.0 / w } else { 0.0 };
            if r2 > 0.0 {
                sum += d * (m / (r2 * r2.sqrt()));
            }
        }
        sum * self.g
    }
}

impl Force for NBody {
    fn name(&self) -> &'static str {
        "nbody"
    }

    fn gpu_form(&self) -> GpuForce {
        GpuForce::NBody {
            g: self.g,
            softening: self.softening,
        }
    }

    fn is_pointwise(&self) -> bool {
        false
    }

    fn pairs(&self, particles: usize) -> u64 {
        let n = particles as u64;
        n.saturating_mul(n.saturating_sub(1)) / 2
    }

    fn accumulate(&self, _t: f32, _first: usize, x: &[Vec3A], _v: &[Vec3A], w: &[f32], out: &mut [Vec3A]) {
        if x.len() >= self.parallel_threshold {
            out.par_iter_mut()
                .enumerate()
                .for_each(|(i, a)| *a += self.row(i, x, w));
        } else {
            for (i, a) in out.iter_mut().enumerate() {
                *a += self.row(i, x, w);
            }
        }
    }

    /// `U = -G sum_{i<j} m_i m_j / sqrt(r^2 + eps^2)`.
    fn potential_energy(&self, x: &[Vec3A], inverse_mass: &[f32]) -> f64 {
        let eps2 = f64::from(self.softening) * f64::from(self.softening);
        let mut u = 0.0;
        for i in 0..x.len() {
            for j in i + 1..x.len() {
                let r2 = (Vec3::from(x[j]) - Vec3::from(x[i])).as_dvec3().length_squared() + eps2;
                if r2 > 0.0 && inverse_mass[i] > 0.0 && inverse_mass[j] > 0.0 {
                    u -= f64::from(self.g) * mass_of(inverse_mass[i]) * mass_of(inverse_mass[j]) / r2.sqrt();
                }
            }
        }
        u
    }
}

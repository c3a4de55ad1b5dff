//! A fixed point mass: `a = GM (p - x) / (|p - x|^2 + eps^2)^(3/2)`.

use glam::{Vec3, Vec3A};

use super::{Force, GpuForce, WgslF32, mass_of};

/// A fixed attracting point (a sun, a black hole) with Plummer softening
/// `eps`, which keeps the acceleration finite at the centre.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Attractor {
    /// Where it is.
    pub position: Vec3,
    /// Its gravitational parameter `G M`, m^3/s^2.
    pub gm: f32,
    /// Softening length `eps`, m (0 = exact Newtonian).
    pub softening: f32,
}

impl Force for Attractor {
    fn name(&self) -> &'static str {
        "attractor"
    }

    fn gpu_form(&self) -> GpuForce {
        GpuForce::Term
    }

    /// `d = p - x; r2 = |d|^2 + eps^2; a += d (GM / (r2 sqrt(r2)))`.
    fn write_wgsl(&self, out: &mut dyn core::fmt::Write) -> core::fmt::Result {
        let p = self.position;
        writeln!(
            out,
            "    {{\n        let d = vec3<f32>({}, {}, {}) - x;\n        let r2 = length_squared(d) + {};\n        \
             a = a + d * ({} / (r2 * sqrt(r2)));\n    }}",
            WgslF32(p.x),
            WgslF32(p.y),
            WgslF32(p.z),
            WgslF32(self.softening * self.softening),
            WgslF32(self.gm)
        )
    }

    fn accumulate(&self, _t: f32, _first: usize, x: &[Vec3A], _v: &[Vec3A], _w: &[f32], out: &mut [Vec3A]) {
        let p = Vec3A::from(self.position);
        let eps2 = self.softening * self.softening;
        for (a, x) in out.iter_mut().zip(x) {
            let d = p - *x;
            let r2 = d.length_squared() + eps2;
            *a += d * (self.gm / (r2 * r2.sqrt()));
        }
    }

    /// `U = -sum GM m / sqrt(r^2 + eps^2)`.
    fn potential_energy(&self, x: &[Vec3A], inverse_mass: &[f32]) -> f64 {
        let p = self.position.as_dvec3();
        let eps2 = f64::from(self.softening) * f64::from(self.softening);
        x.iter()
            .zip(inverse_mass)
            .filter(|&(_, &w)| w > 0.0)
            .map(|(x, &w)| {
                let r2 = (Vec3::from(*x).as_dvec3() - p).length_squared() + eps2;
                -f64::from(self.gm) * mass_of(w) / r2.sqrt()
            })
            .sum()
    }
}

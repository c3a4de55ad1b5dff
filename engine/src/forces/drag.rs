//! Air resistance: linear (`-b v`, low speeds) and quadratic (`-c |v| v`, high speeds).

use glam::Vec3A;

use super::{Force, GpuForce, WgslF32};

/// Linear drag `a = -b v` (an acceleration, so it slows every particle alike).
///
/// Exponential Euler integrates it exactly, at any `b h`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinearDrag {
    /// The rate `b`, 1/s (a velocity decays as `e^(-b t)`).
    pub rate: f32,
}

impl Force for LinearDrag {
    fn name(&self) -> &'static str {
        "linear_drag"
    }

    fn linear_drag(&self) -> f32 {
        self.rate
    }

    fn affine_in_velocity(&self) -> Option<(Vec3A, f32)> {
        Some((Vec3A::ZERO, self.rate))
    }

    fn accumulate(&self, _t: f32, _first: usize, _x: &[Vec3A], v: &[Vec3A], _w: &[f32], out: &mut [Vec3A]) {
        for (a, v) in out.iter_mut().zip(v) {
            *a -= *v * self.rate;
        }
    }
}

/// Quadratic drag `a = -c |v| v`, the regime of a thrown ball or a falling
/// body at terminal speed `sqrt(g / c)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadraticDrag {
    /// The coefficient `c`, 1/m.
    pub coefficient: f32,
}

impl Force for QuadraticDrag {
    fn name(&self) -> &'static str {
        "quadratic_drag"
    }

    fn gpu_form(&self) -> GpuForce {
        GpuForce::Term
    }

    /// `a -= v (k |v|)`, `|v|` as `sqrt` of glam's dot product.
    fn write_wgsl(&self, out: &mut dyn core::fmt::Write) -> core::fmt::Result {
        writeln!(
            out,
            "    a = a - v * ({} * sqrt(length_squared(v)));",
            WgslF32(self.coefficient)
        )
    }

    fn accumulate(&self, _t: f32, _first: usize, _x: &[Vec3A], v: &[Vec3A], _w: &[f32], out: &mut [Vec3A]) {
        for (a, v) in out.iter_mut().zip(v) {
            *a -= *v * (self.coefficient * v.length());
        }
    }
}

//! Dormand-Prince 5(4): an embedded, adaptive Runge-Kutta pair used as
//! sub-stepping inside one fixed step.
//!
//! Seven stages `k_i = f(t + c_i s, y + s sum_j a_ij k_j)` on `y = (x, v)`,
//! `f = (v, a)`, give a fifth-order solution `y5 = y + s sum b_i k_i`
//! (propagated: local extrapolation) and a fourth-order one whose difference
//! estimates the error:
//!
//! ```text
//! err = rms_i( |y5_i - y4_i| / (atol + rtol max(|y_i|, |y5_i|)) )
//! accept when err <= 1;  next s = s min(5, max(0.2, 0.9 err^(-1/5)))
//! ```
//!
//! The fixed step `h` is covered by as many sub-steps `s` as the tolerance
//! needs, the last one shortened to land exactly on `t + h`, so the game loop
//! still sees one fixed step. The last accepted sub-step size carries over to
//! the next fixed step. The last stage is the next sub-step's first (FSAL).
//!
//! - Order 5 for positions and velocities, also with drag (when the tolerance
//!   allows one sub-step per fixed step; otherwise the error follows the
//!   tolerance, not `h`).
//! - Cost: 6 force evaluations per sub-step, plus 1 per fixed step.
//! - Stability: adaptive: sub-steps shrink until stable and accurate, so stiff
//!   forces make it slow rather than wrong; the cap on sub-steps reports
//!   [`StepError::SubstepLimit`] instead of stalling the game.

use crate::integrator::{Integrator, MethodInfo, StepError, StepStats, check_step, fit};
use crate::system::System;
use crate::vector::{Real, Vector};

/// Registry entry.
pub const INFO: MethodInfo = MethodInfo {
    name: "dormand_prince",
    aliases: &["dopri5", "rk45", "dp45"],
    title: "Dormand-Prince 5(4), adaptive",
    notes: "adaptive sub-steps inside the fixed step, to a tolerance",
    order: 5,
    order_velocity: 5,
    order_velocity_forces: 5,
    evaluations: 7,
    ..MethodInfo::SOLVED
};

const C: [f64; 7] = [0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0];
const A: [[f64; 6]; 7] = [
    [0.0; 6],
    [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];
/// Fifth-order weights (the last row of `A`; the seventh weight is 0), kept
/// for the tableau test: the last stage state *is* the fifth-order solution.
#[cfg_attr(not(test), allow(dead_code))]
const B: [f64; 7] = [
    35.0 / 384.0,
    0.0,
    500.0 / 1113.0,
    125.0 / 192.0,
    -2187.0 / 6784.0,
    11.0 / 84.0,
    0.0,
];
/// Fifth-order minus fourth-order weights.
const E: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];

/// Dormand-Prince 5(4) sub-stepping. See the [module documentation](self).
#[derive(Debug, Clone)]
pub struct DormandPrince<V: Vector> {
    /// Relative tolerance per sub-step (default: `1e-6`).
    pub relative_tolerance: f64,
    /// Absolute tolerance per sub-step (default: `1e-9`).
    pub absolute_tolerance: f64,
    /// Most sub-steps one fixed step may take (default: `10_000`).
    pub max_substeps: u32,
    /// Stage velocities `k_i x` and accelerations `k_i v`.
    stage_v: [Vec<V>; 7],
    stage_a: [Vec<V>; 7],
    trial_x: Vec<V>,
    trial_v: Vec<V>,
    start_x: Vec<V>,
    start_v: Vec<V>,
    /// Sub-step size proposed by the last accepted sub-step, as a fraction of `h`.
    next_fraction: f64,
}

impl<V: Vector> Default for DormandPrince<V> {
    fn default() -> Self {
        Self::new()
    }
}

impl<V: Vector> DormandPrince<V> {
    /// Dormand-Prince with the default tolerances.
    #[must_use]
    pub fn new() -> Self {
        Self::with_tolerances(1e-6, 1e-9)
    }

    /// Dormand-Prince with the given relative and absolute tolerances.
    #[must_use]
    pub fn with_tolerances(relative_tolerance: f64, absolute_tolerance: f64) -> Self {
        Self {
            relative_tolerance,
            absolute_tolerance,
            max_substeps: 10_000,
            stage_v: Default::default(),
            stage_a: Default::default(),
            trial_x: Vec::new(),
            trial_v: Vec::new(),
            start_x: Vec::new(),
            start_v: Vec::new(),
            next_fraction: 1.0,
        }
    }

    /// Stage states `y + s sum_j A[stage][j] k_j` into the trial buffers.
    fn stage_state(&mut self, stage: usize, s: f64, x: &[V], v: &[V]) {
        let weights: [V::Real; 6] = core::array::from_fn(|j| V::Real::from_f64(A[stage][j] * s));
        for i in 0..x.len() {
            let mut tx = x[i];
            let mut tv = v[i];
            for (j, w) in weights.iter().enumerate().take(stage) {
                if A[stage][j] != 0.0 {
                    tx += self.stage_v[j][i] * *w;
                    tv += self.stage_a[j][i] * *w;
                }
            }
            self.trial_x[i] = tx;
            self.trial_v[i] = tv;
        }
    }

    /// Scaled RMS error of the embedded pair; `trial_*` hold the 5th-order result.
    fn error_norm(&self, s: f64, x: &[V], v: &[V]) -> f64 {
        let e: [V::Real; 7] = core::array::from_fn(|j| V::Real::from_f64(E[j] * s));
        let (atol, rtol) = (self.absolute_tolerance, self.relative_tolerance);
        let mut sum = 0.0;
        for i in 0..x.len() {
            let mut ex = V::ZERO;
            let mut ev = V::ZERO;
            for j in 0..7 {
                ex += self.stage_v[j][i] * e[j];
                ev += self.stage_a[j][i] * e[j];
            }
            let scale_x = atol
                + rtol
                    * x[i]
                        .length_squared()
                        .to_f64()
                        .sqrt()
                        .max(self.trial_x[i].length_squared().to_f64().sqrt());
            let scale_v = atol
                + rtol
                    * v[i]
                        .length_squared()
                        .to_f64()
                        .sqrt()
                        .max(self.trial_v[i].length_squared().to_f64().sqrt());
            sum +=
                ex.length_squared().to_f64() / (scale_x * scale_x) + ev.length_squared().to_f64() / (scale_v * scale_v);
        }
        if x.is_empty() {
            0.0
        } else {
            (sum / (2 * x.len()) as f64).sqrt()
        }
    }
}

impl<V: Vector> Integrator<V> for DormandPrince<V> {
    fn visit_state(&self, vectors: &mut dyn FnMut(&[V]), bytes: &mut dyn FnMut(&[u8])) {
        let _ = vectors; // the stages are scratch, rewritten every sub-step
        bytes(&self.next_fraction.to_le_bytes());
    }

    fn info(&self) -> MethodInfo {
        INFO
    }

    fn step(
        &mut self,
        t: V::Real,
        dt: V::Real,
        x: &mut [V],
        v: &mut [V],
        system: &mut dyn System<V>,
    ) -> Result<StepStats, StepError> {
        check_step(INFO.name, dt, x, v)?;
        let n = x.len();
        for buffer in self.stage_v.iter_mut().chain(self.stage_a.iter_mut()) {
            fit(buffer, n);
        }
        fit(&mut self.trial_x, n);
        fit(&mut self.trial_v, n);
        fit(&mut self.start_x, n);
        fit(&mut self.start_v, n);
        self.start_x.copy_from_slice(x);
        self.start_v.copy_from_slice(v);
        let h = dt.to_f64();
        let t0 = t.to_f64();
        let mut stats = StepStats::default();
        // Progress through the fixed step as a fraction of h, so the end is exact.
        let mut done = 0.0f64;
        let mut fraction = self.next_fraction.clamp(1e-12, 1.0);
        self.stage_v[0].copy_from_slice(v);
        system.acceleration(t, x, v, &mut self.stage_a[0]);
        stats.evaluations += 1;
        loop {
            let last = done + fraction >= 1.0 - 1e-12;
            let this = if last { 1.0 - done } else { fraction };
            let s = this * h;
            let ts = t0 + done * h;
            for stage in 1..7 {
                self.stage_state(stage, s, x, v);
                self.stage_v[stage].copy_from_slice(&self.trial_v);
                let t_stage = V::Real::from_f64(ts + C[stage] * s);
                system.acceleration(t_stage, &self.trial_x, &self.trial_v, &mut self.stage_a[stage]);
            }
            stats.evaluations += 6;
            // The last stage state is the fifth-order solution (A[6] = B).
            let err = self.error_norm(s, x, v);
            let factor = if err == 0.0 {
                5.0
            } else {
                (0.9 * crate::math::powf(err, -0.2)).clamp(0.2, 5.0)
            };
            if err <= 1.0 {
                x.copy_from_slice(&self.trial_x);
                v.copy_from_slice(&self.trial_v);
                self.stage_v.swap(0, 6);
                self.stage_a.swap(0, 6);
                stats.substeps += 1;
                done += this;
                if last {
                    // A last sub-step shortened to land on t + h says nothing new.
                    self.next_fraction = if this < fraction {
                        fraction
                    } else {
                        (this * factor).min(1.0)
                    };
                    break;
                }
                fraction = (this * factor).min(1.0);
            } else {
                stats.rejected_substeps += 1;
                fraction = this * if err.is_finite() { factor } else { 0.2 };
            }
            if stats.substeps + stats.rejected_substeps >= self.max_substeps || fraction < 1e-12 {
                x.copy_from_slice(&self.start_x);
                v.copy_from_slice(&self.start_v);
                return Err(StepError::SubstepLimit {
                    method: INFO.name,
                    substeps: stats.substeps + stats.rejected_substeps,
                    last_substep: fraction * h,
                });
            }
        }
        Ok(stats)
    }

    fn reset(&mut self) {
        self.next_fraction = 1.0;
    }
}

#[cfg(test)]
mod tests {
    use super::{A, B, C, E};

    #[test]
    fn tableau_is_consistent() {
        // The last stage is evaluated at the fifth-order solution (FSAL).
        assert_eq!(&A[6][..], &B[..6]);
        for (stage, row) in A.iter().enumerate() {
            let sum: f64 = row.iter().sum();
            assert!((sum - C[stage]).abs() < 1e-14, "row {stage} sums to c");
        }
        assert!((B.iter().sum::<f64>() - 1.0).abs() < 1e-14);
        assert!(E.iter().sum::<f64>().abs() < 1e-14, "both weight sets sum to 1");
    }
}

//! Matrix-free Newton-Krylov solver shared by the implicit methods.
//!
//! Every implicit method here reduces one step to a system in one unknown per
//! particle, `u` (an end velocity or an end acceleration), with the end state
//! affine in `u`:
//!
//! ```text
//! x1 = X + cx u,   v1 = W + cv u
//! F(u) = u - R - ca a(t1, x1, v1) = 0
//! J w  = w - ca (da/dx (cx w) + da/dv (cv w))
//! ```
//!
//! Newton's method solves `J du = -F` at each iteration with restarted GMRES,
//! which needs only products `J w`: from [`System::jacobian_product`] when the
//! system supplies them, otherwise by a forward difference of the acceleration
//! (`(a(x + e cx w, v + e cv w) - a(x, v)) / e`, with `e` scaled to the square
//! root of machine epsilon). No matrix is ever formed, so the cost is a few
//! force evaluations per iteration and memory of `restart + 1` vectors per
//! particle.
//!
//! Convergence is relative to the size of the residual's own terms,
//! `S = rms(u) + rms(R) + |ca| rms(a(t1, x1, v1))`:
//!
//! ```text
//! converged:  rms(F) <= tolerance * max(S, absolute_floor)
//! stagnated:  rms(F) > rms(F_previous) / 2
//!             and rms(F) <= stagnation_tolerance * max(S, stagnation_floor)
//! ```
//!
//! A relative test keeps small states exact: with an absolute part
//! (`rms(F) <= 1e-10 (1 + rms u)`, the rule before), stiff drag stopped
//! decaying once `|h b v|` fell below `1e-10`, because the first guess was
//! accepted there, and a small oscillation's one-step map was off by `1e-10`
//! absolute, a large relative error. `absolute_floor` (default `1e-30`, in
//! the unknown's units) only keeps the test defined at an exact zero.
//! Once Newton stagnates (an iteration no longer halves the residual), the
//! residual has reached the round-off floor of the force evaluation, about
//! `eps |da/dx| |x|`: absolute, since it comes from the size of the positions,
//! and for stiff springs in `f32` far above 64 epsilons (k/m = 40 000 s^-2 at
//! |x| = 5 m gives a floor near 1e-3 of the acceleration), so that test keeps
//! an absolute floor (`stagnation_floor`, default `1`). Each linear solve is
//! inexact (relative residual `krylov_tolerance`), which keeps Newton's fast
//! convergence near the solution. A solve that reaches neither within its caps
//! is reported as [`StepError::NotConverged`]; there is no line search, so a
//! strongly nonlinear force at a large step may also fail, and says so.

use crate::integrator::{StepError, StepStats, fit};
use crate::system::System;
use crate::vector::{Real, Vector};

/// Tolerances and caps of the implicit solve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewtonKrylovConfig {
    /// RMS residual, relative to the size of the residual's terms, at which
    /// Newton stops (default: `1e-10`, but at least 64 machine epsilons of the
    /// scalar type).
    pub tolerance: f64,
    /// Smallest size of the residual's terms that `tolerance` is taken
    /// relative to, in the unknown's units (m/s or m/s^2), so that the test is
    /// defined at an exact zero (default: `1e-30`). Raise it to accept an
    /// absolute error on states near zero.
    pub absolute_floor: f64,
    /// Maximum Newton iterations per step (default: `20`).
    pub max_newton_iterations: u32,
    /// Relative residual each GMRES solve aims for (default: `1e-6`).
    pub krylov_tolerance: f64,
    /// GMRES restart length, the number of basis vectors kept (default: `20`).
    pub restart: usize,
    /// Maximum GMRES iterations per Newton iteration, restarts included (default: `100`).
    pub max_krylov_iterations: u32,
    /// Relative RMS residual accepted once Newton stagnates at the round-off
    /// floor (default: `2e-2` for `f32`, where a cloth of stiff springs
    /// measured floors of 1e-4 to 6e-3; `6.1e-6`, the cube root of epsilon,
    /// for `f64`).
    pub stagnation_tolerance: f64,
    /// Smallest size of the residual's terms that `stagnation_tolerance` is
    /// taken relative to, in the unknown's units (default: `1`): the round-off
    /// floor of stiff forces comes from the size of the positions, not of the
    /// unknown, so it is not relative to a small unknown.
    pub stagnation_floor: f64,
}

impl NewtonKrylovConfig {
    /// The defaults for scalar type `R`.
    #[must_use]
    pub fn for_real<R: Real>() -> Self {
        Self {
            tolerance: f64::max(1e-10, 64.0 * R::epsilon().to_f64()),
            absolute_floor: 1e-30,
            max_newton_iterations: 20,
            krylov_tolerance: 1e-6,
            restart: 20,
            max_krylov_iterations: 100,
            stagnation_tolerance: if R::epsilon().to_f64() > 1e-10 {
                2e-2
            } else {
                crate::math::cbrt(R::epsilon().to_f64())
            },
            stagnation_floor: 1.0,
        }
    }
}

/// The affine map from the unknown to the end state, and the residual's terms.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Coefficients<R> {
    pub t1: R,
    pub cx: R,
    pub cv: R,
    pub ca: R,
}

/// Buffers of the solver; the method fills `base_x`, `base_v`, `rhs` and the
/// initial guess `u`, then calls [`NewtonKrylov::solve`].
#[derive(Debug, Clone, Default)]
pub(crate) struct NewtonKrylov<V: Vector> {
    /// `X`: end positions at `u = 0`.
    pub base_x: Vec<V>,
    /// `W`: end velocities at `u = 0`.
    pub base_v: Vec<V>,
    /// `R`: constant part of the residual.
    pub rhs: Vec<V>,
    /// The unknown; holds the solution after a successful solve.
    pub u: Vec<V>,
    /// End state for the current `u`.
    pub x1: Vec<V>,
    pub v1: Vec<V>,
    accel: Vec<V>,
    residual: Vec<V>,
    delta: Vec<V>,
    basis: Vec<Vec<V>>,
    work: Vec<V>,
    probe_x: Vec<V>,
    probe_v: Vec<V>,
    probe_a: Vec<V>,
    /// Hessenberg matrix, column-major `(restart + 1) x restart`, and Givens rotations.
    hessenberg: Vec<f64>,
    cosines: Vec<f64>,
    sines: Vec<f64>,
    g: Vec<f64>,
    y: Vec<f64>,
}

fn rms<V: Vector>(values: &[V]) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    let sum: f64 = values.iter().map(|v| v.dot(*v).to_f64()).sum();
    (sum / (values.len() * V::DIM) as f64).sqrt()
}

fn dot<V: Vector>(a: &[V], b: &[V]) -> f64 {
    a.iter().zip(b).map(|(a, b)| a.dot(*b).to_f64()).sum()
}

impl<V: Vector> NewtonKrylov<V> {
    /// Sizes every per-particle buffer for `n` particles.
    pub(crate) fn fit(&mut self, n: usize, config: &NewtonKrylovConfig) {
        for buffer in [
            &mut self.base_x,
            &mut self.base_v,
            &mut self.rhs,
            &mut self.u,
            &mut self.x1,
            &mut self.v1,
            &mut self.accel,
            &mut self.residual,
            &mut self.delta,
            &mut self.work,
            &mut self.probe_x,
            &mut self.probe_v,
            &mut self.probe_a,
        ] {
            fit(buffer, n);
        }
        let m = config.restart.max(1);
        if self.basis.len() != m + 1 {
            self.basis.resize_with(m + 1, Vec::new);
        }
        for vector in &mut self.basis {
            fit(vector, n);
        }
        if self.hessenberg.len() != (m + 1) * m {
            self.hessenberg.resize((m + 1) * m, 0.0);
            self.cosines.resize(m, 0.0);
            self.sines.resize(m, 0.0);
            self.g.resize(m + 1, 0.0);
            self.y.resize(m, 0.0);
        }
    }

    /// Sets `x1, v1` from `u` and evaluates `a(t1, x1, v1)` and the residual;
    /// returns `rms(F)` and the size of its terms, `rms(u) + rms(R) + |ca| rms(a)`.
    fn evaluate_residual(&mut self, k: &Coefficients<V::Real>, system: &mut dyn System<V>) -> (f64, f64) {
        for i in 0..self.u.len() {
            self.x1[i] = self.base_x[i] + self.u[i] * k.cx;
            self.v1[i] = self.base_v[i] + self.u[i] * k.cv;
        }
        system.acceleration(k.t1, &self.x1, &self.v1, &mut self.accel);
        for i in 0..self.u.len() {
            self.residual[i] = self.u[i] - self.rhs[i] - self.accel[i] * k.ca;
        }
        let terms = rms(&self.u) + rms(&self.rhs) + k.ca.to_f64().abs() * rms(&self.accel);
        (rms(&self.residual), terms)
    }

    /// `out = J w` at the current `(x1, v1)`; returns the evaluations it cost.
    fn jacobian_times(&mut self, k: &Coefficients<V::Real>, w_index: usize, system: &mut dyn System<V>) -> u32 {
        let n = self.u.len();
        let w = &self.basis[w_index];
        for i in 0..n {
            self.probe_x[i] = w[i] * k.cx;
            self.probe_v[i] = w[i] * k.cv;
        }
        let mut evaluations = 0;
        let supplied = system.jacobian_product(
            k.t1,
            &self.x1,
            &self.v1,
            &self.probe_x,
            &self.probe_v,
            &mut self.probe_a,
        );
        if !supplied {
            // Forward difference with e ~ sqrt(eps) (1 + |state|) / |direction|.
            let scale = 1.0 + rms(&self.x1).max(rms(&self.v1));
            let direction = rms(&self.probe_x).max(rms(&self.probe_v));
            if direction == 0.0 {
                self.probe_a.fill(V::ZERO);
            } else {
                let e = V::Real::epsilon().to_f64().sqrt() * scale / direction;
                let e_real = V::Real::from_f64(e);
                for i in 0..n {
                    self.probe_x[i] = self.x1[i] + self.probe_x[i] * e_real;
                    self.probe_v[i] = self.v1[i] + self.probe_v[i] * e_real;
                }
                system.acceleration(k.t1, &self.probe_x, &self.probe_v, &mut self.probe_a);
                evaluations += 1;
                let inv_e = V::Real::from_f64(1.0 / e);
                for i in 0..n {
                    self.probe_a[i] = (self.probe_a[i] - self.accel[i]) * inv_e;
                }
            }
        }
        let w = &self.basis[w_index];
        for i in 0..n {
            self.work[i] = w[i] - self.probe_a[i] * k.ca;
        }
        evaluations
    }

    /// Solves `J delta = -F` by restarted GMRES; returns (evaluations, iterations).
    fn gmres(
        &mut self,
        k: &Coefficients<V::Real>,
        config: &NewtonKrylovConfig,
        system: &mut dyn System<V>,
    ) -> (u32, u32) {
        let n = self.u.len();
        let m = config.restart.max(1);
        let mut evaluations = 0;
        let mut iterations = 0;
        self.delta.fill(V::ZERO);
        // r0 = -F (delta starts at 0).
        for i in 0..n {
            self.basis[0][i] = -self.residual[i];
        }
        let b_norm = dot(&self.basis[0], &self.basis[0]).sqrt();
        if b_norm == 0.0 {
            return (0, 0);
        }
        let target = config.krylov_tolerance * b_norm;
        let mut beta = b_norm;
        loop {
            let inv = V::Real::from_f64(1.0 / beta);
            for value in &mut self.basis[0] {
                *value = *value * inv;
            }
            self.g.fill(0.0);
            self.g[0] = beta;
            let mut columns = 0;
            let mut residual = beta;
            for j in 0..m {
                evaluations += self.jacobian_times(k, j, system);
                iterations += 1;
                // Modified Gram-Schmidt against the basis so far.
                for i in 0..=j {
                    let h = dot(&self.work, &self.basis[i]);
                    self.hessenberg[j * (m + 1) + i] = h;
                    let h_real = V::Real::from_f64(h);
                    for (w, b) in self.work.iter_mut().zip(&self.basis[i]) {
                        *w -= *b * h_real;
                    }
                }
                let h_next = dot(&self.work, &self.work).sqrt();
                self.hessenberg[j * (m + 1) + j + 1] = h_next;
                if h_next > 0.0 {
                    let inv = V::Real::from_f64(1.0 / h_next);
                    for idx in 0..n {
                        self.basis[j + 1][idx] = self.work[idx] * inv;
                    }
                }
                // Apply the earlier rotations to the new column, then a new one.
                let col = j * (m + 1);
                for i in 0..j {
                    let (a, b) = (self.hessenberg[col + i], self.hessenberg[col + i + 1]);
                    self.hessenberg[col + i] = self.cosines[i] * a + self.sines[i] * b;
                    self.hessenberg[col + i + 1] = -self.sines[i] * a + self.cosines[i] * b;
                }
                let (a, b) = (self.hessenberg[col + j], self.hessenberg[col + j + 1]);
                let r = crate::math::hypot(a, b);
                let (cs, sn) = if r == 0.0 { (1.0, 0.0) } else { (a / r, b / r) };
                self.cosines[j] = cs;
                self.sines[j] = sn;
                self.hessenberg[col + j] = r;
                self.hessenberg[col + j + 1] = 0.0;
                self.g[j + 1] = -sn * self.g[j];
                self.g[j] *= cs;
                residual = self.g[j + 1].abs();
                columns = j + 1;
                if residual <= target || h_next == 0.0 || iterations >= config.max_krylov_iterations {
                    break;
                }
            }
            // Back substitution: H y = g, then delta += sum y_i basis_i.
            for i in (0..columns).rev() {
                let mut s = self.g[i];
                for l in i + 1..columns {
                    s -= self.hessenberg[l * (m + 1) + i] * self.y[l];
                }
                let diag = self.hessenberg[i * (m + 1) + i];
                self.y[i] = if diag == 0.0 { 0.0 } else { s / diag };
            }
            for i in 0..columns {
                let yi = V::Real::from_f64(self.y[i]);
                for (d, b) in self.delta.iter_mut().zip(&self.basis[i]) {
                    *d += *b * yi;
                }
            }
            if residual <= target || iterations >= config.max_krylov_iterations {
                return (evaluations, iterations);
            }
            // Restart from the true residual r = -F - J delta.
            self.basis[0].copy_from_slice(&self.delta);
            evaluations += self.jacobian_times(k, 0, system);
            for i in 0..n {
                self.basis[0][i] = -self.residual[i] - self.work[i];
            }
            beta = dot(&self.basis[0], &self.basis[0]).sqrt();
            if beta <= target {
                return (evaluations, iterations);
            }
        }
    }

    /// Runs Newton from the initial guess in `u` and, on success, writes the
    /// end state into `x` and `v`. `extra_evaluations` are the method's own
    /// (a start acceleration), added to the report. On failure `x` and `v`
    /// are untouched.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn solve_into(
        &mut self,
        method: &'static str,
        k: Coefficients<V::Real>,
        config: &NewtonKrylovConfig,
        system: &mut dyn System<V>,
        x: &mut [V],
        v: &mut [V],
        extra_evaluations: u32,
    ) -> Result<StepStats, StepError> {
        let mut stats = StepStats {
            evaluations: extra_evaluations,
            substeps: 1,
            ..StepStats::default()
        };
        let mut previous = f64::INFINITY;
        loop {
            let (residual, terms) = self.evaluate_residual(&k, system);
            stats.evaluations += 1;
            let relative = residual / terms.max(config.absolute_floor);
            let stagnated = residual > 0.5 * previous
                && residual <= config.stagnation_tolerance * terms.max(config.stagnation_floor);
            previous = residual;
            if relative <= config.tolerance || stagnated {
                x.copy_from_slice(&self.x1);
                v.copy_from_slice(&self.v1);
                return Ok(stats);
            }
            if stats.newton_iterations >= config.max_newton_iterations || !relative.is_finite() {
                return Err(StepError::NotConverged {
                    method,
                    iterations: stats.newton_iterations,
                    residual: relative,
                    tolerance: config.tolerance,
                });
            }
            let (evaluations, iterations) = self.gmres(&k, config, system);
            stats.evaluations += evaluations;
            stats.krylov_iterations += iterations;
            stats.newton_iterations += 1;
            for (u, d) in self.u.iter_mut().zip(&self.delta) {
                *u += *d;
            }
        }
    }
}

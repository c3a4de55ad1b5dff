//! The shared core of the Adams-Bashforth methods (linear multistep): the
//! new state from the derivatives at the last `K` steps.
//!
//! ```text
//! x(t + h) = x + h sum_j beta_j v(t - j h)
//! v(t + h) = v + h sum_j beta_j a(t - j h),     j = 0 .. K-1
//! ```
//!
//! One evaluation per step, `K - 1` past derivatives per particle as history.
//! A particle with fewer (first steps, a new particle, or one whose state was
//! changed outside the step) takes RK4 steps until it has them. RK4 is the
//! usual start for AB methods of order up to 4: one-step errors of order 5 do
//! not spoil the method's order. The files `adams_bashforth2.rs`,
//! `adams_bashforth3.rs` and `adams_bashforth4.rs` document each method.

use crate::history::{History, swap_remove_in};
use crate::integrator::{Integrator, MethodInfo, StepError, StepStats, check_step, fit};
use crate::methods::rk4::Rk4Stages;
use crate::system::System;
use crate::vector::{Real, Vector};

/// The weights `b_j` of Adams-Bashforth of `steps` steps (2, 3 or 4; `None`
/// otherwise), newest first: `x(t + h) = x + h sum_j b_j v(t - j h)`. A step
/// multiplies each by `h` in `f64` and rounds once (`beta_j`); the GPU
/// step forms its betas from these, so that both round the same products.
#[must_use]
pub fn coefficients(steps: usize) -> Option<&'static [f64]> {
    match steps {
        2 => Some(&[3.0 / 2.0, -1.0 / 2.0]),
        3 => Some(&[23.0 / 12.0, -16.0 / 12.0, 5.0 / 12.0]),
        4 => Some(&[55.0 / 24.0, -59.0 / 24.0, 37.0 / 24.0, -9.0 / 24.0]),
        _ => None,
    }
}

/// Adams-Bashforth of `K` steps (order `K`); use the aliases
/// [`AdamsBashforth2`](crate::AdamsBashforth2), [`AdamsBashforth3`](crate::AdamsBashforth3),
/// [`AdamsBashforth4`](crate::AdamsBashforth4).
#[derive(Debug, Clone)]
pub struct AdamsBashforth<V: Vector, const K: usize> {
    /// Past velocities, ring of `K - 1` slots; slot `newest` holds lag 1.
    past_v: Vec<Vec<V>>,
    /// Past accelerations, same ring.
    past_a: Vec<Vec<V>>,
    newest: usize,
    accel: Vec<V>,
    bootstrap: Rk4Stages<V>,
    history: History<V>,
}

impl<V: Vector, const K: usize> Default for AdamsBashforth<V, K> {
    fn default() -> Self {
        Self::new()
    }
}

impl<V: Vector, const K: usize> AdamsBashforth<V, K> {
    /// A new Adams-Bashforth integrator.
    ///
    /// # Panics
    /// At compile time use only `K` in `2..=4` (the registered methods).
    #[must_use]
    pub fn new() -> Self {
        const { assert!(K >= 2 && K <= 4, "Adams-Bashforth is provided for 2, 3 and 4 steps") };
        Self {
            past_v: vec![Vec::new(); K - 1],
            past_a: vec![Vec::new(); K - 1],
            newest: 0,
            accel: Vec::new(),
            bootstrap: Rk4Stages::default(),
            history: History::default(),
        }
    }

    fn coefficients() -> &'static [f64] {
        coefficients(K).unwrap_or(&[])
    }
}

impl<V: Vector, const K: usize> Integrator<V> for AdamsBashforth<V, K> {
    fn visit_state(&self, vectors: &mut dyn FnMut(&[V]), bytes: &mut dyn FnMut(&[u8])) {
        for past in self.past_v.iter().chain(&self.past_a) {
            vectors(past);
        }
        bytes(&(self.newest as u64).to_le_bytes());
        self.history.visit(vectors, bytes);
    }

    fn info(&self) -> MethodInfo {
        match K {
            2 => super::adams_bashforth2::INFO,
            3 => super::adams_bashforth3::INFO,
            _ => super::adams_bashforth4::INFO,
        }
    }

    fn step(
        &mut self,
        t: V::Real,
        dt: V::Real,
        x: &mut [V],
        v: &mut [V],
        system: &mut dyn System<V>,
    ) -> Result<StepStats, StepError> {
        check_step(self.info().name, dt, x, v)?;
        let n = x.len();
        fit(&mut self.accel, n);
        for slot in self.past_v.iter_mut().chain(self.past_a.iter_mut()) {
            fit(slot, n);
        }
        let required = (K - 1) as u8;
        let starting = self.history.sync(dt, x, v, required);
        system.acceleration(t, x, v, &mut self.accel);
        let mut evaluations = 1;
        if starting > 0 {
            self.bootstrap
                .run_starting(t, dt, x, v, &self.accel, system, self.history.starting(required));
            evaluations += 3;
        }
        let beta: [V::Real; K] = core::array::from_fn(|j| V::Real::from_f64(Self::coefficients()[j] * dt.to_f64()));
        let slots = K - 1;
        // The oldest slot is overwritten with the current derivatives and becomes lag 1.
        let oldest = (self.newest + slots - 1) % slots;
        for i in 0..n {
            let (v_now, a_now) = (v[i], self.accel[i]);
            if self.history.has(i, required) {
                let mut dx = v_now * beta[0];
                let mut dv = a_now * beta[0];
                for (lag, b) in beta.iter().enumerate().skip(1) {
                    let slot = (self.newest + lag - 1) % slots;
                    dx += self.past_v[slot][i] * *b;
                    dv += self.past_a[slot][i] * *b;
                }
                x[i] += dx;
                v[i] += dv;
            } else {
                let (new_x, new_v) = self.bootstrap.result(i, x[i], v_now);
                x[i] = new_x;
                v[i] = new_v;
            }
            self.past_v[oldest][i] = v_now;
            self.past_a[oldest][i] = a_now;
        }
        self.newest = oldest;
        self.history.record(dt, x, v);
        Ok(StepStats {
            bootstrapped: starting as u32,
            ..StepStats::single(evaluations)
        })
    }

    fn swap_remove(&mut self, index: usize, rows: usize) {
        if self.history.swap_remove(index, rows) {
            for slot in self.past_v.iter_mut().chain(self.past_a.iter_mut()) {
                swap_remove_in(slot, index);
            }
        }
    }

    fn reset(&mut self) {
        self.history.reset();
    }
}

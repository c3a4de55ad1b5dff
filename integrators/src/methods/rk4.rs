//! Classical fourth-order Runge-Kutta (RK4).
//!
//! On the first-order system `y = (x, v)`, `y' = (v, a(t, x, v))`, with the
//! lecture's velocity-dependent stages:
//!
//! ```text
//! k1 = (v,              a(t,       x,               v))
//! k2 = (v + h/2 k1v,    a(t + h/2, x + h/2 k1x,     v + h/2 k1v))
//! k3 = (v + h/2 k2v,    a(t + h/2, x + h/2 k2x,     v + h/2 k2v))
//! k4 = (v + h k3v,      a(t + h,   x + h k3x,       v + h k3v))
//! y(t + h) = y + h/6 (k1 + 2 k2 + 2 k3 + k4)
//! ```
//!
//! - Order 4 for positions and velocities, with or without drag.
//! - Cost: 4 force evaluations per step.
//! - Stability: on the undamped oscillator stable for `h omega <= 2 sqrt(2)`
//!   (about 2.83), with slight numerical damping below it; neither symplectic
//!   nor reversible, so energy drifts slowly over very long runs.
//!
//! The stage loop is also the bootstrap of the history methods
//! (`Rk4Stages`): they restart a particle that has no history by one RK4 step.

use core::ops::Range;

use crate::chunks::for_each_chunk;
use crate::integrator::{Integrator, MethodInfo, StepError, StepStats, check_step, fit};
use crate::system::System;
use crate::vector::{Real, Vector, c};

/// Registry entry.
pub const INFO: MethodInfo = MethodInfo {
    name: "rk4",
    aliases: &["runge_kutta", "runge_kutta4", "classical_rk4"],
    title: "Runge-Kutta 4",
    notes: "",
    order: 4,
    order_velocity: 4,
    order_velocity_forces: 4,
    evaluations: 4,
    ..MethodInfo::EXPLICIT
};

/// The four stages of RK4 with their scratch buffers, computed for all
/// particles ([`Rk4Stages::run`]) or for runs of them
/// ([`Rk4Stages::run_starting`], the restart of history methods); the result
/// is applied to all ([`Rk4Stages::apply_all`]) or read per particle
/// ([`Rk4Stages::result`]).
#[derive(Debug, Clone, Default)]
pub(crate) struct Rk4Stages<V: Vector> {
    trial_x: Vec<V>,
    trial_v: Vec<V>,
    accel: Vec<V>,
    /// `k1x + 2 k2x + 2 k3x + k4x`
    sum_x: Vec<V>,
    /// `k1v + 2 k2v + 2 k3v + k4v`
    sum_v: Vec<V>,
    h: Option<V::Real>,
}

impl<V: Vector> Rk4Stages<V> {
    /// Runs the stages from `(t, x, v)` over `h`, given the first-stage
    /// accelerations `a1 = a(t, x, v)`. Costs 3 evaluations.
    pub(crate) fn run(&mut self, t: V::Real, h: V::Real, x: &[V], v: &[V], a1: &[V], system: &mut dyn System<V>) {
        self.fit(x.len());
        self.stages(t, h, x, v, a1, system, 0..x.len(), false);
    }

    /// The bootstrap of a history method: the stages for the particles in
    /// `runs` (those short of history) only, when the system is pointwise, so
    /// a few bounced particles cost a few RK4 steps, not one over everyone.
    /// `a1` need only hold the runs' accelerations then. Bit-identical to
    /// [`run`](Self::run) for those particles: each particle's arithmetic
    /// is the same, and a pointwise system's
    /// [`acceleration_range`](System::acceleration_range) equals its
    /// whole-slice acceleration. A coupled system (springs) steps everyone,
    /// as a stage must see every particle's trial state.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn run_starting(
        &mut self,
        t: V::Real,
        h: V::Real,
        x: &[V],
        v: &[V],
        a1: &[V],
        system: &mut dyn System<V>,
        runs: impl Iterator<Item = Range<usize>>,
    ) {
        self.fit(x.len());
        if system.is_pointwise() {
            for run in runs {
                self.stages(t, h, x, v, a1, system, run, true);
            }
        } else {
            self.stages(t, h, x, v, a1, system, 0..x.len(), false);
        }
    }

    /// `out = a(t, x, v)` for what [`run_starting`](Self::run_starting)
    /// needs as its `a1`: the runs only for a pointwise system, else everyone.
    pub(crate) fn first_stage(
        t: V::Real,
        x: &[V],
        v: &[V],
        out: &mut [V],
        system: &mut dyn System<V>,
        runs: impl Iterator<Item = Range<usize>>,
    ) {
        if system.is_pointwise() {
            for r in runs {
                system.acceleration_range(t, r.start, &x[r.clone()], &v[r.clone()], &mut out[r]);
            }
        } else {
            system.acceleration(t, x, v, out);
        }
    }

    fn fit(&mut self, n: usize) {
        for buffer in [
            &mut self.trial_x,
            &mut self.trial_v,
            &mut self.accel,
            &mut self.sum_x,
            &mut self.sum_v,
        ] {
            fit(buffer, n);
        }
    }

    /// The stages for the particles in `range`; `ranged` evaluates the
    /// system on that range alone (pointwise systems), else on all particles
    /// (then `range` is all of them).
    #[allow(clippy::too_many_arguments)]
    fn stages(
        &mut self,
        t: V::Real,
        h: V::Real,
        x: &[V],
        v: &[V],
        a1: &[V],
        system: &mut dyn System<V>,
        range: Range<usize>,
        ranged: bool,
    ) {
        let first = range.start;
        let half = h * c(0.5);
        let two: V::Real = c(2.0);
        let Self {
            trial_x,
            trial_v,
            accel,
            sum_x,
            sum_v,
            ..
        } = self;
        // Local slices of equal length let the compiler drop bounds checks.
        let (x, v, a1) = (&x[range.clone()], &v[range.clone()], &a1[range.clone()]);
        let (tx, tv, acc) = (
            &mut trial_x[range.clone()],
            &mut trial_v[range.clone()],
            &mut accel[range.clone()],
        );
        let (sx, sv) = (&mut sum_x[range.clone()], &mut sum_v[range]);
        let n = x.len();
        let (tx, tv, acc, sx, sv) = (&mut tx[..n], &mut tv[..n], &mut acc[..n], &mut sx[..n], &mut sv[..n]);
        let mut evaluate = |t: V::Real, tx: &[V], tv: &[V], acc: &mut [V]| {
            if ranged {
                system.acceleration_range(t, first, tx, tv, acc);
            } else {
                system.acceleration(t, tx, tv, acc);
            }
        };
        for i in 0..n {
            sx[i] = v[i];
            sv[i] = a1[i];
            tx[i] = x[i] + v[i] * half;
            tv[i] = v[i] + a1[i] * half;
        }
        // Stages 2 and 3: k_x is the trial velocity, k_v the acceleration there;
        // the next trial state moves by h/2 (stage 2) or h (stage 3) along them.
        for offset in [half, h] {
            evaluate(t + half, tx, tv, acc);
            for i in 0..n {
                let (kx, kv) = (tv[i], acc[i]);
                sx[i] += kx * two;
                sv[i] += kv * two;
                tx[i] = x[i] + kx * offset;
                tv[i] = v[i] + kv * offset;
            }
        }
        // Stage 4.
        evaluate(t + h, tx, tv, acc);
        for i in 0..n {
            sx[i] += tv[i];
            sv[i] += acc[i];
        }
        self.h = Some(h);
    }

    /// The RK4 result for particle `i` starting from `(x, v)`.
    #[inline]
    pub(crate) fn result(&self, i: usize, x: V, v: V) -> (V, V) {
        let h6 = self.h.unwrap_or(V::Real::ZERO) * c(1.0 / 6.0);
        (x + self.sum_x[i] * h6, v + self.sum_v[i] * h6)
    }

    /// Applies the step to every particle.
    pub(crate) fn apply_all(&self, x: &mut [V], v: &mut [V]) {
        let h6 = self.h.unwrap_or(V::Real::ZERO) * c(1.0 / 6.0);
        for (((x, v), sx), sv) in x.iter_mut().zip(v.iter_mut()).zip(&self.sum_x).zip(&self.sum_v) {
            *x += *sx * h6;
            *v += *sv * h6;
        }
    }
}

/// Classical RK4. See the [module documentation](self).
#[derive(Debug, Clone, Default)]
pub struct Rk4<V: Vector> {
    stages: Rk4Stages<V>,
    a1: Vec<V>,
}

impl<V: Vector> Rk4<V> {
    /// A new RK4 integrator with empty scratch buffers.
    #[must_use]
    pub fn new() -> Self {
        Self {
            stages: Rk4Stages::default(),
            a1: Vec::new(),
        }
    }
}

impl<V: Vector> Integrator<V> for Rk4<V> {
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
        let Self { stages, a1 } = self;
        for_each_chunk(x, v, system, |x, v, system| {
            fit(a1, x.len());
            system.acceleration(t, x, v, a1);
            stages.run(t, dt, x, v, a1, system);
            stages.apply_all(x, v);
        });
        Ok(StepStats::single(4))
    }
}

//! Semi-implicit Euler with the linear drag taken backward: the lecture's
//! `v(t + dt) = v(t) / (1 + dt b)`, in the split form Box2D uses.
//!
//! ```text
//! f = a(t, x, v) + b v                  (the drag-free acceleration)
//! v(t + h) = (v + h f) / (1 + h b)
//! x(t + h) = x + h v(t + h)
//! ```
//!
//! `b` is the system's declared linear drag ([`System::linear_drag`]); the
//! drag part is solved backward (implicitly), and in closed form because it
//! is linear, while the other forces are taken explicitly as in
//! [semi-implicit Euler](crate::SemiImplicitEuler). With `b = 0` it is
//! semi-implicit Euler exactly; on pure drag it is the lecture's backward
//! Euler `v / (1 + h b)` exactly.
//!
//! Beside [`ImplicitEuler`](crate::ImplicitEuler), which solves the whole
//! force backward by Newton-Krylov, this costs one evaluation and no solve,
//! and it never fails to converge; the price is that only the declared
//! linear drag is treated implicitly (quadratic drag and stiff springs are
//! explicit, with semi-implicit Euler's limits).
//!
//! - Order 1 for positions and velocities.
//! - Cost: 1 force evaluation per step.
//! - Stability: unconditionally stable for the drag part (the factor
//!   `1 / (1 + h b)` lies in `(0, 1]` for every `h b >= 0`, and never
//!   reverses the velocity as explicit Euler's `1 - h b` does past `h b = 1`);
//!   stable on the undamped oscillator for `h omega < 2`, and symplectic
//!   there, as semi-implicit Euler.

use crate::chunks::for_each_chunk;
use crate::integrator::{Integrator, MethodInfo, StepError, StepStats, check_step, fit};
use crate::system::System;
use crate::vector::{Real, Vector};

/// Registry entry.
pub const INFO: MethodInfo = MethodInfo {
    name: "implicit_drag_euler",
    aliases: &["backward_drag_euler", "box2d_euler"],
    title: "Semi-implicit Euler, drag backward (Box2D)",
    notes: "semi-implicit Euler with the drag backward, `(v + h f)/(1 + h b)` (Box2D); one evaluation, no solve",
    order: 1,
    order_velocity: 1,
    order_velocity_forces: 1,
    evaluations: 1,
    symplectic: true,
    ..MethodInfo::EXPLICIT
};

/// Semi-implicit Euler with backward-Euler drag. See the [module documentation](self).
#[derive(Debug, Clone, Default)]
pub struct ImplicitDragEuler<V: Vector> {
    accel: Vec<V>,
}

impl<V: Vector> ImplicitDragEuler<V> {
    /// A new integrator.
    #[must_use]
    pub fn new() -> Self {
        Self { accel: Vec::new() }
    }
}

impl<V: Vector> Integrator<V> for ImplicitDragEuler<V> {
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
        let b = system.linear_drag();
        // 1 / (1 + h b) rounded once from f64: exactly 1 when b = 0, so the
        // method is then semi-implicit Euler bit for bit.
        let damping = V::Real::from_f64(1.0 / (1.0 + dt.to_f64() * b.to_f64()));
        let accel = &mut self.accel;
        for_each_chunk(x, v, system, |x, v, system| {
            fit(accel, x.len());
            system.acceleration(t, x, v, accel);
            kick_drift_damped(x, v, accel, b, dt, damping);
        });
        Ok(StepStats::single(1))
    }
}

/// `v = (v + h (a + b v)) / (1 + h b); x += h v`, with the slices and scalars
/// as arguments the compiler knows do not alias (as semi-implicit Euler's).
#[inline]
fn kick_drift_damped<V: Vector>(x: &mut [V], v: &mut [V], a: &[V], b: V::Real, h: V::Real, damping: V::Real) {
    for ((x, v), a) in x.iter_mut().zip(v.iter_mut()).zip(a) {
        let drag_free = *a + *v * b;
        *v = (*v + drag_free * h) * damping;
        *x += *v * h;
    }
}

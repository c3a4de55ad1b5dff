//! Exponential Euler: exact for the linear-drag part, Euler for the rest.
//!
//! With the system's linear drag `b` split off, `a = g(t, x, v) - b v`, and `g`
//! frozen at the start of the step, the pair `x' = v, v' = g - b v` is solved
//! exactly over the step:
//!
//! ```text
//! z = b h,   phi1 = (1 - e^-z) / z,   phi2 = (z - 1 + e^-z) / z^2
//! g = a(t, x, v) + b v
//! v(t + h) = e^-z v + h phi1 g
//! x(t + h) = x + h phi1 v + h^2 phi2 g
//! ```
//!
//! This is the first-order exponential time-differencing form (ETD1), applied
//! to both position and velocity. It was chosen over the common velocity-only
//! form (`v <- e^-z v + ...`, then `x <- x + h v`) because it is exact for a
//! particle under constant force and linear drag (a projectile in air, a
//! particle settling under gravity), which is what games use it for. With
//! `b = 0` it reduces to `v + h a`, `x + h v + h^2/2 a`.
//!
//! - Order 1 for positions and velocities.
//! - Cost: 1 force evaluation per step.
//! - Stability: unconditionally stable for the drag part (any `h b`), since
//!   `e^-z` never exceeds 1; the remaining forces are treated explicitly, so
//!   stiff springs still need a small `h`. `phi1` and `phi2` are evaluated by
//!   their Taylor series for small `z` to avoid cancellation.

use crate::chunks::for_each_chunk;
use crate::integrator::{Integrator, MethodInfo, StepError, StepStats, check_step, fit};
use crate::system::System;
use crate::vector::{Real, Vector};

/// Registry entry.
pub const INFO: MethodInfo = MethodInfo {
    name: "exponential_euler",
    aliases: &["exp_euler", "etd1"],
    title: "Exponential Euler",
    notes: "exact for constant force plus linear drag",
    order: 1,
    order_velocity: 1,
    order_velocity_forces: 1,
    evaluations: 1,
    ..MethodInfo::EXPLICIT
};

/// `(e^-z, phi1(z), phi2(z))` in `f64`, accurate for every `z`.
pub(crate) fn phi(z: f64) -> (f64, f64, f64) {
    let decay = crate::math::exp(-z);
    if z.abs() < 0.1 {
        // phi_k(z) = sum_j (-z)^j / (j + k)!, truncated where the next term is below 1e-15.
        let mut phi1 = 0.0;
        let mut phi2 = 0.0;
        let mut power = 1.0; // (-z)^j
        let mut fact1 = 1.0; // (j + 1)!
        let mut fact2 = 2.0; // (j + 2)!
        for j in 0..9 {
            phi1 += power / fact1;
            phi2 += power / fact2;
            power *= -z;
            fact1 *= (j + 2) as f64;
            fact2 *= (j + 3) as f64;
        }
        (decay, phi1, phi2)
    } else {
        let phi1 = -crate::math::exp_m1(-z) / z;
        let phi2 = (z + crate::math::exp_m1(-z)) / (z * z);
        (decay, phi1, phi2)
    }
}

/// Exponential Euler. See the [module documentation](self).
#[derive(Debug, Clone, Default)]
pub struct ExponentialEuler<V: Vector> {
    accel: Vec<V>,
}

impl<V: Vector> ExponentialEuler<V> {
    /// A new exponential Euler integrator.
    #[must_use]
    pub fn new() -> Self {
        Self { accel: Vec::new() }
    }
}

impl<V: Vector> Integrator<V> for ExponentialEuler<V> {
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
        let h = dt.to_f64();
        let (decay, phi1, phi2) = phi(b.to_f64() * h);
        let decay = V::Real::from_f64(decay);
        let h_phi1 = V::Real::from_f64(h * phi1);
        let h2_phi2 = V::Real::from_f64(h * h * phi2);
        let accel = &mut self.accel;
        for_each_chunk(x, v, system, |x, v, system| {
            fit(accel, x.len());
            system.acceleration(t, x, v, accel);
            for ((x, v), a) in x.iter_mut().zip(v.iter_mut()).zip(accel.iter()) {
                let g = *a + *v * b;
                *x += *v * h_phi1 + g * h2_phi2;
                *v = *v * decay + g * h_phi1;
            }
        });
        Ok(StepStats::single(1))
    }
}

#[cfg(test)]
mod tests {
    use super::phi;

    /// phi_k by its series with 40 terms: a reference for |z| <= 1.
    fn reference(z: f64, k: u32) -> f64 {
        let mut sum = 0.0;
        let mut term = 1.0 / (1..=k).map(f64::from).product::<f64>();
        for j in 0..40u32 {
            sum += term;
            term *= -z / f64::from(j + k + 1);
        }
        sum
    }

    #[test]
    fn phi_is_accurate_on_both_sides_of_the_series_switch() {
        for z in [1e-9, 1e-4, 0.05, 0.0999999, 0.1, 0.1000001, 0.5, 1.0, -0.0999999, -0.5] {
            let (decay, phi1, phi2) = phi(z);
            assert!((decay - crate::math::exp(-z)).abs() < 1e-15);
            assert!(
                (phi1 - reference(z, 1)).abs() < 1e-14,
                "phi1({z}) = {phi1} vs {}",
                reference(z, 1)
            );
            assert!(
                (phi2 - reference(z, 2)).abs() < 1e-14,
                "phi2({z}) = {phi2} vs {}",
                reference(z, 2)
            );
        }
        assert_eq!(phi(0.0), (1.0, 1.0, 0.5));
    }
}

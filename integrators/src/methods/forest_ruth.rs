//! Forest-Ruth: a fourth-order symplectic method, three position-Verlet
//! (drift-kick-drift) steps of sizes `theta h`, `(1 - 2 theta) h`, `theta h`
//! composed so that their third-order errors cancel (Yoshida's triple jump).
//!
//! ```text
//! theta = 1 / (2 - 2^(1/3))          (about 1.3512; the middle weight is negative)
//! x += theta h/2 v
//! v += theta h a(t1, x, v)
//! x += (1 - theta) h/2 v
//! v += (1 - 2 theta) h a(t2, x, v)
//! x += (1 - theta) h/2 v
//! v += theta h a(t3, x, v)
//! x += theta h/2 v
//! ```
//!
//! - Order 4 for positions and velocities on velocity-independent forces;
//!   order 1 with drag, because each kick evaluates the drag explicitly at the
//!   velocity before the kick, which breaks the symmetric composition.
//! - Cost: 3 force evaluations per step.
//! - Stability: symplectic and time-reversible: bounded energy error on
//!   conservative forces. The negative middle sub-step shrinks the stable range
//!   on the oscillator to about `h omega < 1.57`.

use crate::chunks::for_each_chunk;
use crate::integrator::{Integrator, MethodInfo, StepError, StepStats, check_step, fit};
use crate::system::System;
use crate::vector::{Real, Vector};

/// Registry entry.
pub const INFO: MethodInfo = MethodInfo {
    name: "forest_ruth",
    aliases: &["yoshida4", "fr4", "symplectic4"],
    title: "Forest-Ruth (4th-order symplectic)",
    notes: "fourth-order symplectic (Yoshida's triple jump)",
    order: 4,
    order_velocity: 4,
    order_velocity_forces: 1,
    evaluations: 3,
    symplectic: true,
    reversible: true,
    ..MethodInfo::EXPLICIT
};

/// The step's weights, as fractions of the step `h`: the four drifts
/// `(theta/2, (1 - theta)/2, (1 - theta)/2, theta/2)` and the three kicks
/// `(theta, 1 - 2 theta, theta)`, in `f64`. A step multiplies each by `h`
/// in `f64` and rounds once; the GPU step forms its coefficients from
/// these, so that both round the same products.
#[must_use]
pub fn weights() -> ([f64; 4], [f64; 3]) {
    let theta = 1.0 / (2.0 - crate::math::powf(2f64, 1.0 / 3.0));
    (
        [theta / 2.0, (1.0 - theta) / 2.0, (1.0 - theta) / 2.0, theta / 2.0],
        [theta, 1.0 - 2.0 * theta, theta],
    )
}

/// Forest-Ruth. See the [module documentation](self).
#[derive(Debug, Clone, Default)]
pub struct ForestRuth<V: Vector> {
    accel: Vec<V>,
}

impl<V: Vector> ForestRuth<V> {
    /// A new Forest-Ruth integrator.
    #[must_use]
    pub fn new() -> Self {
        Self { accel: Vec::new() }
    }
}

impl<V: Vector> Integrator<V> for ForestRuth<V> {
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
        let h = dt.to_f64();
        let (drifts, kicks) = weights();
        let accel = &mut self.accel;
        for_each_chunk(x, v, system, |x, v, system| {
            fit(accel, x.len());
            let mut elapsed = 0.0;
            for stage in 0..4 {
                let drift = V::Real::from_f64(drifts[stage] * h);
                for (x, v) in x.iter_mut().zip(v.iter()) {
                    *x += *v * drift;
                }
                elapsed += drifts[stage];
                if stage < 3 {
                    let kick = V::Real::from_f64(kicks[stage] * h);
                    system.acceleration(t + V::Real::from_f64(elapsed * h), x, v, accel);
                    for (v, a) in v.iter_mut().zip(accel.iter()) {
                        *v += *a * kick;
                    }
                }
            }
        });
        Ok(StepStats::single(3))
    }
}

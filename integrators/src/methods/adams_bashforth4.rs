//! Adams-Bashforth 4: the four-step linear multistep method.
//!
//! ```text
//! y(t + h) = y + h/24 (55 f(t) - 59 f(t - h) + 37 f(t - 2h) - 9 f(t - 3h)),    y = (x, v), f = (v, a)
//! ```
//!
//! - Order 4 for positions and velocities, also with drag.
//! - Cost: 1 force evaluation per step (a quarter of RK4's for the same
//!   order); started by three RK4 steps.
//! - Stability: the smallest region of the family: on the undamped oscillator
//!   stable for `h omega` below about 0.43; on linear drag for `h b` below
//!   about 0.3. Cheap and accurate for smooth motion at small steps, fragile
//!   at large ones.
//!
//! The implementation is shared with AB2 and AB3 in
//! [`AdamsBashforth`](crate::AdamsBashforth).

use crate::integrator::MethodInfo;

/// Registry entry.
pub const INFO: MethodInfo = MethodInfo {
    name: "adams_bashforth4",
    aliases: &["ab4"],
    title: "Adams-Bashforth 4",
    notes: "a quarter of RK4's cost at the same order, small stability region",
    order: 4,
    order_velocity: 4,
    order_velocity_forces: 4,
    evaluations: 1,
    ..MethodInfo::WITH_HISTORY
};

/// Adams-Bashforth 4. See the [module documentation](self).
pub type AdamsBashforth4<V> = super::adams_bashforth::AdamsBashforth<V, 4>;

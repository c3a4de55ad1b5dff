//! Adams-Bashforth 3: the three-step linear multistep method.
//!
//! ```text
//! y(t + h) = y + h/12 (23 f(t) - 16 f(t - h) + 5 f(t - 2h)),    y = (x, v), f = (v, a)
//! ```
//!
//! - Order 3 for positions and velocities, also with drag.
//! - Cost: 1 force evaluation per step; started by two RK4 steps.
//! - Stability: on the undamped oscillator stable for `h omega` below about
//!   0.72; on linear drag stable for `h b` below about 0.55.
//!
//! The implementation is shared with AB2 and AB4 in
//! [`AdamsBashforth`](crate::AdamsBashforth).

use crate::integrator::MethodInfo;

/// Registry entry.
pub const INFO: MethodInfo = MethodInfo {
    name: "adams_bashforth3",
    aliases: &["ab3"],
    title: "Adams-Bashforth 3",
    notes: "",
    order: 3,
    order_velocity: 3,
    order_velocity_forces: 3,
    evaluations: 1,
    ..MethodInfo::WITH_HISTORY
};

/// Adams-Bashforth 3. See the [module documentation](self).
pub type AdamsBashforth3<V> = super::adams_bashforth::AdamsBashforth<V, 3>;

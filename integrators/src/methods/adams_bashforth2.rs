//! Adams-Bashforth 2: the two-step linear multistep method.
//!
//! ```text
//! y(t + h) = y + h (3/2 f(t) - 1/2 f(t - h)),    y = (x, v), f = (v, a)
//! ```
//!
//! - Order 2 for positions and velocities, also with drag.
//! - Cost: 1 force evaluation per step; started by one RK4 step (4 evaluations).
//! - Stability: its stability region touches the imaginary axis only at 0, so
//!   on the undamped oscillator the amplitude grows slowly for every `h` (by a
//!   factor of about `1 + (h omega)^4 / 4` per step); on linear drag stable for
//!   `h b < 1`.
//!
//! The implementation is shared with AB3 and AB4 in
//! [`AdamsBashforth`](crate::AdamsBashforth).

use crate::integrator::MethodInfo;

/// Registry entry.
pub const INFO: MethodInfo = MethodInfo {
    name: "adams_bashforth2",
    aliases: &["ab2"],
    title: "Adams-Bashforth 2",
    notes: "linear multistep; RK4 start",
    order: 2,
    order_velocity: 2,
    order_velocity_forces: 2,
    evaluations: 1,
    ..MethodInfo::WITH_HISTORY
};

/// Adams-Bashforth 2. See the [module documentation](self).
pub type AdamsBashforth2<V> = super::adams_bashforth::AdamsBashforth<V, 2>;

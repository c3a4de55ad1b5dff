//! The system being integrated: one acceleration callback over all particles.

use crate::vector::{Real, Vector};

/// The right-hand side `a(t, x, v)` of `x'' = a(t, x, x')` for a whole slice of
/// particles at once.
///
/// Multi-stage methods call [`System::acceleration`] on whole trial states, so
/// coupled forces (springs, n-body) see every particle at the same stage.
/// Any closure `FnMut(t, positions, velocities, accelerations_out)` is a system.
pub trait System<V: Vector> {
    /// Fills `out[i]` with the acceleration of particle `i` at time `t` for the
    /// given positions and velocities. All three slices have the same length.
    fn acceleration(&mut self, t: V::Real, positions: &[V], velocities: &[V], out: &mut [V]);

    /// Jacobian-vector product `out = (da/dx) dx + (da/dv) dv` at `(t, x, v)`,
    /// for the implicit methods' Newton-Krylov solver.
    ///
    /// Return `false` (the default) to let the solver use a finite difference
    /// of [`System::acceleration`] instead; return `true` after filling `out`
    /// when the system knows its derivatives (cheaper and exact).
    #[allow(clippy::too_many_arguments)]
    fn jacobian_product(
        &mut self,
        _t: V::Real,
        _positions: &[V],
        _velocities: &[V],
        _dx: &[V],
        _dv: &[V],
        _out: &mut [V],
    ) -> bool {
        false
    }

    /// The linear drag coefficient `b` (per unit mass) contained in
    /// [`System::acceleration`], which then reads `a = g(t, x, v) - b v`.
    ///
    /// Exponential Euler integrates this part exactly; every other method
    /// ignores it. Default: `0`.
    fn linear_drag(&self) -> V::Real {
        V::Real::ZERO
    }

    /// `Some((c, b))` when the acceleration of each of the particles
    /// `first .. first + count` is exactly `a = c - b v` with the same
    /// constants (gravity, linear drag, wind): a method may then evaluate it
    /// inside its own update loop instead of filling a buffer first, with the
    /// same arithmetic (`c - v * b`), so the result is bit-identical to
    /// [`acceleration`](Self::acceleration)'s. Default: `None`.
    fn affine_range(&self, first: usize, count: usize) -> Option<(V, V::Real)> {
        let _ = (first, count);
        None
    }

    /// True when each particle's acceleration depends only on its own
    /// position and velocity (and `t`): gravity, drag, wind, fixed attractors;
    /// not springs between particles or n-body gravity. Default: `false`.
    ///
    /// Explicit self-starting methods then step the particles in cache-sized
    /// chunks (see [`System::acceleration_range`]), which keeps their scratch
    /// buffers in cache and brings large steps close to the memory-bandwidth
    /// limit. Results are bit-identical to the whole-slice step.
    fn is_pointwise(&self) -> bool {
        false
    }

    /// Accelerations of the particles `first .. first + positions.len()` only,
    /// for pointwise systems stepped in chunks. The slices are that range of the
    /// full columns; `first` lets a system index its own per-particle data
    /// (masses, charges). Default: [`System::acceleration`] on the range, right
    /// for systems with no per-particle data.
    fn acceleration_range(&mut self, t: V::Real, first: usize, positions: &[V], velocities: &[V], out: &mut [V]) {
        let _ = first;
        self.acceleration(t, positions, velocities, out);
    }
}

impl<V, F> System<V> for F
where
    V: Vector,
    F: FnMut(V::Real, &[V], &[V], &mut [V]),
{
    #[inline]
    fn acceleration(&mut self, t: V::Real, positions: &[V], velocities: &[V], out: &mut [V]) {
        self(t, positions, velocities, out)
    }
}

//! Where things are drawn between two fixed steps: one home for the
//! formulas the GPU and the CPU share.
//!
//! The renderer draws a frame `alpha` of a step past the last one
//! (`alpha` in `[0, 1)`, from the clock) by mixing the previous and the
//! current state with a parameter `t` ([`Interpolation::parameter`]):
//!
//! ```text
//! lerp      x(t) = x0 + t (x1 - x0)                       (common.wgsl `interpolated`)
//! hermite   x(t) = h00 x0 + h10 dt v0 + h01 x1 + h11 dt v1 (common.wgsl `hermite`)
//!           h00 = 2t^3 - 3t^2 + 1   h10 = t^3 - 2t^2 + t   h01 = -2t^3 + 3t^2   h11 = t^3 - t^2
//! slerp     q(t) = q0 (q0^-1 q1)^t                        (orientations; past t = 1 the same turn goes on)
//! ```
//!
//! `lerp` is exact for motion at constant velocity and off by
//! `a dt^2 t (1 - t) / 2` under an acceleration `a` (a ball's arc is drawn
//! as chords); `hermite`, from positions *and* velocities at both steps,
//! is exact for any motion up to cubic in time, so an arc stays an arc (as
//! avian offers and no other engine builds in).
//!
//! The world keeps each particle's previous and current position but only
//! its current velocity, so for particles the start velocity is derived
//! ([`start_velocity`]): `v0 = 2 (x1 - x0) / dt - v1`, the start velocity
//! of the constant-acceleration motion through both positions that ends at
//! `v1`. [`hermite_from_end`] is then the parabola
//! `x(t) = lerp(x0, x1, t) + t (1 - t) (x1 - x0 - dt v1)`, written through
//! [`hermite`] so that the shader evaluates the very same formula.
//!
//! The particles' shaders (quads and splat) use `lerp` by default, from a
//! 32-byte record with no velocities, and [`Interpolation::Hermite`] when
//! asked, from a second 12-byte velocity record; springs, trails and rigid
//! bodies are placed on the CPU by [`Interpolation::position`], the same
//! formulas, and a game's own positions (a paddle, a camera target) through
//! [`Interpolated`].

use glam::{Quat, Vec3};

/// Where particles are drawn between two fixed steps.
///
/// Chosen in the renderer's `RendererConfig::interpolation` or by
/// `Renderer::set_interpolation` (the `render` feature).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Interpolation {
    /// Between the previous and the current step, by the clock's alpha
    /// (default): [`lerp`], smooth, one step behind the simulation, and
    /// straight within a step (an arc is drawn as chords).
    #[default]
    Interpolate,
    /// Beyond the current step, as if the velocity stayed constant: no
    /// latency, but overshoots at bounces.
    Extrapolate,
    /// At the current step: shows the raw fixed-step motion (judder).
    None,
    /// Between the previous and the current step along a curve:
    /// [`hermite_from_end`] with steps of `dt` seconds (the clock's fixed
    /// step; must be finite and positive). Exact on a projectile's arc when
    /// the integrator's step is exact there (velocity Verlet, leapfrog,
    /// Heun, midpoint, RK4: see [`start_velocity`]); with semi-implicit
    /// Euler, the default, it draws what [`Interpolate`](Self::Interpolate)
    /// draws, since that method's step *is* a straight move at the end
    /// velocity. Costs 12 more bytes per particle uploaded (the velocities).
    Hermite {
        /// The fixed step in seconds, as the clock's `dt()`.
        dt: f32,
    },
}

impl Interpolation {
    /// The mixing parameter `t` for a frame's `alpha`: `alpha`
    /// (interpolate, Hermite), `1 + alpha` (one step further) or 1.
    #[must_use]
    pub fn parameter(self, alpha: f32) -> f32 {
        match self {
            Self::Interpolate | Self::Hermite { .. } => alpha,
            Self::Extrapolate => 1.0 + alpha,
            Self::None => 1.0,
        }
    }

    /// Where a particle that moved from `previous` to `current` in the last
    /// step, ending at `velocity`, is drawn at `t` (from
    /// [`parameter`](Self::parameter)): [`hermite_from_end`] in Hermite
    /// mode, [`lerp`] otherwise. The CPU twin of the particle shaders, for
    /// what the renderer places on the CPU (springs, trails, rigid bodies)
    /// and for tests.
    #[must_use]
    pub fn position(self, previous: Vec3, current: Vec3, velocity: Vec3, t: f32) -> Vec3 {
        match self {
            Self::Hermite { dt } => hermite_from_end(previous, current, velocity, dt, t),
            _ => lerp(previous, current, t),
        }
    }
}

/// `x0 + t (x1 - x0)`: the position `t` of the way from the previous step
/// to the current one.
#[must_use]
pub fn lerp(previous: Vec3, current: Vec3, t: f32) -> Vec3 {
    previous + t * (current - previous)
}

/// The cubic Hermite position `t` of the way through a step of `dt`
/// seconds that starts at `x0` moving at `v0` and ends at `x1` moving at
/// `v1` (exact for motion up to cubic in time):
/// `h00 x0 + h10 dt v0 + h01 x1 + h11 dt v1` with the basis of the
/// [module docs](self). The particle shaders' `hermite` (common.wgsl) is
/// its twin, term for term.
#[must_use]
pub fn hermite(x0: Vec3, v0: Vec3, x1: Vec3, v1: Vec3, dt: f32, t: f32) -> Vec3 {
    let (t2, t3) = (t * t, t * t * t);
    let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
    let h10 = t3 - 2.0 * t2 + t;
    let h01 = -2.0 * t3 + 3.0 * t2;
    let h11 = t3 - t2;
    h00 * x0 + (h10 * dt) * v0 + h01 * x1 + (h11 * dt) * v1
}

/// The velocity at the start of a step of `dt` seconds from `x0` to `x1`
/// that ended at `v1`, for Hermite when the start velocity was not kept:
/// `v0 = 2 (x1 - x0) / dt - v1`, the start of the constant-acceleration
/// motion (`x1 = x0 + dt (v0 + v1) / 2`) through both positions.
///
/// Exact when the step moved the particle along the constant-acceleration
/// arc: velocity Verlet, leapfrog, Heun, midpoint and RK4 do under gravity.
/// A semi-implicit Euler step moves in a straight line at its end velocity
/// (`x1 = x0 + dt v1`), so this gives `v0 = v1` and Hermite gives the chord
/// (as [`lerp`]); the acceleration of that step is not in the world's
/// columns, which keep no previous velocity. [`hermite_from_end`] uses it
/// only where both tangents point along the step.
#[inline]
#[must_use]
pub fn start_velocity(x0: Vec3, x1: Vec3, v1: Vec3, dt: f32) -> Vec3 {
    2.0 * (x1 - x0) / dt - v1
}

/// [`hermite`] through a step whose start velocity was not kept, from the
/// [`start_velocity`] it implies: the parabola through `x0` and `x1` that
/// ends at `v1`, `x(t) = lerp(x0, x1, t) + t (1 - t) (x1 - x0 - dt v1)`.
///
/// Only where both tangents point along the step `d = x1 - x0`
/// (`v1 . d > 0` and `v0 . d = 2 |d|^2 / dt - v1 . d > 0`): elsewhere a
/// contact or the game turned the velocity after the motion (a bounce, whose
/// parabola would dip through the floor), and the chord ([`lerp`]) is
/// drawn; so is a particle that did not move (`x0 == x1`: spawned,
/// teleported, at rest), which stays at `x1`. The particle shaders'
/// `hermite_from_end` (common.wgsl) is its twin.
#[must_use]
pub fn hermite_from_end(x0: Vec3, x1: Vec3, v1: Vec3, dt: f32, t: f32) -> Vec3 {
    let d = x1 - x0;
    let along = d.dot(v1);
    if !(along > 0.0 && along < 2.0 * d.length_squared() / dt) {
        return lerp(x0, x1, t);
    }
    hermite(x0, start_velocity(x0, x1, v1, dt), x1, v1, dt, t)
}

/// The orientation `t` of the way from `previous` to `current`: slerp for
/// `t` in `[0, 1]`, and past 1 the same rotation continued
/// (`q(t) = (q1 q0^-1)^(t - 1) q1`, for extrapolation).
#[must_use]
pub fn slerp(previous: Quat, current: Quat, t: f32) -> Quat {
    if t <= 1.0 {
        previous.slerp(current, t)
    } else {
        // The shorter way round, as slerp turns (q and -q are one rotation).
        let delta = current * previous.inverse();
        let delta = if delta.w < 0.0 { -delta } else { delta };
        let (axis, angle) = delta.to_axis_angle();
        (Quat::from_axis_angle(axis, angle * (t - 1.0)) * current).normalize()
    }
}

/// A game-owned position kept for drawing between steps: told the new
/// position and velocity once per fixed step, asked where it is at a
/// frame's `alpha`.
///
/// ```
/// use glam::Vec3;
/// use tickwork_engine::interpolation::Interpolated;
///
/// let mut paddle = Interpolated::at(Vec3::ZERO, Vec3::ZERO);
/// paddle.step_to(Vec3::new(0.5, 0.0, 0.0), Vec3::new(30.0, 0.0, 0.0)); // in fixed_update
/// assert_eq!(paddle.lerp(0.5), Vec3::new(0.25, 0.0, 0.0)); // in draw
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Interpolated {
    previous: (Vec3, Vec3),
    current: (Vec3, Vec3),
}

impl Interpolated {
    /// At `position`, moving at `velocity`, with no earlier step: drawn at
    /// `position` by [`lerp`](Self::lerp) whatever the alpha until the next
    /// step (Hermite, from one point with a velocity at both ends, moves a
    /// little about it).
    #[must_use]
    pub fn at(position: Vec3, velocity: Vec3) -> Self {
        Self {
            previous: (position, velocity),
            current: (position, velocity),
        }
    }

    /// The state after a fixed step; the last one becomes the previous.
    pub fn step_to(&mut self, position: Vec3, velocity: Vec3) {
        self.previous = self.current;
        self.current = (position, velocity);
    }

    /// A jump (a respawn): no streak across it.
    pub fn teleport(&mut self, position: Vec3, velocity: Vec3) {
        *self = Self::at(position, velocity);
    }

    /// The position after the last step.
    #[must_use]
    pub fn current(&self) -> Vec3 {
        self.current.0
    }

    /// Drawn by [`lerp`] at `t` (a frame's alpha).
    #[must_use]
    pub fn lerp(&self, t: f32) -> Vec3 {
        lerp(self.previous.0, self.current.0, t)
    }

    /// Drawn by [`hermite`] through a step of `dt` seconds, at `t` (the
    /// arguments in the free function's order).
    #[must_use]
    pub fn hermite(&self, dt: f32, t: f32) -> Vec3 {
        hermite(self.previous.0, self.previous.1, self.current.0, self.current.1, dt, t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A projectile: x(s) = x0 + v0 s + g s^2 / 2, v(s) = v0 + g s.
    fn projectile(s: f32) -> (Vec3, Vec3) {
        let (x0, v0, g) = (
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(3.0, 4.0, 0.0),
            Vec3::new(0.0, -9.81, 0.0),
        );
        (x0 + v0 * s + 0.5 * g * s * s, v0 + g * s)
    }

    #[test]
    fn hermite_draws_an_arc_exactly_and_lerp_cuts_its_chord_by_theory() {
        let dt = 0.1;
        let mut tracked = Interpolated::at(projectile(0.0).0, projectile(0.0).1);
        let (x1, v1) = projectile(dt);
        tracked.step_to(x1, v1);
        for t in [0.0f32, 0.25, 0.5, 0.9, 1.0] {
            let exact = projectile(t * dt).0;
            assert!(tracked.hermite(dt, t).abs_diff_eq(exact, 1e-6), "t = {t}");
            // The chord runs g dt^2 t (1 - t) / 2 below the arc.
            let sag = 9.81 * dt * dt * t * (1.0 - t) / 2.0;
            assert!((exact.y - tracked.lerp(t).y - sag).abs() < 1e-6, "t = {t}");
        }
        assert_eq!(tracked.current(), x1);
        tracked.teleport(Vec3::ZERO, Vec3::ONE);
        assert_eq!(tracked.lerp(0.3), Vec3::ZERO, "no streak across a jump");
    }

    #[test]
    fn hermite_from_the_end_velocity_draws_the_arc_of_an_exact_step_and_the_chord_of_a_semi_implicit_one() {
        let dt = 0.1;
        let ((x0, _), (x1, v1)) = (projectile(0.0), projectile(dt));
        let mode = Interpolation::Hermite { dt };
        for t in [0.0f32, 0.25, 0.5, 0.9, 1.0] {
            let exact = projectile(t * dt).0;
            assert!(hermite_from_end(x0, x1, v1, dt, t).abs_diff_eq(exact, 1e-6), "t = {t}");
            assert_eq!(mode.position(x0, x1, v1, t), hermite_from_end(x0, x1, v1, dt, t));
            // The parabola written as the chord plus its bow.
            let bow = lerp(x0, x1, t) + t * (1.0 - t) * (x1 - x0 - dt * v1);
            assert!(bow.abs_diff_eq(exact, 1e-6), "t = {t}");
            assert_eq!(Interpolation::Interpolate.position(x0, x1, v1, t), lerp(x0, x1, t));
        }
        // The derived start velocity is the arc's.
        assert!(start_velocity(x0, x1, v1, dt).abs_diff_eq(projectile(0.0).1, 1e-4));
        // Semi-implicit Euler moves in a straight line at its end velocity:
        // Hermite has nothing to bend it by and draws the chord.
        let (v0, g) = (Vec3::new(3.0, 4.0, 0.0), Vec3::new(0.0, -9.81, 0.0));
        let v1 = v0 + g * dt;
        let x1 = x0 + v1 * dt;
        for t in [0.25f32, 0.5, 0.75] {
            assert!(hermite_from_end(x0, x1, v1, dt, t).abs_diff_eq(lerp(x0, x1, t), 1e-6));
        }
        // A particle that did not move (spawned, teleported) stays put.
        let still = Vec3::new(1.0, 2.0, 3.0);
        assert!(hermite_from_end(still, still, v1, dt, 0.5).abs_diff_eq(still, 1e-6));
        assert_eq!(mode.parameter(0.25), 0.25);
    }

    #[test]
    fn slerp_turns_between_steps_and_keeps_turning_past_them() {
        let (q0, q1) = (Quat::IDENTITY, Quat::from_rotation_z(0.4));
        assert!(slerp(q0, q1, 0.5).abs_diff_eq(Quat::from_rotation_z(0.2), 1e-6));
        assert!(slerp(q0, q1, 1.5).abs_diff_eq(Quat::from_rotation_z(0.6), 1e-6));
        assert_eq!(Interpolation::Extrapolate.parameter(0.25), 1.25);
        assert_eq!(Interpolation::None.parameter(0.25), 1.0);
    }
}

//! The interface every method implements, and what a step reports.

use core::any::Any;
use core::fmt;

use crate::system::System;
use crate::vector::{Real, Vector};

/// What a method is: the static description the registry lists.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MethodInfo {
    /// Canonical name, snake_case (`"velocity_verlet"`).
    pub name: &'static str,
    /// Other accepted names (`"vv"`).
    pub aliases: &'static [&'static str],
    /// Human-readable title.
    pub title: &'static str,
    /// What to know when choosing it, in one line (empty when nothing beyond
    /// the other fields): the table `tickwork integrators` prints.
    pub notes: &'static str,
    /// Global order of accuracy of positions on smooth, velocity-independent forces.
    pub order: u32,
    /// Global order of the velocities the method reports.
    pub order_velocity: u32,
    /// Global order of the state (positions and velocities, Euclidean norm) when
    /// the forces depend on velocity (drag).
    pub order_velocity_forces: u32,
    /// Force evaluations per step in steady state (for implicit and adaptive
    /// methods: on a linear problem with a converged solve; see [`MethodInfo::variable_cost`]).
    pub evaluations: u32,
    /// Preserves the symplectic form (bounded energy error on Hamiltonian systems).
    pub symplectic: bool,
    /// Symmetric in time: stepping back with negated velocities retraces the path.
    pub reversible: bool,
    /// Needs no history from earlier steps (history methods bootstrap with RK4).
    pub self_starting: bool,
    /// Solves an implicit equation each step (Newton-Krylov).
    pub implicit: bool,
    /// The number of evaluations varies from step to step.
    pub variable_cost: bool,
    /// Stepping disjoint sub-slices of a pointwise system separately (in
    /// any order, on any thread, each with its own copy of the method)
    /// gives bit-identical results to one whole-slice step: true for the
    /// explicit self-starting methods, which keep no per-particle state
    /// between steps. The engine then fuses its per-particle work
    /// (colliders, the finiteness check) into cache-sized chunks and spreads
    /// chunks over threads.
    pub splits_pointwise: bool,
}

impl MethodInfo {
    /// What an explicit, self-starting method is unless its entry says
    /// otherwise (first order, one evaluation, not symplectic, keeps no
    /// history, splits pointwise): the base a method's [`INFO`] spreads from
    /// (`MethodInfo { name: "rk4", order: 4, ..MethodInfo::EXPLICIT }`), so
    /// each entry states only what sets it apart.
    ///
    /// [`INFO`]: crate::methods::rk4::INFO
    pub const EXPLICIT: Self = Self {
        name: "",
        aliases: &[],
        title: "",
        notes: "",
        order: 1,
        order_velocity: 1,
        order_velocity_forces: 1,
        evaluations: 1,
        symplectic: false,
        reversible: false,
        self_starting: true,
        implicit: false,
        variable_cost: false,
        splits_pointwise: true,
    };

    /// The base of a method that keeps a history between steps (Verlet's
    /// positions, Beeman's and Adams-Bashforth's past accelerations): not
    /// self-starting, so not split pointwise either.
    pub const WITH_HISTORY: Self = Self {
        self_starting: false,
        splits_pointwise: false,
        ..Self::EXPLICIT
    };

    /// The base of a method that solves an equation each step (Newton-Krylov,
    /// or adaptive step control): its evaluations vary, and it steps the
    /// whole slice.
    pub const SOLVED: Self = Self {
        variable_cost: true,
        splits_pointwise: false,
        ..Self::EXPLICIT
    };
}

/// Counters a step reports, for diagnostics and cost comparisons.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StepStats {
    /// Calls of [`System::acceleration`] (finite-difference Jacobian products included).
    pub evaluations: u32,
    /// Newton iterations (implicit methods).
    pub newton_iterations: u32,
    /// Krylov (GMRES) iterations, summed over the Newton iterations.
    pub krylov_iterations: u32,
    /// Accepted sub-steps (adaptive methods), 1 otherwise.
    pub substeps: u32,
    /// Rejected sub-steps (adaptive methods).
    pub rejected_substeps: u32,
    /// Particles that were (re)started by an RK4 bootstrap step (history methods).
    pub bootstrapped: u32,
}

impl StepStats {
    /// The report of a plain one-step method that called the system `evaluations` times.
    #[must_use]
    pub(crate) fn single(evaluations: u32) -> Self {
        Self {
            evaluations,
            substeps: 1,
            ..Self::default()
        }
    }
}

/// Why a step could not be taken. The state is left as it was before the step.
#[derive(Clone, Debug, PartialEq)]
pub enum StepError {
    /// `dt` was zero, NaN or infinite.
    InvalidTimeStep {
        /// The method that refused.
        method: &'static str,
        /// The offending value, as `f64`.
        dt: f64,
    },
    /// Positions and velocities had different lengths.
    LengthMismatch {
        /// The method that refused.
        method: &'static str,
        /// Number of positions.
        positions: usize,
        /// Number of velocities.
        velocities: usize,
    },
    /// An implicit solve did not reach its tolerance within its iteration cap.
    NotConverged {
        /// The method whose solve failed.
        method: &'static str,
        /// Newton iterations spent.
        iterations: u32,
        /// Final RMS residual, relative to the solution's scale.
        residual: f64,
        /// The tolerance that was asked for.
        tolerance: f64,
    },
    /// An adaptive method needed more sub-steps than its cap, or its sub-step
    /// shrank below the smallest allowed.
    SubstepLimit {
        /// The method that gave up.
        method: &'static str,
        /// Sub-steps taken before giving up.
        substeps: u32,
        /// The last sub-step size tried.
        last_substep: f64,
    },
}

impl fmt::Display for StepError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StepError::InvalidTimeStep { method, dt } => {
                write!(f, "{method}: time step must be finite and non-zero, got {dt}")
            }
            StepError::LengthMismatch {
                method,
                positions,
                velocities,
            } => write!(
                f,
                "{method}: {positions} positions but {velocities} velocities; the slices must have the same length"
            ),
            StepError::NotConverged {
                method,
                iterations,
                residual,
                tolerance,
            } => write!(
                f,
                "{method}: implicit solve did not converge after {iterations} Newton iterations \
                 (relative residual {residual:.3e}, tolerance {tolerance:.3e}); try a smaller time step \
                 or a larger iteration cap"
            ),
            StepError::SubstepLimit {
                method,
                substeps,
                last_substep,
            } => write!(
                f,
                "{method}: gave up after {substeps} sub-steps (last sub-step {last_substep:.3e}); \
                 the tolerance is too tight for this time step or the solution is not smooth"
            ),
        }
    }
}

impl std::error::Error for StepError {}

/// A time-integration method for `x'' = a(t, x, x')` over a slice of particles.
///
/// A method owns its scratch and history buffers. They grow when particles are
/// appended (new particles are detected by the slice length and, for history
/// methods, bootstrapped), follow [`Integrator::swap_remove`] when particles are
/// removed, and are reused otherwise, so steady-state steps allocate nothing.
/// Dynamic dispatch happens once per step (and once per force evaluation),
/// never per particle.
pub trait Integrator<V: Vector>: Send + IntegratorState<V> {
    /// The method's description (orders, cost, flags).
    fn info(&self) -> MethodInfo;

    /// [`MethodInfo::splits_pointwise`] of this method (a property of the
    /// registry entry, like every other).
    fn splits_pointwise(&self) -> bool {
        self.info().splits_pointwise
    }

    /// Shows everything the method remembers from one step to the next
    /// (history, cached accelerations, the adaptive step it proposed), in a
    /// fixed order, for checksums: each per-particle buffer to `vectors`,
    /// every other value as little-endian bytes to `bytes`. Scratch that the
    /// next step overwrites before reading is left out. Default: nothing,
    /// for the methods that keep no state between steps.
    fn visit_state(&self, vectors: &mut dyn FnMut(&[V]), bytes: &mut dyn FnMut(&[u8])) {
        let _ = (vectors, bytes);
    }

    /// Advances `positions` and `velocities` from time `t` to `t + dt`.
    ///
    /// # Errors
    /// [`StepError`] when `dt` is not finite and non-zero, the slices differ in
    /// length, or an implicit or adaptive solve fails; the state is then left
    /// unchanged.
    fn step(
        &mut self,
        t: V::Real,
        dt: V::Real,
        positions: &mut [V],
        velocities: &mut [V],
        system: &mut dyn System<V>,
    ) -> Result<StepStats, StepError>;

    /// [`step`](Self::step) with the start positions in a buffer of their own:
    /// reads `start`, writes the end positions into `positions` (whatever it
    /// held), updates `velocities` in place. Bit-identical to copying `start`
    /// into `positions` and calling `step`, which is the default.
    ///
    /// This is what lets the engine keep the previous positions (for
    /// interpolation) by swapping two buffers instead of copying one: the
    /// explicit methods override it to read the old buffer and write the new
    /// one in the same pass, so no copy is ever streamed.
    ///
    /// # Errors
    /// As [`step`](Self::step), and [`StepError::LengthMismatch`] when `start`
    /// and `positions` differ in length.
    fn step_from(
        &mut self,
        t: V::Real,
        dt: V::Real,
        start: &[V],
        positions: &mut [V],
        velocities: &mut [V],
        system: &mut dyn System<V>,
    ) -> Result<StepStats, StepError> {
        check_start(self.info().name, start, positions)?;
        positions.copy_from_slice(start);
        self.step(t, dt, positions, velocities, system)
    }

    /// Particle `index` was removed from `rows` particles with
    /// `Vec::swap_remove` semantics: the last (`rows - 1`) moved into its
    /// slot. History moves with it; a particle appended since the last step
    /// has none, so where one moved in, that slot starts afresh.
    fn swap_remove(&mut self, index: usize, rows: usize) {
        let _ = (index, rows);
    }

    /// Forgets all history and cached accelerations, for example after the
    /// forces changed discontinuously. The next step restarts every particle.
    fn reset(&mut self) {}
}

/// Checks the arguments every method receives.
pub(crate) fn check_step<V: Vector>(
    method: &'static str,
    dt: V::Real,
    positions: &[V],
    velocities: &[V],
) -> Result<(), StepError> {
    if !dt.is_finite() || dt == V::Real::ZERO {
        return Err(StepError::InvalidTimeStep {
            method,
            dt: dt.to_f64(),
        });
    }
    if positions.len() != velocities.len() {
        return Err(StepError::LengthMismatch {
            method,
            positions: positions.len(),
            velocities: velocities.len(),
        });
    }
    Ok(())
}

/// Checks that the start positions of [`Integrator::step_from`] fit the output.
pub(crate) fn check_start<V: Vector>(method: &'static str, start: &[V], positions: &[V]) -> Result<(), StepError> {
    if start.len() == positions.len() {
        Ok(())
    } else {
        Err(StepError::LengthMismatch {
            method,
            positions: start.len(),
            velocities: positions.len(),
        })
    }
}

/// Resizes a scratch buffer to `n` entries; allocates only when it grows.
#[inline]
pub(crate) fn fit<V: Vector>(buffer: &mut Vec<V>, n: usize) {
    if buffer.len() != n {
        buffer.resize(n, V::ZERO);
    }
}

/// Copying a method's whole state (history, cached accelerations, settings),
/// for snapshots and for per-thread copies.
///
/// Implemented for every `Integrator + Clone`; method authors never write it.
pub trait IntegratorState<V: Vector> {
    /// A boxed copy of the method and everything it remembers.
    fn clone_boxed(&self) -> Box<dyn Integrator<V>>;

    /// The method as `Any`, so a state can be copied into a method of the same type.
    fn as_any(&self) -> &dyn Any;

    /// Overwrites this method's state with `source`'s, reusing this method's
    /// buffers (no allocation once they are large enough). Returns false,
    /// leaving `self` unchanged, when `source` is a different method type.
    fn copy_state_from(&mut self, source: &dyn Integrator<V>) -> bool;
}

impl<V: Vector, T: Integrator<V> + Clone + 'static> IntegratorState<V> for T {
    fn clone_boxed(&self) -> Box<dyn Integrator<V>> {
        Box::new(self.clone())
    }

    fn as_any(&self) -> &dyn Any {
        self
    }

    fn copy_state_from(&mut self, source: &dyn Integrator<V>) -> bool {
        match source.as_any().downcast_ref::<T>() {
            Some(source) => {
                self.clone_from(source);
                true
            }
            None => false,
        }
    }
}

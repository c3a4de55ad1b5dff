//! Per-particle bookkeeping shared by the methods that remember earlier steps
//! (position Verlet, Beeman, Adams-Bashforth) or cache the last acceleration
//! (leapfrog, velocity Verlet).
//!
//! History belongs to a particle, not to a slot: it moves with
//! `swap_remove`, starts empty for an appended particle, and is discarded for a
//! particle whose position or velocity was changed outside the step (a bounce,
//! a teleport), detected by comparing with what the last step wrote. A change
//! of `dt` discards everyone's history, since the multistep coefficients
//! assume equal spacing. Particles with too little history are restarted by
//! an RK4 step, so a particle's trajectory does not depend on the particles
//! spawned or despawned around it.
//!
//! History is keyed on the sequence of steps and `h`, not on the time passed
//! in: each step continues the last one when `h` is the same and the state is
//! the one the last step wrote. The time only reaches the forces. A caller
//! that passes `t = 0` on every step (natural for time-independent forces)
//! therefore keeps the method it asked for at one evaluation per step, where
//! a time-keyed history silently restarted every particle with RK4 on every
//! step, at 4-5 times the cost. A caller that rewinds the state restores the
//! method's state too (snapshots copy it), or the state comparison restarts
//! the particles that changed.

use core::ops::Range;

use crate::integrator::fit;
use crate::vector::{Real, Vector};

/// Depth of history per particle, and the state each particle had when the
/// last step ended.
#[derive(Debug, Clone)]
pub(crate) struct History<V: Vector> {
    last_positions: Vec<V>,
    last_velocities: Vec<V>,
    /// Steps of history each particle has (saturating).
    depth: Vec<u8>,
    /// `dt` of the last step, to detect changes of spacing.
    last_dt: Option<V::Real>,
}

impl<V: Vector> Default for History<V> {
    fn default() -> Self {
        Self {
            last_positions: Vec::new(),
            last_velocities: Vec::new(),
            depth: Vec::new(),
            last_dt: None,
        }
    }
}

impl<V: Vector> History<V> {
    /// Shows the history's state (see [`Integrator::visit_state`](crate::Integrator::visit_state)).
    pub(crate) fn visit(&self, vectors: &mut dyn FnMut(&[V]), bytes: &mut dyn FnMut(&[u8])) {
        vectors(&self.last_positions);
        vectors(&self.last_velocities);
        bytes(&self.depth);
        bytes(&self.last_dt.map_or(f64::NAN, V::Real::to_f64).to_le_bytes());
    }

    /// Brings the history in line with the state about to be stepped and
    /// returns how many particles have less than `required` steps of history.
    pub(crate) fn sync(&mut self, dt: V::Real, x: &[V], v: &[V], required: u8) -> usize {
        let n = x.len();
        if self.depth.len() != n {
            // Appended particles start with no history; a shorter slice without
            // `swap_remove` drops the tail.
            self.depth.resize(n, 0);
            fit(&mut self.last_positions, n);
            fit(&mut self.last_velocities, n);
        }
        let continues = self.last_dt == Some(dt);
        if !continues {
            self.depth.fill(0);
        }
        let mut short = 0;
        for i in 0..n {
            if x[i] != self.last_positions[i] || v[i] != self.last_velocities[i] {
                self.depth[i] = 0;
            }
            short += usize::from(self.depth[i] < required);
        }
        short
    }

    /// The runs of consecutive particles with less than `required` steps of
    /// history, in order (found by a scan of the depths, so nothing is stored
    /// and nothing allocated however many runs there are).
    pub(crate) fn starting(&self, required: u8) -> impl Iterator<Item = Range<usize>> + '_ {
        let depth = &self.depth;
        let mut next = 0;
        core::iter::from_fn(move || {
            let first = next + depth[next..].iter().position(|&d| d < required)?;
            let end = depth[first..]
                .iter()
                .position(|&d| d >= required)
                .map_or(depth.len(), |k| first + k);
            next = end;
            Some(first..end)
        })
    }

    /// Whether particle `i` has at least `required` steps of history.
    #[inline]
    pub(crate) fn has(&self, i: usize, required: u8) -> bool {
        self.depth[i] >= required
    }

    /// Records what the step wrote for particle `i`, which gains one step of
    /// history. Called from the step's last per-particle loop, so the record
    /// costs no pass of its own.
    #[inline]
    pub(crate) fn note(&mut self, i: usize, x: V, v: V) {
        self.last_positions[i] = x;
        self.last_velocities[i] = v;
        self.depth[i] = self.depth[i].saturating_add(1);
    }

    /// Closes a step in which every particle was [noted](History::note).
    pub(crate) fn close(&mut self, dt: V::Real) {
        self.last_dt = Some(dt);
    }

    /// Notes every particle and closes the step, in a pass of its own: for
    /// methods whose last loop is too busy to take the notes (measured: Adams-
    /// Bashforth 4 ran 1.7x slower with the notes inside its lag loop).
    pub(crate) fn record(&mut self, dt: V::Real, x: &[V], v: &[V]) {
        self.last_positions.copy_from_slice(x);
        self.last_velocities.copy_from_slice(v);
        for depth in &mut self.depth {
            *depth = depth.saturating_add(1);
        }
        self.close(dt);
    }

    /// Follows `Vec::swap_remove(index)` on particle columns of `rows`
    /// rows, returning whether the history moved (then a method's own
    /// per-particle buffers follow with [`swap_remove_in`]). The history
    /// holds the particles of the last step; those appended since have
    /// none: where one of them moves into `index`, that slot starts afresh
    /// and nothing moves (the particle that was last at the step keeps its
    /// history where it is).
    pub(crate) fn swap_remove(&mut self, index: usize, rows: usize) -> bool {
        let held = self.depth.len();
        if index >= held {
            return false;
        }
        if rows > held {
            self.depth[index] = 0;
            return false;
        }
        self.depth.swap_remove(index);
        self.last_positions.swap_remove(index);
        self.last_velocities.swap_remove(index);
        true
    }

    /// Forgets everything.
    pub(crate) fn reset(&mut self) {
        self.depth.fill(0);
        self.last_dt = None;
    }
}

/// `swap_remove` on a per-particle buffer, if it holds that index.
#[inline]
pub(crate) fn swap_remove_in<V: Copy>(buffer: &mut Vec<V>, index: usize) {
    if index < buffer.len() {
        buffer.swap_remove(index);
    }
}

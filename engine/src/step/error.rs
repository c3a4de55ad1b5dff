//! Why a step failed: [`SimulationError`], naming the tick, the entity, the
//! field and the value (and, for a non-finite state, its likely cause).

use core::fmt;

use glam::Vec3;
use tickwork_integrators::StepError;

use crate::world::Entity;

/// A step that failed.
#[derive(Clone, Debug, PartialEq)]
pub enum SimulationError {
    /// The integrator refused or failed (bad `dt`, a solver that did not converge).
    Integrator {
        /// The tick of the step.
        tick: u64,
        /// What the method said.
        error: StepError,
    },
    /// An emitter's settings are invalid (changed through `emitters_mut`).
    Emitter {
        /// The tick of the step.
        tick: u64,
        /// The emitter's index.
        index: usize,
        /// The invalid setting.
        error: crate::world::SpawnError,
    },
    /// A position or velocity became NaN or infinite (an explosion: a step too
    /// large for the method's stability, or a force that divides by zero),
    /// or was already so, or a force gave a non-finite acceleration.
    NonFinite {
        /// The tick of the step.
        tick: u64,
        /// The first entity (in row order) with a non-finite value.
        entity: Entity,
        /// `"position"`, `"velocity"` or `"acceleration"`.
        field: &'static str,
        /// The value.
        value: Vec3,
        /// What is known of how it came about.
        cause: NonFiniteCause,
    },
    /// An emitter is due more particles in one step than
    /// [`WorldConfig::max_spawns_per_step`](crate::world::WorldConfig) allows.
    SpawnLimit {
        /// The tick of the step.
        tick: u64,
        /// The emitter's index.
        emitter: usize,
        /// Particles it was due.
        due: f64,
        /// The limit in force.
        limit: u32,
    },
    /// An emitter would take the world past
    /// [`WorldConfig::max_particles`](crate::world::WorldConfig).
    ParticleLimit {
        /// The tick of the step.
        tick: u64,
        /// The emitter's index.
        emitter: usize,
        /// The limit in force.
        limit: usize,
    },
    /// The forces would visit more pairs of particles in one evaluation
    /// than [`WorldConfig::max_pairs`](crate::world::WorldConfig) allows
    /// (n-body among too many particles); checked before the step changes
    /// anything.
    PairLimit {
        /// The tick of the step.
        tick: u64,
        /// The force's name (`"nbody"`).
        force: &'static str,
        /// The particles it would act among.
        particles: usize,
        /// The pairs one evaluation would visit.
        pairs: u64,
        /// The limit in force.
        limit: u64,
    },
    /// The sensors would test more sensor-particle pairs in one step than
    /// [`WorldConfig::max_pairs`](crate::world::WorldConfig) allows (each
    /// sensor tests every particle); checked before the step changes
    /// anything.
    SensorPairLimit {
        /// The tick of the step.
        tick: u64,
        /// The world's sensors.
        sensors: usize,
        /// The particles each tests.
        particles: usize,
        /// Sensors times particles.
        pairs: u64,
        /// The limit in force.
        limit: u64,
    },
    /// A collider of pairs (sphere collisions) would test more candidate
    /// pairs in one step than [`WorldConfig::max_pairs`](crate::world::WorldConfig)
    /// allows: spheres crowded into the same grid cells (overlapping each
    /// other, or piled together by another collider). Found after the
    /// integration, before those contacts are resolved: the world is left
    /// as the step made it (as for `NonFinite`); restore a snapshot to go on.
    ContactPairLimit {
        /// The tick of the step.
        tick: u64,
        /// The collider's name (`"spheres"`).
        collider: &'static str,
        /// Its index among the world's colliders.
        index: usize,
        /// The particles it would resolve among.
        particles: usize,
        /// The candidate pairs it would test, at least.
        pairs: u64,
        /// The limit in force.
        limit: u64,
    },
    /// A particle met more contacts in one step than
    /// [`MAX_CONTACT_EVENTS`](crate::colliders::MAX_CONTACT_EVENTS), with
    /// colliders that find contacts inside the step (squeezed between
    /// surfaces closing in, or between walls far closer than its travel in
    /// a step), in a world whose
    /// [`WorldConfig::contact_overflow`](crate::WorldConfig) is
    /// [`ContactOverflow::Error`](crate::ContactOverflow). The world is
    /// left as the step made it.
    ContactEventLimit {
        /// The tick of the step.
        tick: u64,
        /// The particle.
        entity: crate::layout::Entity,
        /// The collider of its last contact (`"plane"`, `"box"`).
        collider: &'static str,
        /// That collider's index among the world's colliders.
        index: usize,
        /// The limit.
        limit: u32,
    },
    /// A character's numbers are out of range (set through
    /// [`World::character_mut`](crate::World::character_mut)); checked
    /// before the step changes anything.
    Character {
        /// The tick of the step.
        tick: u64,
        /// The character.
        id: crate::character::CharacterId,
        /// What is wrong.
        error: crate::character::CharacterError,
    },
    /// The fixed step itself is invalid: a time or `dt` that is not finite
    /// (`dt` not above zero is the integrator's [`StepError::InvalidTimeStep`]).
    InvalidStep {
        /// The tick of the step.
        tick: u64,
        /// Its time, in seconds.
        time: f64,
        /// Its `dt`, in seconds.
        dt: f64,
    },
}

/// How a non-finite value came about, as far as the step can tell.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NonFiniteCause {
    /// The step made it: too large a step for the method's stability, or a
    /// force that diverged.
    Step,
    /// It was already non-finite when the step began: set outside the step
    /// (through `particles_mut`, a game's system).
    Start,
    /// The forces gave a non-finite acceleration at a finite state (what
    /// made an implicit or adaptive solve fail).
    Force,
}

impl fmt::Display for SimulationError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Integrator { tick, error } => write!(f, "step {tick}: {error}"),
            Self::Emitter { tick, index, error } => write!(f, "step {tick}: emitter {index}: {error}"),
            Self::NonFinite {
                tick,
                entity,
                field,
                value,
                cause,
            } => {
                write!(f, "step {tick}: entity {entity} has a non-finite {field} {value}; ")?;
                f.write_str(match cause {
                    NonFiniteCause::Step => "the step is too large for the integrator's stability, or a force diverged",
                    NonFiniteCause::Start => {
                        "it was so before the step began: it was set outside the step (particles_mut, a game system)"
                    }
                    NonFiniteCause::Force => "the forces gave it at a finite position and velocity",
                })
            }
            Self::SpawnLimit {
                tick,
                emitter,
                due,
                limit,
            } => write!(
                f,
                "step {tick}: emitter {emitter} is due {} particles in one step, past the limit of {limit} \
                 (WorldConfig::max_spawns_per_step); lower its rate or raise the limit",
                // `due` was an f32: its shortest form, not its widening's digits.
                crate::clock::Number::from(*due as f32)
            ),
            Self::ParticleLimit { tick, emitter, limit } => write!(
                f,
                "step {tick}: emitter {emitter} would take the world past its limit of {limit} particles \
                 (WorldConfig::max_particles); give its particles a shorter lifetime, lower its rate \
                 or raise the limit"
            ),
            Self::PairLimit {
                tick,
                force,
                particles,
                pairs,
                limit,
            } => write!(
                f,
                "step {tick}: force {force} would visit {pairs} pairs among {particles} particles in one evaluation, \
                 past the limit of {limit} (WorldConfig::max_pairs); use fewer particles or raise the limit"
            ),
            Self::SensorPairLimit {
                tick,
                sensors,
                particles,
                pairs,
                limit,
            } => write!(
                f,
                "step {tick}: {sensors} sensors would test {pairs} pairs with {particles} particles in one step, past \
                 the limit of {limit} (WorldConfig::max_pairs); use fewer sensors or raise the limit"
            ),
            Self::ContactPairLimit {
                tick,
                collider,
                index,
                particles,
                pairs,
                limit,
            } => write!(
                f,
                "step {tick}: collider {index} ({collider}) would test at least {pairs} candidate pairs among \
                 {particles} particles, past the limit of {limit} (WorldConfig::max_pairs): the spheres are \
                 crowded into the same grid cells (overlapping one another, or piled together by another \
                 collider); give them room, smaller radii, or raise the limit"
            ),
            Self::ContactEventLimit {
                tick,
                entity,
                collider,
                index,
                limit,
            } => write!(
                f,
                "step {tick}: entity {entity} met more than {limit} contacts in one step (the last with \
                 collider {index}, {collider}; MAX_CONTACT_EVENTS): it is squeezed between surfaces, or \
                 bounces between walls far closer than it travels in a step; give it room or take a \
                 smaller step"
            ),
            Self::Character { tick, id, error } => write!(f, "step {tick}: {id}: {error}"),
            Self::InvalidStep { tick, time, dt } => write!(
                f,
                "step {tick}: invalid fixed step: time {} s, dt {} s (both must be finite)",
                crate::clock::Number(*time),
                crate::clock::Number(*dt)
            ),
        }
    }
}

impl std::error::Error for SimulationError {}

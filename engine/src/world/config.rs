//! A world's settings ([`WorldConfig`]) and the errors of its calls ([`WorldError`]).

use core::fmt;

use super::{Entity, EntityError, SpawnError};

/// Settings of a new [`World`](super::World).
#[derive(Clone, Debug, PartialEq)]
pub struct WorldConfig {
    /// The integrator, by registry name or alias (default: `"semi_implicit_euler"`).
    pub integrator: String,
    /// The angular integrator for rigid bodies (default: `"angular_rk4"`, 4th
    /// order: rigid bodies are few, and the first-order methods drift in energy).
    pub angular_integrator: String,
    /// Seed of the world's random generator (emitters, games) (default: `0`).
    pub seed: u64,
    /// Particle count from which a step is spread over rayon's threads, when
    /// the forces and the method allow it (default: `4096`: measured on two
    /// cores, two lanes step 4 096 particles in 0.85 of one lane's time and
    /// 16k-64k in 0.6-0.7; below, waking a thread costs more than it saves).
    pub parallel_threshold: usize,
    /// Most particles one emitter may spawn in one step (default:
    /// `1_000_000`): an emitter of 1e12 per second is an error naming this
    /// limit, not an allocation that takes the machine.
    pub max_spawns_per_step: u32,
    /// Most particles the world may hold, live and queued (default:
    /// `10_000_000`, about a gigabyte of columns): a spawn past it is
    /// [`SpawnError::ParticleLimit`], an emitter's step past it
    /// [`SimulationError::ParticleLimit`](crate::step::SimulationError), not an
    /// allocation that aborts the process.
    pub max_particles: usize,
    /// Most pairs of particles one evaluation of the forces may visit
    /// (default: `50_000_000`, n-body among 10 000 particles, a few tenths
    /// of a second a step on one core): a step past it is
    /// [`SimulationError::PairLimit`](crate::step::SimulationError), naming
    /// the force, the pairs and this limit, not a step that runs for
    /// minutes (n-body among 100 000 particles is 5e9 pairs). Sphere
    /// collisions are held to it too: spheres sharing a grid cell are
    /// tested pair by pair, and past this many such pairs a step is
    /// [`SimulationError::ContactPairLimit`](crate::step::SimulationError)
    /// (grains of one size that do not overlap fit at most eight to a
    /// cell, so a pile makes at most 3.5 such pairs a grain: ten million
    /// grains stay below the default).
    pub max_pairs: u64,
    /// Below this approach speed, in m/s, a contact found inside the step
    /// ([`ContactRule::InStep`](crate::colliders::ContactRule)) does not
    /// bounce: the particle comes to rest on the surface (default `0.5`,
    /// about what gravity gives in two steps at 60 Hz, as Box2D's
    /// restitution threshold of 1 m/s). Without it a ball with restitution
    /// below 1 would bounce ever lower, infinitely often (Zeno); 0 (or
    /// NaN, or a negative speed) keeps every bounce, so a particle settling
    /// on a surface may meet `MAX_CONTACT_EVENTS` in a step.
    pub rest_speed: f32,
    /// What a step does with a particle that meets more than
    /// [`MAX_CONTACT_EVENTS`](crate::colliders::MAX_CONTACT_EVENTS)
    /// contacts found inside it (squeezed between a kinematic box and a
    /// wall, or bouncing between walls far closer than its travel a step):
    /// default [`ContactOverflow::EndOfStep`]. A world stepped on the GPU
    /// leaves such a particle to the end-of-step rule whatever this says,
    /// and names none (a GPU step reads nothing back unasked).
    pub contact_overflow: ContactOverflow,
    /// Where a runner steps the world's particles (default
    /// [`Backend::Cpu`]); `--gpu` on the command line sets
    /// [`Backend::Gpu`] for every world of a run.
    pub backend: Backend,
}

/// What a step does with a particle past
/// [`MAX_CONTACT_EVENTS`](crate::colliders::MAX_CONTACT_EVENTS) contacts
/// inside it ([`WorldConfig::contact_overflow`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum ContactOverflow {
    /// The particle stays where its last contact left it, and the
    /// end-of-step rule resolves it, as `ContactRule::EndOfStep` would; the
    /// step goes on and its [`StepReport::contact_overflow`](crate::StepReport)
    /// names the first such particle (default: a ball a game's paddle
    /// pins against a wall must not end the game).
    #[default]
    EndOfStep,
    /// The step fails with
    /// [`SimulationError::ContactEventLimit`](crate::SimulationError),
    /// naming the particle, the collider and the limit (the world is left
    /// as the step made it): for tools and tests that treat it as bad input.
    Error,
}

/// Where a runner steps a world's particles.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Backend {
    /// On the CPU, [`World::step`](super::World::step) (default).
    #[default]
    Cpu,
    /// On the GPU (`gpu_step::GpuWorld`, in builds with the
    /// `render` feature): the particles' state lives in GPU buffers,
    /// drawn from there; the [`World`](super::World) keeps the rest
    /// (entities, emitters, lifetimes, tick), its positions and velocities
    /// those of the last read-back. What the GPU step does not do is an
    /// error naming it when the run starts.
    Gpu,
}

impl Default for WorldConfig {
    fn default() -> Self {
        Self {
            integrator: "semi_implicit_euler".into(),
            angular_integrator: "angular_rk4".into(),
            seed: 0,
            parallel_threshold: 4_096,
            max_spawns_per_step: 1_000_000,
            max_particles: 10_000_000,
            max_pairs: 50_000_000,
            rest_speed: 0.5,
            contact_overflow: ContactOverflow::EndOfStep,
            backend: Backend::Cpu,
        }
    }
}

/// A request to change an entity that failed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum WorldError {
    /// The handle names no live entity.
    Entity(EntityError),
    /// A value is invalid (the field is named).
    Invalid {
        /// The entity.
        entity: Entity,
        /// What was wrong.
        error: SpawnError,
    },
    /// The component type was never registered.
    UnregisteredComponent {
        /// The type's name.
        type_name: &'static str,
    },
}

impl fmt::Display for WorldError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Entity(e) => e.fmt(f),
            Self::Invalid { entity, error } => write!(f, "entity {entity}: {error}"),
            Self::UnregisteredComponent { type_name } => {
                write!(
                    f,
                    "component {type_name} is not registered; call World::register::<{type_name}>() first"
                )
            }
        }
    }
}

impl std::error::Error for WorldError {}

impl From<EntityError> for WorldError {
    fn from(e: EntityError) -> Self {
        Self::Entity(e)
    }
}

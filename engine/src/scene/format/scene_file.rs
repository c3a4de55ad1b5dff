//! The root of a scene file: its name, integrator, rate, seed, duration
//! and camera, and the lists of forces, colliders, particles, lattices,
//! emitters and rigid bodies, each with its default.

use serde::{Deserialize, Serialize};

use super::camera::CameraHint;
use super::check_item::checked_list;
use super::collider::ColliderSpec;
use super::emitter::EmitterSpec;
use super::force::ForceSpec;
use super::lattice::LatticeSpec;
use super::method_name::MethodName;
use super::numbers::Positive;
use super::particle::ParticleSpec;
use super::rate::RateSpec;
use super::rigid_body::RigidBodySpec;

/// A scene file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// Name shown in titles and summaries (default: the file name).
    #[serde(default)]
    pub name: Option<String>,
    /// One line saying what the scene shows (default: empty).
    #[serde(default)]
    pub description: String,
    /// The integrator (default: `"semi_implicit_euler"`).
    #[serde(default = "default_integrator")]
    pub integrator: MethodName,
    /// The fixed step (default: `Hz(60)`).
    #[serde(default = "default_rate")]
    pub rate: RateSpec,
    /// Seed of the world's random generator (default: `0`).
    #[serde(default)]
    pub seed: u64,
    /// Where a runner steps the particles: `Cpu` or `Gpu` (default: `Cpu`;
    /// `--gpu` overrides it).
    #[serde(default)]
    pub backend: crate::world::Backend,
    /// Simulated seconds a headless run lasts unless told otherwise (default: `10.0`).
    #[serde(default = "default_duration")]
    pub duration: Positive,
    /// How a renderer should frame the scene (default: 2D, centred, 10 m tall).
    #[serde(default)]
    pub camera: CameraHint,
    /// Force generators (default: none).
    #[serde(default)]
    pub forces: Vec<ForceSpec>,
    /// Colliders (default: none).
    #[serde(default, deserialize_with = "checked_list")]
    pub colliders: Vec<ColliderSpec>,
    /// Particles, one by one; springs refer to them by index (default: none).
    #[serde(default)]
    pub particles: Vec<ParticleSpec>,
    /// Blocks of particles on a lattice (default: none).
    #[serde(default)]
    pub lattices: Vec<LatticeSpec>,
    /// Emitters (default: none).
    #[serde(default, deserialize_with = "checked_list")]
    pub emitters: Vec<EmitterSpec>,
    /// Rigid bodies (default: none).
    #[serde(default, deserialize_with = "checked_list")]
    pub rigid_bodies: Vec<RigidBodySpec>,
}

fn default_integrator() -> MethodName {
    MethodName("semi_implicit_euler".into())
}
fn default_rate() -> RateSpec {
    RateSpec::Hz(Positive(60.0))
}
fn default_duration() -> Positive {
    Positive(10.0)
}

//! One case: scene text parsed, built into a world (under a small particle
//! limit, so that a mutated count costs an error, not minutes) and stepped
//! a few times. A refusal is a fine outcome; a panic, or an error that does
//! not say where, is a defect.

use tickwork_engine::clock::FixedStep;
use tickwork_engine::{Scene, WorldConfig};

/// Steps run per case that builds: enough for the colliders, emitters and
/// multi-step methods (history starts) to act.
pub const STEPS: u64 = 4;

/// The particle limit of a case's world: mutated lattice counts and
/// emitter rates reach it quickly, and the N-body force is quadratic.
pub const MAX_PARTICLES: usize = 4096;

/// The particle limit of a full-scale case ([`run_full_scale_case`]): the
/// shipped 100 000-particle scenes fit, with room for mutations to grow
/// them; what is quadratic at that scale shows as a case over its time
/// budget ([`Campaign::case_budget`](crate::Campaign)).
pub const FULL_SCALE_PARTICLES: usize = 250_000;

/// Where a case stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// `Scene::parse` refused the text.
    Parse,
    /// The rate or `Scene::build_with` refused the scene.
    Build,
    /// A step returned an error.
    Step,
}

/// What a case did.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Refused at `Stage` with this message.
    Refused(Stage, String),
    /// Parsed, built and stepped [`STEPS`] times.
    Stepped,
}

/// Runs one case. `Err` is a defect: the description of a refusal that
/// does not say where (a parse error without a line and column, an empty
/// message). Panics propagate, for the caller's `catch_unwind`.
///
/// # Errors
/// The defect found.
pub fn run_case(text: &str) -> Result<Outcome, String> {
    run_case_with(text, MAX_PARTICLES)
}

/// [`run_case`] at full scale: the world may hold
/// [`FULL_SCALE_PARTICLES`], so the shipped 100 000-particle scenes run
/// as they ship (with their mutations), and only the engine's own limits
/// (`WorldConfig::max_pairs`, the sphere grid's levels) keep a case short.
///
/// # Errors
/// The defect found.
pub fn run_full_scale_case(text: &str) -> Result<Outcome, String> {
    run_case_with(text, FULL_SCALE_PARTICLES)
}

fn run_case_with(text: &str, max_particles: usize) -> Result<Outcome, String> {
    let scene = match Scene::parse(text, "fuzz.ron") {
        Ok(scene) => scene,
        Err(error) => {
            if error.position.is_none() {
                return Err(format!("a parse error without a line and column: {error}"));
            }
            return refused(Stage::Parse, error.to_string());
        }
    };
    let rate = match scene.rate() {
        Ok(rate) => rate,
        Err(error) => return refused(Stage::Build, error.to_string()),
    };
    let config = WorldConfig {
        max_particles,
        ..scene.world_config()
    };
    let mut world = match scene.build_with(config) {
        Ok((world, _)) => world,
        Err(error) => return refused(Stage::Build, error.to_string()),
    };
    let dt = rate.step_seconds();
    for tick in 0..STEPS {
        let step = FixedStep {
            tick,
            time: tick as f64 * dt,
            dt,
        };
        if let Err(error) = world.step(step) {
            return refused(Stage::Step, error.to_string());
        }
    }
    // The state's hash reads every column: a panic there is found too.
    let _ = world.state_hash();
    Ok(Outcome::Stepped)
}

fn refused(stage: Stage, message: String) -> Result<Outcome, String> {
    if message.trim().is_empty() {
        return Err(format!("an empty {stage:?} error"));
    }
    Ok(Outcome::Refused(stage, message))
}

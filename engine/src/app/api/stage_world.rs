//! A world on the stage ([`StageWorld`]) and what the runner keeps for it:
//! its trails, its energy trace, what a failed step does, and where its
//! steps run.

use crate::SimulationError;
use crate::app::api::backend::{self, StepFailure, Stepper};
use crate::clock::FixedStep;
use crate::gpu_step::GpuStepError;
use crate::render::{Gpu, Texture, Trails};
use crate::world::{Colour, World};

/// A world on the stage, with what the runner keeps for it.
#[derive(Debug)]
pub struct StageWorld {
    /// Shown in the legend, the panel and error messages.
    pub label: String,
    /// The world. One whose [`WorldConfig::backend`](crate::WorldConfig::backend) is the GPU keeps
    /// its particles' positions and velocities there once it has stepped:
    /// here they are those of the last read-back
    /// (`Stage::read_back`); its entities, lifetimes, emitters, forces
    /// and colliders are current.
    pub world: World,
    /// Its trails (none followed by default).
    pub trails: Trails,
    /// Its colour in the panel's energy plot and legends.
    pub colour: Colour,
    /// Whether the integrator belongs to the game (an integrator race), so
    /// `--integrator`, Tab, 1-9 and the panel leave it alone (default false).
    pub fixed_integrator: bool,
    /// Relative energy error since set-up, sampled by the runner.
    pub energy: EnergyTrace,
    /// What a failed step does (default [`OnFailure::Stop`]).
    pub on_failure: OnFailure,
    /// Why the world stopped, under [`OnFailure::Freeze`] (`None` while it runs).
    pub failure: Option<String>,
    /// The state before the current step, kept under [`OnFailure::Freeze`].
    pub(crate) last_good: Option<crate::world::Snapshot>,
    /// Its particles drawn as this image, each as wide as its disc, tinted
    /// by its colour and turned by its heading (default `None`: discs).
    pub sprite: Option<Texture>,
    /// The layer its particles, trails and outlines are drawn on: after
    /// the shapes of that layer (default `None`: the frame's
    /// [`Draw::particle_layer`](crate::app::Draw::particle_layer)).
    pub layer: Option<i32>,
    /// Where its steps run, and its GPU copy once it has one.
    pub(crate) stepper: Stepper,
}

/// What happens when a world's step fails (an explicit method blowing up
/// on stiff springs, an implicit solve that does not converge).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum OnFailure {
    /// The run stops with the error (default): a game's world must not fail.
    #[default]
    Stop,
    /// The world goes back to its state before the failed step and stops
    /// there, with [`StageWorld::failure`] saying why; the others go on
    /// (an integrator race, a stability demonstration). Switching its
    /// integrator resumes it. Costs a snapshot per step.
    Freeze,
}

/// The relative energy error `(E - E0) / |E0|` of a world over recent
/// steps, for plots and legends.
#[derive(Clone, Debug, Default)]
pub struct EnergyTrace {
    initial: Option<f64>,
    /// `(time, relative error)` samples, oldest first, at most [`EnergyTrace::CAPACITY`].
    samples: std::collections::VecDeque<(f64, f64)>,
}

impl EnergyTrace {
    /// Samples kept.
    pub const CAPACITY: usize = 600;

    /// Records the world's energy now (the first call sets `E0`).
    ///
    /// # Errors
    /// The world's refusal to sum a potential past its pair limit
    /// ([`World::energy`]); nothing is recorded.
    pub fn sample(&mut self, world: &mut World) -> Result<(), SimulationError> {
        let energy = world.energy()?.total();
        let initial = *self.initial.get_or_insert(energy);
        let error = if initial.abs() > 1e-12 {
            (energy - initial) / initial.abs()
        } else {
            energy - initial
        };
        if self.samples.len() == Self::CAPACITY {
            self.samples.pop_front();
        }
        self.samples.push_back((world.time(), error));
        Ok(())
    }

    /// The latest relative error (0 before any sample).
    #[must_use]
    pub fn latest(&self) -> f64 {
        self.samples.back().map_or(0.0, |s| s.1)
    }

    /// The samples, oldest first.
    pub fn samples(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.samples.iter().copied()
    }
}

/// Worlds up to this many particles sample their energy every step (for
/// the panel's plot and the HUD); larger ones every 30 steps, since an
/// energy sum costs about as much as a step.
pub(crate) const ENERGY_EVERY_STEP_UP_TO: usize = 4_000;

impl StageWorld {
    /// Runs one fixed step of this world (on the GPU where its
    /// configuration says, on `gpu`), then records its trails and samples
    /// its energy (a world on the CPU). A world that fails stops the run,
    /// or, if it freezes on failure, goes back to its last finite state
    /// and stays there (its `failure` says why) while the others run on.
    pub(crate) fn step(&mut self, gpu: &mut Option<Gpu>, step: FixedStep) -> Result<(), StepFailure> {
        if self.failure.is_some() {
            return Ok(());
        }
        let on_gpu = backend::on_gpu(&self.world);
        if on_gpu && self.sprite.is_some() {
            return Err(StepFailure::Gpu(GpuStepError::Unsupported(
                "sprites for a world's particles (they are drawn from the CPU's columns)",
            )));
        }
        if self.on_failure == OnFailure::Freeze {
            if on_gpu {
                return Err(StepFailure::Gpu(GpuStepError::Unsupported(
                    "OnFailure::Freeze (a snapshot of the state every step): a world on the GPU stops the run",
                )));
            }
            match &mut self.last_good {
                Some(snapshot) => self.world.snapshot_into(snapshot),
                None => self.last_good = Some(self.world.snapshot()),
            }
        }
        if let Err(failure) = self.stepper.step(gpu, &mut self.world, step) {
            return match (failure, self.on_failure, &self.last_good) {
                (StepFailure::Simulation(error), OnFailure::Freeze, Some(snapshot)) => {
                    self.world.restore(snapshot);
                    self.failure = Some(format!("failed at t = {:.2} s: {error}", step.time));
                    Ok(())
                }
                (failure, ..) => Err(failure),
            };
        }
        if on_gpu {
            return Ok(());
        }
        self.trails.record(&self.world);
        if self.world.len() <= ENERGY_EVERY_STEP_UP_TO || step.tick.is_multiple_of(30) {
            self.energy.sample(&mut self.world).map_err(StepFailure::Simulation)?;
        }
        Ok(())
    }

    /// Whether its particles are stepped on the GPU now (a world whose
    /// backend is the GPU, from its first step there): then
    /// `Stage::world`'s positions are those of the last read-back
    /// (`Stage::read_back`).
    #[must_use]
    pub fn on_gpu(&self) -> bool {
        self.stepper.on_gpu().is_some()
    }

    /// Its particles stepped on the GPU, drawn from the GPU's buffers
    /// (`None` for a world on the CPU, or before its first step).
    pub(crate) fn gpu_particles(&self) -> Option<crate::render::GpuParticles<'_>> {
        self.stepper.particles()
    }

    /// Reads a world on the GPU back (its positions and velocities), so
    /// that [`world`](Self::world) is current: costs a copy of its state
    /// and a wait for the GPU.
    pub(crate) fn sync(&mut self, gpu: Option<&Gpu>) -> Result<(), GpuStepError> {
        self.stepper.sync(gpu, &mut self.world)
    }
}

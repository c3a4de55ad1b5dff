//! Where a runner steps a world: on the CPU ([`World::step`]), or on the
//! GPU ([`GpuWorld::advance`]) where the world's
//! [`WorldConfig::backend`](crate::WorldConfig) is [`Backend::Gpu`]. The
//! one place the two differ for the runners: a [`GameSession`](crate::app::GameSession)'s
//! worlds and a [`Playback`](crate::app::Playback) both step through a
//! [`Stepper`], and draw a GPU world from its own buffers.
//!
//! A GPU world is made from the world at its first step (after the game's
//! first `fixed_update`, so what set-up and that update did is uploaded),
//! on the runner's GPU (the one it draws with), or on a GPU of its own
//! for a run that draws nothing. Its positions and velocities stay on the
//! GPU: [`Stepper::sync`] reads them back into the world (a checksum, a
//! snapshot), and costs a wait.

use crate::clock::FixedStep;
use crate::gpu_step::{GpuStepError, GpuWorld};
use crate::render::{Gpu, GpuParticles};
use crate::step::SimulationError;
use crate::world::{Backend, World};

/// Why a step through a [`Stepper`] failed.
#[derive(Debug)]
pub(crate) enum StepFailure {
    /// The world's own step (either backend).
    Simulation(SimulationError),
    /// The GPU step: what it does not do, no adapter, a lost device.
    Gpu(GpuStepError),
}

impl From<GpuStepError> for StepFailure {
    fn from(error: GpuStepError) -> Self {
        match error {
            GpuStepError::Simulation(error) => Self::Simulation(error),
            error => Self::Gpu(error),
        }
    }
}

/// Whether a runner steps `world` on the GPU: the one place the runners
/// read [`WorldConfig::backend`](crate::WorldConfig) (the panel, the
/// HUD, a rollback's refusal and a read-back all ask here, so that the
/// choice has one owner).
pub(crate) fn on_gpu(world: &World) -> bool {
    world.config().backend == Backend::Gpu
}

/// A world's GPU copy, once it steps on the GPU.
#[derive(Debug, Default)]
pub(crate) struct Stepper {
    on_gpu: Option<GpuWorld>,
}

impl Stepper {
    /// One fixed step of `world` where its configuration says, on `gpu`
    /// (a headless one is made into it if the runner gave none). A world
    /// moved back to the CPU after steps on the GPU takes its state back
    /// first (and its method starts its history afresh).
    pub fn step(&mut self, gpu: &mut Option<Gpu>, world: &mut World, step: FixedStep) -> Result<(), StepFailure> {
        if !on_gpu(world) {
            if self.on_gpu.is_some() {
                self.sync(gpu.as_ref(), world)?;
                self.on_gpu = None;
            }
            world.step(step).map_err(StepFailure::Simulation)?;
            return Ok(());
        }
        let gpu = match gpu {
            Some(gpu) => &*gpu,
            None => &*gpu.insert(Gpu::headless().map_err(|e| GpuStepError::NoAdapter(e.to_string()))?),
        };
        let on_gpu = match &mut self.on_gpu {
            Some(on_gpu) => on_gpu,
            None => self.on_gpu.insert(GpuWorld::new(gpu, world)?),
        };
        on_gpu.advance(gpu, world, step)?;
        Ok(())
    }

    /// The GPU world, once the world has stepped on the GPU.
    pub fn on_gpu(&self) -> Option<&GpuWorld> {
        self.on_gpu.as_ref()
    }

    /// Its particles as the renderer draws them, if it steps on the GPU.
    pub fn particles(&self) -> Option<GpuParticles<'_>> {
        self.on_gpu.as_ref().map(GpuWorld::particles)
    }

    /// Reads a GPU world's state back into `world` (nothing for a world on
    /// the CPU): its checksum and snapshots are then its own.
    pub fn sync(&mut self, gpu: Option<&Gpu>, world: &mut World) -> Result<(), GpuStepError> {
        let (Some(on_gpu), Some(gpu)) = (&mut self.on_gpu, gpu) else {
            return Ok(());
        };
        // Every step was an `advance`: the world has booked them, and the
        // step is not read.
        let booked = FixedStep {
            tick: world.tick().saturating_sub(1),
            time: world.time(),
            dt: 0.0,
        };
        on_gpu.store_into(gpu, world, booked)
    }

    /// Forgets the GPU copy (the world was restored or rebuilt): the next
    /// step makes it again from the world.
    pub fn forget(&mut self) {
        self.on_gpu = None;
    }
}

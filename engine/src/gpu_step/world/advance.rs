//! Advancing a [`World`] by its GPU copy: the fixed step with the world's
//! own row changes followed, the contacts read back, history restarted.

use glam::Vec3A;

use super::GpuWorld;
use super::buffers::{TOUCH_BYTES, touches_buffer};
use super::read_back::{f32_at, map_words};
use crate::clock::FixedStep;
use crate::colliders::RowTouch;
use crate::device::Gpu;
use crate::gpu_step::dispatch::dispatch;
use crate::gpu_step::error::GpuStepError;
use crate::gpu_step::kernel::refresh;
use crate::step::StepReport;
use crate::world::{RowChange, World};

impl GpuWorld {
    /// One fixed step of `world`, the world this was made from: its
    /// particles stepped on the GPU, and the rest of its step on the CPU
    /// ([`World::step`]'s lifetimes, expiry, emitters, queued spawns and
    /// despawns, tick and time), the GPU's rows then following the
    /// world's (removed rows filled from the end as the CPU's
    /// swap-removes fill them, new particles uploaded: their records
    /// only). The forces' and colliders' values are re-read at each step,
    /// so a game may change them between steps (a wind, an emitter, a
    /// method); spawns and despawns between steps are followed too.
    /// Nothing is read back: the world's positions and velocities are
    /// those of the last [`store_into`](Self::store_into).
    ///
    /// # Errors
    /// [`GpuStepError::Simulation`] for what the world's step refuses (an
    /// emitter past its limits, ...), [`GpuStepError::Edited`] if the
    /// world's particles were changed between steps other than by spawns
    /// and despawns, what of the world the GPU step does not do (a force
    /// added since, ...), and [`GpuStepError::Unsupported`] for another
    /// world or a step from another tick.
    pub fn advance(&mut self, gpu: &Gpu, world: &mut World, step: FixedStep) -> Result<StepReport, GpuStepError> {
        let dt = step.dt as f32;
        if !(dt.is_finite() && dt > 0.0) {
            return Err(GpuStepError::Step(dt));
        }
        if self.behind > 0 || world.tick() != self.next_tick || step.tick != world.tick() {
            return Err(GpuStepError::Unsupported(
                "advancing a world other than the one it was made from, or from another tick than the world's \
                 (store steps taken with GpuWorld::step into it first)",
            ));
        }
        // The changes to the rows since the last step (a game's spawns
        // and despawns), followed before this step.
        let mut log = if self.following {
            let log = world.take_row_log();
            let logged = self.revision + log.len() as u64;
            if world.revision() != logged || world.edited_outside_steps() {
                world.give_row_log(log);
                return Err(GpuStepError::Edited);
            }
            log
        } else {
            if world.revision() != self.revision || world.len() != self.len() {
                return Err(GpuStepError::Edited);
            }
            self.following = true;
            Vec::new()
        };
        let outcome = self.advance_logged(gpu, world, step, &mut log);
        log.clear();
        world.give_row_log(log);
        self.revision = world.revision();
        outcome
    }

    /// [`advance`](Self::advance) once the world's log is taken: `log`
    /// holds the changes since the last step, and is used again for the
    /// step's own.
    pub(super) fn advance_logged(
        &mut self,
        gpu: &Gpu,
        world: &mut World,
        step: FixedStep,
        log: &mut Vec<RowChange>,
    ) -> Result<StepReport, GpuStepError> {
        if !log.is_empty() {
            let mut encoder = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("tickwork gpu rows"),
            });
            self.follow_rows(gpu, &mut encoder, log, world)?;
            gpu.queue.submit([encoder.finish()]);
            log.clear();
        }
        // The step's checks, then its first change, as on the CPU: the
        // kinematic colliders move, and their records follow.
        world.check_step(step).map_err(GpuStepError::Simulation)?;
        world.advance_colliders(step.dt as f32);
        refresh(world, &mut self.scratch)?;
        self.adopt_plan(gpu)?;
        // The particles' step.
        let dt = step.dt as f32;
        gpu.queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&self.params(dt)));
        self.start_history(gpu, dt);
        if self.plan.reporting > 0 {
            gpu.queue.write_buffer(&self.flags, 8, bytemuck::bytes_of(&0u32));
        }
        let mut encoder = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("tickwork gpu step"),
        });
        if self.n > 0 {
            self.keep_previous(&mut encoder);
            self.encode_steps(&mut encoder, step.tick, 1);
        }
        gpu.queue.submit([encoder.finish()]);
        self.took(dt, 1);
        // Its contacts, named while the rows are still the step's.
        world.clear_contacts();
        let mut past_room = None;
        if self.plan.reporting > 0 && self.n > 0 {
            past_room = self.read_touches(gpu, world)?;
        }
        // The rest of the world's step, logging the rows it changes, which
        // the GPU's rows then follow.
        world.give_row_log(core::mem::take(log));
        let report = world.step_bookkeeping(step);
        *log = world.take_row_log();
        let report = report.map_err(GpuStepError::Simulation)?;
        if !log.is_empty() {
            let mut encoder = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("tickwork gpu rows"),
            });
            self.follow_rows(gpu, &mut encoder, log, world)?;
            gpu.queue.submit([encoder.finish()]);
        }
        if let Some((found, room)) = past_room {
            // The step is whole; the next ones have room for twice this
            // many, as far as one binding holds.
            let most = gpu.device.limits().max_storage_buffer_binding_size / TOUCH_BYTES;
            self.touches = touches_buffer(&gpu.device, (2 * u64::from(found)).min(most));
            self.rebind(&gpu.device);
            return Err(GpuStepError::Contacts { found, room });
        }
        Ok(report)
    }

    /// Room for contacts in the touches buffer ([`Plan::touch_records`] a
    /// particle).
    pub(super) fn touch_room(&self) -> u32 {
        u32::try_from(self.touches.size() / TOUCH_BYTES).unwrap_or(u32::MAX)
    }

    /// Reads the step's contacts back (a wait for the GPU) into the world's
    /// touches, and names them as the CPU's step does (sorted by collider
    /// and row, whatever order the GPU found them in). A step that found
    /// more than the room for them keeps those that fit and returns how
    /// many it found and the room.
    pub(super) fn read_touches(&self, gpu: &Gpu, world: &mut World) -> Result<Option<(u32, u32)>, GpuStepError> {
        let [count] = map_words(gpu, [(&self.flags, 8, 4)])?;
        let found = f32_at(&count, 0).to_bits();
        let room = self.touch_room();
        let count = found.min(room);
        let records = if count > 0 {
            let [records] = map_words(gpu, [(&self.touches, 0, u64::from(count) * TOUCH_BYTES)])?;
            records
        } else {
            Vec::new()
        };
        world.set_touches(records.chunks_exact(TOUCH_BYTES as usize).map(|t| {
            let f = |k: usize| f32_at(t, k);
            RowTouch {
                collider: f(0).to_bits(),
                row: f(1).to_bits(),
                other: u32::MAX,
                point: Vec3A::new(f(4), f(5), f(6)),
                normal: Vec3A::new(f(8), f(9), f(10)),
                impulse: f(11),
                event: f(2).to_bits(),
                fraction: f(3),
            }
        }));
        Ok((found > room).then_some((found, room)))
    }

    /// Before steps of `dt`: tells a method with history, through its
    /// flags, whether every particle starts afresh (the first step, a new
    /// step length, a new method) or rows changed, as the CPU's history
    /// decides it.
    pub(super) fn start_history(&mut self, gpu: &Gpu, dt: f32) {
        if self.last_dt.is_none_or(|last| last.to_bits() != dt.to_bits()) {
            self.restart |= 1;
            self.last_dt = Some(dt);
        }
        // (Bit 1 may already be set by the last step: kept, or implied by
        // bit 0.)
        if self.plan.history > 0 && self.restart != 0 {
            gpu.queue
                .write_buffer(&self.flags, 0, bytemuck::cast_slice(&[self.restart, 0]));
        }
        self.restart = 0;
    }

    /// Records into `encoder` what `log` did to the rows, leaving the
    /// GPU's rows the world's (growing the buffers first if it has more).
    pub(super) fn follow_rows(
        &mut self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        log: &[RowChange],
        world: &World,
    ) -> Result<(), GpuStepError> {
        if log.is_empty() {
            return Ok(());
        }
        // Rows added or removed: the next step is told.
        self.restart |= 2;
        let (n, groups) = dispatch(world.len(), self.plan.records(), &gpu.device.limits())?;
        self.reserve(gpu, encoder, n)?;
        self.row_plan.plan(log, self.n, world);
        self.max_radius = self.row_plan.max_radius().max(self.max_radius);
        self.rows
            .encode(gpu, encoder, &self.row_plan, &self.state.buffers(), self.plan.history)?;
        (self.n, self.groups) = (n, groups);
        Ok(())
    }
}

//! A GPU world's buffers and pipelines: the state's columns, the step's
//! pipelines built from its plan's shader, the bind group, and the buffers
//! that grow with the world.

use wgpu::util::DeviceExt;

use super::GpuWorld;
use crate::device::{Gpu, bind_buffers, compute_pipeline};
use crate::gpu_step::dispatch::dispatch;
use crate::gpu_step::error::GpuStepError;
use crate::gpu_step::kernel::{ColliderRecord, Plan};
use crate::gpu_step::rows::StateBuffers;

/// A particle's columns on the GPU.
#[derive(Debug)]
pub(super) struct State {
    /// `(x, y, z, radius)` a particle.
    pub(super) positions: wgpu::Buffer,
    /// `(vx, vy, vz, inverse mass)` a particle.
    pub(super) velocities: wgpu::Buffer,
    /// The positions at the start of the last step (a copy before its
    /// dispatch): the world's previous positions, for interpolation.
    pub(super) previous: wgpu::Buffer,
    /// Each particle's colour, for drawing.
    pub(super) colours: wgpu::Buffer,
    /// Each particle's history, for methods that keep one (`history` in
    /// `step.wgsl`; one record otherwise).
    pub(super) history: wgpu::Buffer,
}

impl State {
    /// Empty buffers for `capacity` particles (with `history` records
    /// each of a method's history).
    pub(super) fn new(device: &wgpu::Device, capacity: u32, history: u32) -> Self {
        let vec4s = |label| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: u64::from(capacity.max(1)) * 16,
                usage: STATE_USAGE,
                mapped_at_creation: false,
            })
        };
        Self {
            positions: vec4s("tickwork gpu step positions"),
            velocities: vec4s("tickwork gpu step velocities"),
            previous: vec4s("tickwork gpu step previous positions"),
            colours: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("tickwork gpu step colours"),
                size: u64::from(capacity.max(1)) * 4,
                usage: STATE_USAGE,
                mapped_at_creation: false,
            }),
            history: history_buffer(device, history, capacity),
        }
    }

    pub(super) fn buffers(&self) -> StateBuffers<'_> {
        StateBuffers {
            positions: &self.positions,
            velocities: &self.velocities,
            previous: &self.previous,
            colours: &self.colours,
            history: &self.history,
        }
    }
}

/// `records` vec4s a particle for a method with history; one otherwise.
pub(super) fn history_buffer(device: &wgpu::Device, records: u32, capacity: u32) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("tickwork gpu step history"),
        size: 16 * u64::from(records.max(1)) * if records > 0 { u64::from(capacity.max(1)) } else { 1 },
        usage: STATE_USAGE,
        mapped_at_creation: false,
    })
}

/// The state buffers: stepped, drawn, copied in and out.
pub(super) const STATE_USAGE: wgpu::BufferUsages = wgpu::BufferUsages::STORAGE
    .union(wgpu::BufferUsages::VERTEX)
    .union(wgpu::BufferUsages::COPY_SRC)
    .union(wgpu::BufferUsages::COPY_DST);

/// The step's compute pipelines, built from a plan's shader.
#[derive(Debug)]
pub(super) struct Pipelines {
    pub(super) step: wgpu::ComputePipeline,
    /// With n-body, each evaluation's round: its probe (the trial
    /// positions) and its sums (`STAGE` set to the evaluation).
    pub(super) rounds: Vec<(wgpu::ComputePipeline, wgpu::ComputePipeline)>,
    /// Subnormal velocities to 0, after the ticks the CPU's step flushes.
    pub(super) flush: wgpu::ComputePipeline,
    /// After each step of a method with history or with n-body: its news
    /// to the next.
    pub(super) rotate: Option<wgpu::ComputePipeline>,
}

impl Pipelines {
    pub(super) fn new(device: &wgpu::Device, layout: &wgpu::PipelineLayout, plan: &Plan) -> Self {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(plan.method),
            source: wgpu::ShaderSource::Wgsl(plan.source.as_str().into()),
        });
        let pipeline_of = |entry_point| compute_pipeline(device, layout, &module, entry_point, &[]);
        let round = |stage: u32| {
            let constants = [("STAGE", f64::from(stage))];
            let of = |entry_point| compute_pipeline(device, layout, &module, entry_point, &constants);
            (of("probe"), of("nbody_sums"))
        };
        Self {
            step: pipeline_of("step"),
            rounds: (0..plan.stages).map(round).collect(),
            flush: pipeline_of("flush"),
            rotate: (plan.history > 0 || plan.stages > 0).then(|| pipeline_of("rotate")),
        }
    }
}

impl GpuWorld {
    /// Grows the state buffers to hold `rows` (at least twice what they
    /// held), copying what they hold in `encoder`.
    pub(super) fn reserve(
        &mut self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        rows: u32,
    ) -> Result<(), GpuStepError> {
        if rows <= self.capacity {
            return Ok(());
        }
        let limits = gpu.device.limits();
        let doubled = self.capacity.saturating_mul(2).max(rows);
        let capacity = if dispatch(doubled as usize, self.plan.records(), &limits).is_ok() {
            doubled
        } else {
            dispatch(rows as usize, self.plan.records(), &limits)?;
            rows
        };
        let device = &gpu.device;
        let state = State::new(device, capacity, self.plan.history);
        for (from, to) in [
            (&self.state.positions, &state.positions),
            (&self.state.velocities, &state.velocities),
            (&self.state.previous, &state.previous),
            (&self.state.colours, &state.colours),
            (&self.state.history, &state.history),
        ] {
            encoder.copy_buffer_to_buffer(from, 0, to, 0, from.size());
        }
        self.state = state;
        self.capacity = capacity;
        if self.plan.stages > 0 {
            self.nbody = nbody_buffer(device, self.plan.stages, capacity);
        }
        if self.plan.reporting > 0 {
            self.touches = touches_buffer(device, self.plan.touch_room(u64::from(capacity)));
        }
        self.rebind(device);
        Ok(())
    }

    /// Makes the step's bind group again (a buffer was replaced).
    pub(super) fn rebind(&mut self, device: &wgpu::Device) {
        self.bind_group = step_bind_group(
            device,
            &self.layout,
            &self.params,
            &self.state,
            [&self.colliders, &self.nbody, &self.flags, &self.touches],
        );
        self.rows.unbind();
    }

    /// Takes the plan just re-read from the world: a new shader where its
    /// method or forces changed, new collider records where they did.
    pub(super) fn adopt_plan(&mut self, gpu: &Gpu) -> Result<(), GpuStepError> {
        let device = &gpu.device;
        // A method with more history, or n-body rounds, may not fit.
        dispatch(self.capacity as usize, self.scratch.records(), &device.limits())?;
        let mut rebind = false;
        let records = u64::from(self.scratch.stages + 1);
        if self.scratch.stages > 0 && self.nbody.size() < records * u64::from(self.capacity) * 16 {
            self.nbody = nbody_buffer(device, self.scratch.stages, self.capacity);
            rebind = true;
        }
        let room = self.scratch.touch_room(u64::from(self.capacity));
        if self.touches.size() < TOUCH_BYTES * room {
            self.touches = touches_buffer(device, room);
            rebind = true;
        }
        let records = u64::from(self.scratch.history);
        if self.state.history.size() < records * u64::from(self.capacity) * 16 {
            self.state.history = history_buffer(device, self.scratch.history, self.capacity);
            rebind = true;
        }
        if self.scratch.method != self.plan.method {
            // A new method starts without history, as `set_integrator`'s.
            self.restart |= 1;
        }
        if self.scratch.source != self.plan.source {
            self.pipelines = Pipelines::new(device, &self.pipeline_layout, &self.scratch);
        }
        if self.scratch.colliders != self.plan.colliders {
            let bytes = (self.scratch.colliders.len() * std::mem::size_of::<ColliderRecord>()) as u64;
            if bytes > self.colliders.size() {
                self.colliders = colliders_buffer(device, &self.scratch.colliders);
                rebind = true;
            } else if bytes > 0 {
                gpu.queue
                    .write_buffer(&self.colliders, 0, bytemuck::cast_slice(&self.scratch.colliders));
            }
        }
        core::mem::swap(&mut self.plan, &mut self.scratch);
        if rebind {
            self.rebind(device);
        }
        Ok(())
    }

    /// Copies the positions into the previous positions (the start of the
    /// step to come, for interpolation).
    pub(super) fn keep_previous(&self, encoder: &mut wgpu::CommandEncoder) {
        let bytes = u64::from(self.n) * 16;
        encoder.copy_buffer_to_buffer(&self.state.positions, 0, &self.state.previous, 0, bytes);
    }
}

/// The colliders' records (one zeroed record for none: a binding is never
/// empty, and `colliders: 0` reads none).
pub(super) fn colliders_buffer(device: &wgpu::Device, colliders: &[ColliderRecord]) -> wgpu::Buffer {
    let zero = [bytemuck::Zeroable::zeroed()];
    let records: &[ColliderRecord] = if colliders.is_empty() { &zero } else { colliders };
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("tickwork gpu step colliders"),
        contents: bytemuck::cast_slice(records),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
    })
}

/// Room for `room` contacts (48 bytes each; one for none).
pub(super) fn touches_buffer(device: &wgpu::Device, room: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("tickwork gpu step touches"),
        size: TOUCH_BYTES * room.max(1),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}

/// A contact's record (`Touch` in `step.wgsl`).
pub(super) const TOUCH_BYTES: u64 = 48;

/// Where the world has an n-body force, `stages + 1` vec4s a particle
/// (each evaluation's sums, and the trial positions being summed); one
/// vec4 otherwise (a binding is never empty).
pub(super) fn nbody_buffer(device: &wgpu::Device, stages: u32, capacity: u32) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("tickwork gpu step n-body"),
        size: if stages > 0 {
            16 * u64::from(stages + 1) * u64::from(capacity.max(1))
        } else {
            16
        },
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    })
}

/// The step's bind group over these buffers (`[colliders, n-body, flags,
/// touches]` with the state's).
pub(super) fn step_bind_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    params: &wgpu::Buffer,
    state: &State,
    [colliders, nbody, flags, touches]: [&wgpu::Buffer; 4],
) -> wgpu::BindGroup {
    let buffers = [
        params,
        &state.positions,
        &state.velocities,
        colliders,
        nbody,
        &state.history,
        flags,
        touches,
    ];
    bind_buffers(device, layout, &buffers)
}

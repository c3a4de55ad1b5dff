//! A particle world on the GPU: its state in two storage buffers, stepped
//! by one dispatch a fixed step.

use glam::{Vec3, Vec3A};
use wgpu::util::DeviceExt;

use super::dispatch::dispatch;
use super::error::GpuStepError;
use super::kernel::{ColliderRecord, Plan, changes_rows, coefficients, plan, refresh};
use super::rows::{RowKernel, RowPlan, StateBuffers};
use crate::clock::FixedStep;
use crate::colliders::RowTouch;
use crate::render::{Gpu, bind_buffers, buffer_entry, compute_pipeline, compute_storage};
use crate::step::StepReport;
use crate::world::{RowChange, World};

/// Storage buffers the row kernels and the step bind (`rows.wgsl`,
/// `step.wgsl`).
const STORAGE_BUFFERS: u32 = 7;

/// The shader's `Params` (see `step.wgsl`): WGSL's uniform layout puts
/// `drift` at byte 32 (a `vec4` aligns to 16), right after `colliders`.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct Params {
    c: [f32; 3],
    b: f32,
    dt: f32,
    n: u32,
    groups_x: u32,
    colliders: u32,
    drift: [f32; 4],
    kick: [f32; 4],
    nbody_g: f32,
    nbody_eps2: f32,
    /// `+inf`: WGSL has no infinite constant.
    infinity: f32,
    /// Room in the touches buffer (and the size a 16-byte multiple).
    touch_room: u32,
}

const _: () = assert!(std::mem::size_of::<Params>() == 80 && std::mem::offset_of!(Params, drift) == 32);

/// A world's particles stepped on the GPU (see the [module](super)): made
/// from a [`World`] (its state uploaded once), stepped with
/// [`advance`](Self::advance) (a fixed step of the world, its rows
/// following the world's) or [`step`](Self::step) (steps in a batch), read
/// back only when asked.
#[derive(Debug)]
pub struct GpuWorld {
    plan: Plan,
    /// The plan re-read from the world at each [`advance`](Self::advance).
    scratch: Plan,
    n: u32,
    /// Rows the state buffers hold (they grow as the world does).
    capacity: u32,
    groups: (u32, u32),
    state: State,
    colliders: wgpu::Buffer,
    params: wgpu::Buffer,
    /// Where the world has an n-body force, each evaluation's sums and the
    /// trial positions being summed (`nbody` in `step.wgsl`).
    nbody: wgpu::Buffer,
    /// What a step of a method with history reads of the last, and the
    /// count of the step's contacts (`flags` in `step.wgsl`).
    flags: wgpu::Buffer,
    /// The step's contacts of colliders that report them (`touches`).
    touches: wgpu::Buffer,
    /// What the next step of a method with history is told (`flags[0]` in
    /// `step.wgsl`), as the CPU's `History` decides it: bit 0, every
    /// particle starts afresh (the first step, a new step length, a new
    /// method); bit 1, rows were added or removed (which restarts velocity
    /// Verlet's and leapfrog's cached accelerations; position Verlet's new
    /// rows start alone).
    restart: u32,
    /// The last step's length.
    last_dt: Option<f32>,
    layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    pipelines: Pipelines,
    bind_group: wgpu::BindGroup,
    rows: RowKernel,
    row_plan: RowPlan,
    /// The world's tick at the next step (the flush's schedule follows it).
    next_tick: u64,
    ticks: u64,
    /// Steps [`step`](Self::step) took that no world has booked yet.
    behind: u64,
    /// The length of every step taken, while they were all the same
    /// (`Err` once two differed): what `store_into` ages the world by.
    dt: Result<Option<f32>, ()>,
    /// Whether the world's steps change its rows (emitters, lifetimes,
    /// queued commands): then only `advance` steps it.
    changes_rows: bool,
    /// The world's revision this follows (when made, after each advance
    /// and store), and whether the world logs its row changes for it.
    revision: u64,
    following: bool,
    /// At least the largest radius of its particles (for the renderer).
    max_radius: f32,
}

/// A particle's columns on the GPU.
#[derive(Debug)]
struct State {
    /// `(x, y, z, radius)` a particle.
    positions: wgpu::Buffer,
    /// `(vx, vy, vz, inverse mass)` a particle.
    velocities: wgpu::Buffer,
    /// The positions at the start of the last step (a copy before its
    /// dispatch): the world's previous positions, for interpolation.
    previous: wgpu::Buffer,
    /// Each particle's colour, for drawing.
    colours: wgpu::Buffer,
    /// Each particle's history, for methods that keep one (`history` in
    /// `step.wgsl`; one record otherwise).
    history: wgpu::Buffer,
}

impl State {
    /// Empty buffers for `capacity` particles (with `history` records
    /// each of a method's history).
    fn new(device: &wgpu::Device, capacity: u32, history: u32) -> Self {
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

    fn buffers(&self) -> StateBuffers<'_> {
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
fn history_buffer(device: &wgpu::Device, records: u32, capacity: u32) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("tickwork gpu step history"),
        size: 16 * u64::from(records.max(1)) * if records > 0 { u64::from(capacity.max(1)) } else { 1 },
        usage: STATE_USAGE,
        mapped_at_creation: false,
    })
}

/// The state buffers: stepped, drawn, copied in and out.
const STATE_USAGE: wgpu::BufferUsages = wgpu::BufferUsages::STORAGE
    .union(wgpu::BufferUsages::VERTEX)
    .union(wgpu::BufferUsages::COPY_SRC)
    .union(wgpu::BufferUsages::COPY_DST);

/// The step's compute pipelines, built from a plan's shader.
#[derive(Debug)]
struct Pipelines {
    step: wgpu::ComputePipeline,
    /// With n-body, each evaluation's round: its probe (the trial
    /// positions) and its sums (`STAGE` set to the evaluation).
    rounds: Vec<(wgpu::ComputePipeline, wgpu::ComputePipeline)>,
    /// Subnormal velocities to 0, after the ticks the CPU's step flushes.
    flush: wgpu::ComputePipeline,
    /// After each step of a method with history or with n-body: its news
    /// to the next.
    rotate: Option<wgpu::ComputePipeline>,
}

impl Pipelines {
    fn new(device: &wgpu::Device, layout: &wgpu::PipelineLayout, plan: &Plan) -> Self {
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
    /// Uploads `world`'s particles to `gpu` and builds its step. A method
    /// with history (velocity Verlet's and leapfrog's last acceleration,
    /// position Verlet's last position) starts it afresh here, as a new
    /// integrator would: a world that has stepped on the CPU goes on as
    /// after [`World::set_integrator`].
    ///
    /// # Errors
    /// [`GpuStepError`]: what of the world the GPU step does not do (its
    /// method, a force, a collider, ...), an adapter without compute
    /// shaders, or buffers past the device's limits (naming the limit and
    /// how many particles fit).
    pub fn new(gpu: &Gpu, world: &World) -> Result<Self, GpuStepError> {
        if !gpu
            .adapter
            .get_downlevel_capabilities()
            .flags
            .contains(wgpu::DownlevelFlags::COMPUTE_SHADERS)
        {
            return Err(GpuStepError::NoCompute);
        }
        if gpu.device.limits().max_storage_buffers_per_shader_stage < STORAGE_BUFFERS {
            return Err(GpuStepError::Unsupported(
                "an adapter with fewer than 7 storage buffers a compute shader \
                 (wgpu::Limits::max_storage_buffers_per_shader_stage)",
            ));
        }
        let plan = plan(world)?;
        let p = world.particles();
        let count = p.len();
        let (n, groups) = dispatch(count, plan.records(), &gpu.device.limits())?;
        let device = &gpu.device;
        let state = State::new(device, n, plan.history);
        let mut positions = Vec::with_capacity(count);
        let mut previous = Vec::with_capacity(count);
        let mut velocities = Vec::with_capacity(count);
        for (k, ((x, x0), v)) in p
            .position
            .iter()
            .zip(p.previous_position.iter())
            .zip(p.velocity.iter())
            .enumerate()
        {
            positions.push([x.x, x.y, x.z, p.radius[k]]);
            previous.push([x0.x, x0.y, x0.z, p.radius[k]]);
            velocities.push([v.x, v.y, v.z, p.inverse_mass[k]]);
        }
        // Colours for drawing: sRGB RGBA as little-endian words, hidden
        // particles transparent (as the renderer's own records).
        let hidden = world.hidden_rows();
        let colours: Vec<u32> = (0..count)
            .map(|k| {
                let shown = hidden.is_none_or(|h| !h[k].0);
                if shown { u32::from_le_bytes(p.colour[k]) } else { 0 }
            })
            .collect();
        if count > 0 {
            gpu.queue
                .write_buffer(&state.positions, 0, bytemuck::cast_slice(&positions));
            gpu.queue
                .write_buffer(&state.previous, 0, bytemuck::cast_slice(&previous));
            gpu.queue
                .write_buffer(&state.velocities, 0, bytemuck::cast_slice(&velocities));
            gpu.queue
                .write_buffer(&state.colours, 0, bytemuck::cast_slice(&colours));
        }
        let colliders = colliders_buffer(device, &plan.colliders);
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("tickwork gpu step params"),
            size: std::mem::size_of::<Params>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let nbody = nbody_buffer(device, plan.stages, n);
        let flags = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("tickwork gpu step flags"),
            size: 16,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let touches = touches_buffer(device, plan.touch_room(u64::from(n)));
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("tickwork gpu step"),
            entries: &[
                buffer_entry(0, wgpu::ShaderStages::COMPUTE, wgpu::BufferBindingType::Uniform),
                compute_storage(1, false),
                compute_storage(2, false),
                compute_storage(3, true),
                compute_storage(4, false),
                compute_storage(5, false),
                compute_storage(6, false),
                compute_storage(7, false),
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("tickwork gpu step"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipelines = Pipelines::new(device, &pipeline_layout, &plan);
        let bind_group = step_bind_group(device, &layout, &params, &state, [&colliders, &nbody, &flags, &touches]);
        Ok(Self {
            scratch: plan.clone(),
            plan,
            n,
            capacity: n.max(1),
            groups,
            state,
            colliders,
            params,
            nbody,
            flags,
            touches,
            restart: 1,
            last_dt: None,
            layout,
            pipeline_layout,
            pipelines,
            bind_group,
            rows: RowKernel::new(device),
            row_plan: RowPlan::default(),
            next_tick: world.tick(),
            ticks: 0,
            behind: 0,
            dt: Ok(None),
            changes_rows: changes_rows(world),
            revision: world.revision(),
            following: false,
            max_radius: p.radius.iter().fold(0.0, |m: f32, &r| m.max(r)),
        })
    }

    /// The number of particles.
    #[must_use]
    pub fn len(&self) -> usize {
        self.n as usize
    }

    /// Whether it has no particles.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// The method it steps with.
    #[must_use]
    pub fn method(&self) -> &'static str {
        self.plan.method
    }

    /// Whether [`step`](Self::step) takes this world: its rows stay as
    /// they are (no emitters, lifetimes or queued commands), its colliders
    /// where they are (none kinematic) and none reports contacts;
    /// otherwise it steps by [`advance`](Self::advance).
    #[must_use]
    pub fn steps_in_batches(&self) -> bool {
        !self.changes_rows && !self.plan.moving && self.plan.reporting == 0
    }

    /// The fixed steps taken.
    #[must_use]
    pub fn ticks(&self) -> u64 {
        self.ticks
    }

    /// The bytes a step reads and writes: 32 read and 32 written a
    /// particle (the bandwidth figure a benchmark divides by).
    #[must_use]
    pub fn bytes_per_step(&self) -> u64 {
        u64::from(self.n) * 64
    }

    /// Its particles as the renderer draws them, straight from these
    /// buffers (a [`FrameView`](crate::render::FrameView)'s
    /// `gpu_particles`): interpolated between the positions before and
    /// after the last step, nothing uploaded or read back.
    #[must_use]
    pub fn particles(&self) -> crate::render::GpuParticles<'_> {
        crate::render::GpuParticles {
            previous: &self.state.previous,
            current: &self.state.positions,
            velocities: &self.state.velocities,
            colours: &self.state.colours,
            count: self.n,
            max_radius: self.max_radius,
            layer: None,
        }
    }

    /// The state's two buffers, `(x, y, z, radius)` and `(vx, vy, vz,
    /// inverse mass)` a particle (row order; they may hold more rows than
    /// [`len`](Self::len)), for a renderer or a benchmark's copy.
    #[must_use]
    pub fn buffers(&self) -> (&wgpu::Buffer, &wgpu::Buffer) {
        (&self.state.positions, &self.state.velocities)
    }

    /// The shader's parameters for steps of `dt`.
    fn params(&self, dt: f32) -> Params {
        let (c, b) = self.plan.affine;
        let (drift, kick) = coefficients(self.plan.method, dt);
        let (nbody_g, nbody_eps2) = self.plan.nbody.unwrap_or_default();
        Params {
            c: c.to_array(),
            b,
            dt,
            n: self.n,
            groups_x: self.groups.0,
            colliders: u32::try_from(self.plan.colliders.len()).unwrap_or(u32::MAX),
            drift,
            kick,
            nbody_g,
            nbody_eps2,
            infinity: f32::INFINITY,
            touch_room: self.touch_room(),
        }
    }

    /// Notes a step of `dt` taken (for `store_into`'s ageing).
    fn took(&mut self, dt: f32, steps: u32) {
        if steps > 0 {
            self.dt = match self.dt {
                Ok(None) => Ok(Some(dt)),
                Ok(Some(same)) if same.to_bits() == dt.to_bits() => Ok(Some(dt)),
                _ => Err(()),
            };
        }
        self.next_tick += u64::from(steps);
        self.ticks += u64::from(steps);
    }

    /// Records `steps` fixed steps of `dt` seconds into one command
    /// buffer, one dispatch each in one compute pass (WebGPU orders their
    /// storage writes), and submits it. Nothing is read back, and the
    /// world is not told: [`store_into`](Self::store_into) books the steps
    /// into it. For a world whose rows stay as they are; one with
    /// emitters, lifetimes or queued commands steps with
    /// [`advance`](Self::advance).
    ///
    /// # Errors
    /// [`GpuStepError::Step`] for a `dt` that is not finite and positive;
    /// [`GpuStepError::Unsupported`] for a world whose rows change.
    pub fn step(&mut self, gpu: &Gpu, dt: f32, steps: u32) -> Result<(), GpuStepError> {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(GpuStepError::Step(dt));
        }
        if self.changes_rows {
            return Err(GpuStepError::Unsupported(
                "steps in a batch of a world whose rows change (emitters, lifetimes, queued spawns or \
                 despawns): step it with GpuWorld::advance, which follows them",
            ));
        }
        if self.plan.moving {
            return Err(GpuStepError::Unsupported(
                "steps in a batch of a world with a moving collider: step it with GpuWorld::advance, which \
                 moves it step by step",
            ));
        }
        if self.plan.reporting > 0 {
            return Err(GpuStepError::Unsupported(
                "steps in a batch of a world whose colliders report contacts: step it with GpuWorld::advance, \
                 which reads them back step by step",
            ));
        }
        gpu.queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&self.params(dt)));
        if steps > 0 {
            self.start_history(gpu, dt);
        }
        let mut encoder = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("tickwork gpu step"),
        });
        if self.n > 0 && steps > 0 {
            // All steps but the last, then the positions kept as the
            // previous ones, then the last.
            self.encode_steps(&mut encoder, self.next_tick, steps - 1);
            self.keep_previous(&mut encoder);
            self.encode_steps(&mut encoder, self.next_tick + u64::from(steps - 1), 1);
        }
        gpu.queue.submit([encoder.finish()]);
        self.took(dt, steps);
        self.behind += u64::from(steps);
        Ok(())
    }

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
            let log = world.row_log.take().unwrap_or_default();
            let logged = self.revision + log.len() as u64;
            world.row_log = Some(log);
            if world.revision() != logged || world.edited {
                return Err(GpuStepError::Edited);
            }
            world.row_log.take().unwrap_or_default()
        } else {
            if world.revision() != self.revision || world.len() != self.len() {
                return Err(GpuStepError::Edited);
            }
            self.following = true;
            Vec::new()
        };
        let outcome = self.advance_logged(gpu, world, step, &mut log);
        log.clear();
        world.row_log = Some(log);
        self.revision = world.revision();
        outcome
    }

    /// [`advance`](Self::advance) once the world's log is taken: `log`
    /// holds the changes since the last step, and is used again for the
    /// step's own.
    fn advance_logged(
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
        world.contacts.clear();
        let mut past_room = None;
        if self.plan.reporting > 0 && self.n > 0 {
            past_room = self.read_touches(gpu, world)?;
        }
        // The rest of the world's step, logging the rows it changes, which
        // the GPU's rows then follow.
        world.row_log = Some(core::mem::take(log));
        let report = world.step_bookkeeping(step);
        *log = world.row_log.take().unwrap_or_default();
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
    fn touch_room(&self) -> u32 {
        u32::try_from(self.touches.size() / TOUCH_BYTES).unwrap_or(u32::MAX)
    }

    /// Reads the step's contacts back (a wait for the GPU) into the world's
    /// touches, and names them as the CPU's step does (sorted by collider
    /// and row, whatever order the GPU found them in). A step that found
    /// more than the room for them keeps those that fit and returns how
    /// many it found and the room.
    fn read_touches(&self, gpu: &Gpu, world: &mut World) -> Result<Option<(u32, u32)>, GpuStepError> {
        let [count] = map_words(gpu, [(&self.flags, 8, 4)])?;
        let found = f32_at(&count, 0).to_bits();
        let room = self.touch_room();
        let count = found.min(room);
        world.touches.clear();
        if count > 0 {
            let [records] = map_words(gpu, [(&self.touches, 0, u64::from(count) * TOUCH_BYTES)])?;
            world
                .touches
                .extend(records.chunks_exact(TOUCH_BYTES as usize).map(|t| {
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
        }
        world.name_contacts(false);
        Ok((found > room).then_some((found, room)))
    }

    /// Before steps of `dt`: tells a method with history, through its
    /// flags, whether every particle starts afresh (the first step, a new
    /// step length, a new method) or rows changed, as the CPU's history
    /// decides it.
    fn start_history(&mut self, gpu: &Gpu, dt: f32) {
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
    fn follow_rows(
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

    /// Grows the state buffers to hold `rows` (at least twice what they
    /// held), copying what they hold in `encoder`.
    fn reserve(&mut self, gpu: &Gpu, encoder: &mut wgpu::CommandEncoder, rows: u32) -> Result<(), GpuStepError> {
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
    fn rebind(&mut self, device: &wgpu::Device) {
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
    fn adopt_plan(&mut self, gpu: &Gpu) -> Result<(), GpuStepError> {
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
    fn keep_previous(&self, encoder: &mut wgpu::CommandEncoder) {
        let bytes = u64::from(self.n) * 16;
        encoder.copy_buffer_to_buffer(&self.state.positions, 0, &self.state.previous, 0, bytes);
    }

    /// Waits until the GPU has done every step it was given (a tool's
    /// progress, a bounded queue; a game's frame needs no wait).
    ///
    /// # Errors
    /// [`GpuStepError::ReadBack`] with the device's message if it is lost.
    pub fn finish(&self, gpu: &Gpu) -> Result<(), GpuStepError> {
        gpu.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| GpuStepError::ReadBack(e.to_string()))
    }

    /// Records `steps` steps from the world's tick `first` into one compute
    /// pass of `encoder`: each the n-body pull (if any), the step, and the
    /// subnormal flush after the ticks the CPU flushes.
    fn encode_steps(&self, encoder: &mut wgpu::CommandEncoder, first: u64, steps: u32) {
        if steps == 0 {
            return;
        }
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("tickwork gpu step"),
            timestamp_writes: None,
        });
        pass.set_bind_group(0, &self.bind_group, &[]);
        let p = &self.pipelines;
        for tick in first..first + u64::from(steps) {
            for (probe, sums) in &p.rounds {
                pass.set_pipeline(probe);
                pass.dispatch_workgroups(self.groups.0, self.groups.1, 1);
                pass.set_pipeline(sums);
                pass.dispatch_workgroups(self.groups.0, self.groups.1, 1);
            }
            pass.set_pipeline(&p.step);
            pass.dispatch_workgroups(self.groups.0, self.groups.1, 1);
            if tick.is_multiple_of(crate::step::SUBNORMAL_FLUSH_EVERY) {
                pass.set_pipeline(&p.flush);
                pass.dispatch_workgroups(self.groups.0, self.groups.1, 1);
            }
            if let Some(rotate) = &p.rotate {
                pass.set_pipeline(rotate);
                pass.dispatch_workgroups(1, 1, 1);
            }
        }
    }

    /// Copies the state back: every position and velocity, in the world's
    /// row order. It costs a copy of both buffers (32 bytes a particle)
    /// into a mappable one and a wait for the GPU to finish all it was
    /// given: for tests, checksums and snapshots, not every frame.
    ///
    /// # Errors
    /// [`GpuStepError::ReadBack`] if the buffer cannot be mapped.
    pub fn read_back(&self, gpu: &Gpu) -> Result<(Vec<Vec3>, Vec<Vec3>), GpuStepError> {
        let [positions, velocities] = self.read(gpu, [&self.state.positions, &self.state.velocities])?;
        Ok((positions, velocities))
    }

    /// Writes the GPU's state into `world`, the world this was made from,
    /// as the CPU's steps would have left it: positions, velocities and
    /// the previous positions; for steps taken with [`step`](Self::step),
    /// also the tick and time after `last` (the last step taken, as the
    /// clock gave it) and the lived time (each step's `dt` added, as the
    /// CPU adds it), which [`advance`](Self::advance) has booked already
    /// (then `last` is not read). Its checksum is then the CPU run's where
    /// the GPU's states are the CPU's (on lavapipe, tested), and the
    /// adapter's own elsewhere; for a method with history it differs even
    /// so: the checksum covers the method's history, which stays on the
    /// GPU (the world's integrator keeps none). Costs a read-back of three buffers (48
    /// bytes a particle) and a wait.
    ///
    /// # Errors
    /// [`GpuStepError::ReadBack`] if the buffers cannot be mapped;
    /// [`GpuStepError::NonFinite`] for a state that became infinite or
    /// NaN; [`GpuStepError::Unsupported`] for a world that is not this
    /// one's (another particle count, or a tick that `last` does not
    /// follow from).
    pub fn store_into(&mut self, gpu: &Gpu, world: &mut World, last: FixedStep) -> Result<(), GpuStepError> {
        let booked = if self.behind == 0 {
            world.tick() == self.next_tick
        } else {
            world.tick() + self.behind == last.tick + 1
        };
        if world.len() != self.len() || !booked {
            return Err(GpuStepError::Unsupported(
                "storing into a world other than the one it was made from, at the tick it was made",
            ));
        }
        if self.ticks == 0 {
            return Ok(());
        }
        if self.behind > 0 && self.dt != Ok(Some(last.dt as f32)) {
            return Err(GpuStepError::Unsupported(
                "storing steps of different lengths, or of another length than the last step's",
            ));
        }
        let [x, v, previous] = self.read(
            gpu,
            [&self.state.positions, &self.state.velocities, &self.state.previous],
        )?;
        // As the CPU's step refuses a state it made non-finite.
        if let Some(row) = x.iter().zip(&v).position(|(x, v)| !(x.is_finite() && v.is_finite())) {
            return Err(GpuStepError::NonFinite {
                row,
                position: x[row],
                velocity: v[row],
            });
        }
        let p = &mut world.particles;
        for (row, ((x, v), previous)) in x.iter().zip(&v).zip(&previous).enumerate() {
            p.position.set(row, Vec3A::from(*x));
            p.velocity.set(row, Vec3A::from(*v));
            p.previous_position.set(row, Vec3A::from(*previous));
        }
        if self.behind > 0 {
            world.contacts.clear();
            world.removed.clear();
            for _ in 0..self.behind {
                p.lifetimes.lived += last.dt;
            }
            world.tick = last.tick + 1;
            world.time = last.time + last.dt;
            self.behind = 0;
        }
        world.revision += 1;
        self.revision = world.revision();
        Ok(())
    }

    /// Copies `buffers` out and waits: their `xyz`, a particle each.
    fn read<const N: usize>(&self, gpu: &Gpu, buffers: [&wgpu::Buffer; N]) -> Result<[Vec<Vec3>; N], GpuStepError> {
        let bytes = u64::from(self.n) * 16;
        let parts = map_words(gpu, buffers.map(|buffer| (buffer, 0, bytes)))?;
        Ok(parts.map(|part| {
            part.chunks_exact(16)
                .map(|r| Vec3::new(f32_at(r, 0), f32_at(r, 1), f32_at(r, 2)))
                .collect()
        }))
    }
}

/// The colliders' records (one zeroed record for none: a binding is never
/// empty, and `colliders: 0` reads none).
fn colliders_buffer(device: &wgpu::Device, colliders: &[ColliderRecord]) -> wgpu::Buffer {
    let zero = [bytemuck::Zeroable::zeroed()];
    let records: &[ColliderRecord] = if colliders.is_empty() { &zero } else { colliders };
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("tickwork gpu step colliders"),
        contents: bytemuck::cast_slice(records),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
    })
}

/// Copies each `(buffer, offset, bytes)` out and waits: their bytes. A
/// page cannot wait, and is told so.
fn map_words<const N: usize>(gpu: &Gpu, parts: [(&wgpu::Buffer, u64, u64); N]) -> Result<[Vec<u8>; N], GpuStepError> {
    let total: u64 = parts.iter().map(|p| p.2).sum();
    let staging = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("tickwork gpu step read-back"),
        size: total.max(4),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("tickwork gpu step read-back"),
    });
    let mut at = 0;
    for (buffer, offset, bytes) in parts {
        encoder.copy_buffer_to_buffer(buffer, offset, &staging, at, bytes);
        at += bytes;
    }
    gpu.queue.submit([encoder.finish()]);
    let slice = staging.slice(..);
    let (sender, receiver) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |result| {
        let _ = sender.send(result);
    });
    gpu.device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| GpuStepError::ReadBack(e.to_string()))?;
    // Natively the wait has run the callback; a page cannot wait (its GPU
    // answers once its script yields), and is told so.
    receiver
        .try_recv()
        .map_err(|_| {
            GpuStepError::ReadBack(
                "the GPU has not answered: a page cannot wait for a read-back (read a GPU world back natively)".into(),
            )
        })?
        .map_err(|e| GpuStepError::ReadBack(e.to_string()))?;
    let mapped = slice
        .get_mapped_range()
        .map_err(|e| GpuStepError::ReadBack(e.to_string()))?;
    let mut at = 0usize;
    Ok(parts.map(|(_, _, bytes)| {
        let part = mapped[at..at + bytes as usize].to_vec();
        at += bytes as usize;
        part
    }))
}

/// The `k`th 4-byte word of `bytes` as an f32 (0 past the end).
fn f32_at(bytes: &[u8], k: usize) -> f32 {
    bytes
        .get(4 * k..4 * k + 4)
        .and_then(|w| w.try_into().ok())
        .map_or(0.0, f32::from_le_bytes)
}

/// Room for `room` contacts (48 bytes each; one for none).
fn touches_buffer(device: &wgpu::Device, room: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("tickwork gpu step touches"),
        size: TOUCH_BYTES * room.max(1),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}

/// A contact's record (`Touch` in `step.wgsl`).
const TOUCH_BYTES: u64 = 48;

/// Where the world has an n-body force, `stages + 1` vec4s a particle
/// (each evaluation's sums, and the trial positions being summed); one
/// vec4 otherwise (a binding is never empty).
fn nbody_buffer(device: &wgpu::Device, stages: u32, capacity: u32) -> wgpu::Buffer {
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
fn step_bind_group(
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

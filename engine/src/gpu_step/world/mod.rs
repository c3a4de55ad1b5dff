//! A particle world on the GPU: its state in two storage buffers, stepped
//! by one dispatch a fixed step.

mod advance;
mod buffers;
mod read_back;

use super::dispatch::dispatch;
use super::error::GpuStepError;
use super::kernel::{Plan, changes_rows, coefficients, plan};
use super::rows::{RowKernel, RowPlan};
use crate::device::{Gpu, compute_storage, entry as buffer_entry};
use crate::world::World;

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
}

use buffers::{Pipelines, State, colliders_buffer, nbody_buffer, step_bind_group, touches_buffer};

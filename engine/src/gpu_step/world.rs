//! A particle world on the GPU: its state in two storage buffers, stepped
//! by one dispatch a fixed step.

use glam::{Vec3, Vec3A};
use wgpu::util::DeviceExt;

use super::error::GpuStepError;
use super::kernel::{ColliderRecord, Plan, coefficients, plan};
use crate::clock::FixedStep;
use crate::render::Gpu;
use crate::world::World;

/// Invocations a workgroup (`@workgroup_size` in `step.wgsl`).
pub const WORKGROUP: u32 = 256;

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
    /// WGSL rounds a uniform struct's size up to 16 bytes.
    _pad: f32,
}

const _: () = assert!(std::mem::size_of::<Params>() == 80 && std::mem::offset_of!(Params, drift) == 32);

/// A world's particles stepped on the GPU (see the [module](super)): made
/// from a [`World`] (its state uploaded once), stepped with
/// [`step`](Self::step), read back only when asked.
#[derive(Debug)]
pub struct GpuWorld {
    plan: Plan,
    n: u32,
    groups: (u32, u32),
    /// `(x, y, z, radius)` a particle.
    positions: wgpu::Buffer,
    /// `(vx, vy, vz, inverse mass)` a particle.
    velocities: wgpu::Buffer,
    /// The positions at the start of the last step (a copy before its
    /// dispatch): the world's previous positions, for interpolation.
    previous: wgpu::Buffer,
    /// Each particle's colour, for drawing.
    colours: wgpu::Buffer,
    params: wgpu::Buffer,
    pipeline: wgpu::ComputePipeline,
    /// Each particle's n-body acceleration at the step's start, where the
    /// world has an n-body force.
    nbody: Option<wgpu::ComputePipeline>,
    /// Subnormal velocities to 0, after the ticks the CPU's step flushes.
    flush: wgpu::ComputePipeline,
    /// The world's tick at the next step (the flush's schedule follows it).
    next_tick: u64,
    bind_group: wgpu::BindGroup,
    ticks: u64,
    /// The length of every step taken, while they were all the same
    /// (`Err` once two differed): what `store_into` ages the world by.
    dt: Result<Option<f32>, ()>,
}

impl GpuWorld {
    /// Uploads `world`'s particles to `gpu` and builds its step.
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
        let plan = plan(world)?;
        let p = world.particles();
        let count = p.len();
        let (n, groups) = dispatch(count, &gpu.device.limits())?;
        let mut positions = Vec::with_capacity(count.max(1));
        let mut previous = Vec::with_capacity(count.max(1));
        let mut velocities = Vec::with_capacity(count.max(1));
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
        // A binding is never empty.
        if count == 0 {
            positions.push([0.0; 4]);
            previous.push([0.0; 4]);
            velocities.push([0.0; 4]);
        }
        let device = &gpu.device;
        let storage = |label, data: &[[f32; 4]]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytemuck::cast_slice(data),
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::VERTEX
                    | wgpu::BufferUsages::COPY_SRC
                    | wgpu::BufferUsages::COPY_DST,
            })
        };
        let previous = storage("tickwork gpu step previous positions", &previous);
        let positions = storage("tickwork gpu step positions", &positions);
        let velocities = storage("tickwork gpu step velocities", &velocities);
        let mut records: Vec<ColliderRecord> = plan.colliders.clone();
        if records.is_empty() {
            // A binding is never empty; `colliders: 0` reads none.
            records.push(bytemuck::Zeroable::zeroed());
        }
        // Colours for drawing: sRGB RGBA as little-endian words, hidden
        // particles transparent (as the renderer's own records).
        let hidden = world.hidden_rows();
        let mut colours: Vec<u32> = (0..count)
            .map(|k| {
                let shown = hidden.is_none_or(|h| !h[k].0);
                if shown { u32::from_le_bytes(p.colour[k]) } else { 0 }
            })
            .collect();
        if colours.is_empty() {
            colours.push(0);
        }
        let colours = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("tickwork gpu step colours"),
            contents: bytemuck::cast_slice(&colours),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let colliders = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("tickwork gpu step colliders"),
            contents: bytemuck::cast_slice(&records),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("tickwork gpu step params"),
            size: std::mem::size_of::<Params>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        // A vec4 a particle where the world has an n-body force; one
        // otherwise (a binding is never empty).
        let nbody_accel = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("tickwork gpu step n-body"),
            size: if plan.nbody.is_some() {
                16 * count.max(1) as u64
            } else {
                16
            },
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(plan.method),
            source: wgpu::ShaderSource::Wgsl(plan.source.as_str().into()),
        });
        let entry = |binding, ty| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty,
            count: None,
        };
        let storage = |read_only| wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("tickwork gpu step"),
            entries: &[
                entry(
                    0,
                    wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                ),
                entry(1, storage(false)),
                entry(2, storage(false)),
                entry(3, storage(true)),
                entry(4, storage(false)),
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("tickwork gpu step"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline_of = |entry_point| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry_point),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(entry_point),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let pipeline = pipeline_of("step");
        let nbody = plan.nbody.map(|_| pipeline_of("nbody"));
        let flush = pipeline_of("flush");
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("tickwork gpu step"),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: params.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: positions.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: velocities.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: colliders.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: nbody_accel.as_entire_binding(),
                },
            ],
        });
        Ok(Self {
            plan,
            n,
            groups,
            positions,
            velocities,
            previous,
            colours,
            params,
            pipeline,
            nbody,
            flush,
            next_tick: world.tick(),
            bind_group,
            ticks: 0,
            dt: Ok(None),
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
            previous: &self.previous,
            current: &self.positions,
            colours: &self.colours,
            count: self.n,
        }
    }

    /// The state's two buffers, `(x, y, z, radius)` and `(vx, vy, vz,
    /// inverse mass)` a particle, for a renderer or a benchmark's copy.
    #[must_use]
    pub fn buffers(&self) -> (&wgpu::Buffer, &wgpu::Buffer) {
        (&self.positions, &self.velocities)
    }

    /// Records `steps` fixed steps of `dt` seconds into one command
    /// buffer, one dispatch each in one compute pass (WebGPU orders their
    /// storage writes), and submits it. Nothing is read back.
    ///
    /// # Errors
    /// [`GpuStepError::Step`] for a `dt` that is not finite and positive.
    pub fn step(&mut self, gpu: &Gpu, dt: f32, steps: u32) -> Result<(), GpuStepError> {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(GpuStepError::Step(dt));
        }
        if steps > 0 {
            self.dt = match self.dt {
                Ok(None) => Ok(Some(dt)),
                Ok(Some(same)) if same.to_bits() == dt.to_bits() => Ok(Some(dt)),
                _ => Err(()),
            };
        }
        let (c, b) = self.plan.affine;
        let (drift, kick) = coefficients(self.plan.method, dt);
        let (nbody_g, nbody_eps2) = self.plan.nbody.unwrap_or_default();
        let params = Params {
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
            _pad: 0.0,
        };
        gpu.queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        let mut encoder = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("tickwork gpu step"),
        });
        if self.n > 0 && steps > 0 {
            // All steps but the last, then the positions kept as the
            // previous ones, then the last.
            self.encode_steps(&mut encoder, self.next_tick, steps - 1);
            let bytes = self.positions.size();
            encoder.copy_buffer_to_buffer(&self.positions, 0, &self.previous, 0, bytes);
            self.encode_steps(&mut encoder, self.next_tick + u64::from(steps - 1), 1);
        }
        self.next_tick += u64::from(steps);
        gpu.queue.submit([encoder.finish()]);
        self.ticks += u64::from(steps);
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
        for tick in first..first + u64::from(steps) {
            if let Some(nbody) = &self.nbody {
                pass.set_pipeline(nbody);
                pass.dispatch_workgroups(self.groups.0, self.groups.1, 1);
            }
            pass.set_pipeline(&self.pipeline);
            pass.dispatch_workgroups(self.groups.0, self.groups.1, 1);
            if tick.is_multiple_of(crate::step::SUBNORMAL_FLUSH_EVERY) {
                pass.set_pipeline(&self.flush);
                pass.dispatch_workgroups(self.groups.0, self.groups.1, 1);
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
        let [positions, velocities] = self.read(gpu, [&self.positions, &self.velocities])?;
        Ok((positions, velocities))
    }

    /// Writes the GPU's state into `world`, the world this was made from,
    /// as the CPU's steps would have left it: positions, velocities and
    /// the previous positions, the tick and time after `last` (the last
    /// step taken, as the clock gave it), the lived time (each step's `dt`
    /// added, as the CPU adds it). Its checksum is then the CPU run's where
    /// the GPU's states are the CPU's (on lavapipe, tested), and the
    /// adapter's own elsewhere. Costs a read-back of three buffers (48
    /// bytes a particle) and a wait.
    ///
    /// # Errors
    /// [`GpuStepError::ReadBack`] if the buffers cannot be mapped;
    /// [`GpuStepError::Unsupported`] for a world that is not this one's
    /// origin (another particle count, or a tick that `last` does not
    /// follow from).
    pub fn store_into(&self, gpu: &Gpu, world: &mut World, last: FixedStep) -> Result<(), GpuStepError> {
        if world.len() != self.len() || world.tick() + self.ticks != last.tick + 1 {
            return Err(GpuStepError::Unsupported(
                "storing into a world other than the one it was made from, at the tick it was made",
            ));
        }
        if self.ticks == 0 {
            return Ok(());
        }
        if self.dt != Ok(Some(last.dt as f32)) {
            return Err(GpuStepError::Unsupported(
                "storing steps of different lengths, or of another length than the last step's",
            ));
        }
        let [x, v, previous] = self.read(gpu, [&self.positions, &self.velocities, &self.previous])?;
        // As the CPU's step refuses a state it made non-finite.
        if let Some(row) = x.iter().zip(&v).position(|(x, v)| !(x.is_finite() && v.is_finite())) {
            return Err(GpuStepError::NonFinite {
                row,
                position: x[row],
                velocity: v[row],
            });
        }
        world.contacts.clear();
        world.removed.clear();
        let p = &mut world.particles;
        for (row, ((x, v), previous)) in x.iter().zip(&v).zip(&previous).enumerate() {
            p.position.set(row, Vec3A::from(*x));
            p.velocity.set(row, Vec3A::from(*v));
            p.previous_position.set(row, Vec3A::from(*previous));
        }
        for _ in 0..self.ticks {
            p.lifetimes.lived += last.dt;
        }
        world.tick = last.tick + 1;
        world.time = last.time + last.dt;
        world.revision += 1;
        Ok(())
    }

    /// Copies `buffers` out and waits: their `xyz`, a particle each.
    fn read<const N: usize>(&self, gpu: &Gpu, buffers: [&wgpu::Buffer; N]) -> Result<[Vec<Vec3>; N], GpuStepError> {
        let bytes = self.positions.size();
        let staging = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("tickwork gpu step read-back"),
            size: N as u64 * bytes,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("tickwork gpu step read-back"),
        });
        for (k, buffer) in buffers.iter().enumerate() {
            encoder.copy_buffer_to_buffer(buffer, 0, &staging, k as u64 * bytes, bytes);
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
        receiver
            .recv()
            .map_err(|_| GpuStepError::ReadBack("the read-back was dropped".into()))?
            .map_err(|e| GpuStepError::ReadBack(e.to_string()))?;
        let mapped = slice
            .get_mapped_range()
            .map_err(|e| GpuStepError::ReadBack(e.to_string()))?;
        let records: &[[f32; 4]] = bytemuck::cast_slice(&mapped);
        let each = records.len() / N;
        let n = self.len();
        Ok(std::array::from_fn(|k| {
            records[k * each..(k + 1) * each]
                .iter()
                .take(n)
                .map(|r| Vec3::new(r[0], r[1], r[2]))
                .collect()
        }))
    }
}

/// The particle count as the shader's `n`, and the workgroups of one
/// dispatch `(x, y)` (past the per-dimension limit, the rest folds into
/// y), or the limit the particles are past.
fn dispatch(count: usize, limits: &wgpu::Limits) -> Result<(u32, (u32, u32)), GpuStepError> {
    let bytes = count as u64 * 16;
    for (limit, value) in [
        (
            "max_storage_buffer_binding_size",
            limits.max_storage_buffer_binding_size,
        ),
        ("max_buffer_size", limits.max_buffer_size),
    ] {
        if bytes > value {
            return Err(GpuStepError::Limit {
                limit,
                value,
                needed: bytes,
                fits: value / 16,
            });
        }
    }
    let per_dimension = u64::from(limits.max_compute_workgroups_per_dimension.max(1));
    let groups = (count as u64).div_ceil(u64::from(WORKGROUP));
    let x = groups.min(per_dimension);
    let y = groups.div_ceil(x.max(1));
    let n = u32::try_from(count)
        .ok()
        .filter(|_| y <= per_dimension)
        .ok_or(GpuStepError::Limit {
            limit: "max_compute_workgroups_per_dimension",
            value: per_dimension,
            needed: y,
            fits: per_dimension * per_dimension * u64::from(WORKGROUP),
        })?;
    // Both fit in u32: x and y are at most the per-dimension limit.
    Ok((n, (x as u32, y.max(1) as u32)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dispatch_folds_past_the_per_dimension_limit_and_buffers_past_their_limits_are_errors() {
        let limits = wgpu::Limits {
            max_compute_workgroups_per_dimension: 65_535,
            max_storage_buffer_binding_size: 1 << 30,
            max_buffer_size: 1 << 30,
            ..wgpu::Limits::downlevel_defaults()
        };
        assert_eq!(dispatch(0, &limits), Ok((0, (0, 1))));
        assert_eq!(dispatch(1000, &limits), Ok((1000, (4, 1))));
        // 10 million: 39 063 workgroups, one row.
        assert_eq!(dispatch(10_000_000, &limits), Ok((10_000_000, (39_063, 1))));
        // 20 million: 78 125 workgroups, two rows of 65 535.
        assert_eq!(dispatch(20_000_000, &limits), Ok((20_000_000, (65_535, 2))));
        let small = wgpu::Limits {
            max_storage_buffer_binding_size: 1 << 20,
            ..limits
        };
        assert_eq!(
            dispatch(100_000, &small),
            Err(GpuStepError::Limit {
                limit: "max_storage_buffer_binding_size",
                value: 1 << 20,
                needed: 1_600_000,
                fits: 65_536,
            })
        );
        assert_eq!(
            dispatch(100_000, &small).map_err(|e| e.to_string()),
            Err(
                "the particles need 1600000 of the device's max_storage_buffer_binding_size (1048576): at most \
                 65536 particles fit"
                    .to_owned()
            )
        );
    }
}

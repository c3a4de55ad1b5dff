//! GPU worlds' particles gathered into the frame's instance records
//! (`engine/shaders/gather.wgsl`): one compute pass a frame writes each
//! GPU world's previous and current positions, radii and colours after
//! the CPU worlds' records, so the quads and the splat draw every world
//! the same way. Nothing is uploaded or read back: 32 bytes a particle
//! written on the GPU.

use super::frame_view::GpuParticles;
use crate::device::{Gpu, bind_buffers, compute_pipeline, entry, wgsl};

/// Invocations a workgroup (`@workgroup_size` in `gather.wgsl`).
const WORKGROUP: u32 = 64;

/// `Gather` in `gather.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct GatherParams {
    first: u32,
    count: u32,
    groups_x: u32,
    pad: u32,
}

/// The gather pipelines and a uniform a GPU world.
pub(crate) struct Gather {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
    /// Velocities into the Hermite records (group 1: the world's
    /// velocities, the records).
    velocity_layout: wgpu::BindGroupLayout,
    velocity_pipeline: wgpu::ComputePipeline,
    /// One a GPU world of the frame, kept from frame to frame.
    params: Vec<wgpu::Buffer>,
}

impl Gather {
    pub(crate) fn new(device: &wgpu::Device) -> Self {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("tickwork gather"),
            source: wgpu::ShaderSource::Wgsl(wgsl!("gather.wgsl").into()),
        });
        let buffer = |binding, ty| entry(binding, wgpu::ShaderStages::COMPUTE, ty);
        use wgpu::BufferBindingType::{Storage, Uniform};
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("tickwork gather"),
            entries: &[
                buffer(0, Uniform),
                buffer(1, Storage { read_only: true }),
                buffer(2, Storage { read_only: true }),
                buffer(3, Storage { read_only: true }),
                buffer(4, Storage { read_only: false }),
            ],
        });
        let velocity_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("tickwork gather velocities"),
            entries: &[
                buffer(0, Storage { read_only: true }),
                buffer(1, Storage { read_only: false }),
            ],
        });
        let pipeline = |layouts: &[Option<&wgpu::BindGroupLayout>], entry_point| {
            let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(entry_point),
                bind_group_layouts: layouts,
                immediate_size: 0,
            });
            compute_pipeline(device, &pipeline_layout, &module, entry_point, &[])
        };
        Self {
            pipeline: pipeline(&[Some(&layout)], "gather_particles"),
            velocity_pipeline: pipeline(&[Some(&layout), Some(&velocity_layout)], "gather_velocities"),
            layout,
            velocity_layout,
            params: Vec::new(),
        }
    }

    /// Writes `worlds`' particles into `instances` from record `first` on,
    /// one after the other (and their velocities into `hermite`'s velocity
    /// records, if given), and submits the pass (before the frame's own
    /// commands, which draw them).
    pub(crate) fn gather(
        &mut self,
        gpu: &Gpu,
        instances: &wgpu::Buffer,
        hermite: Option<&wgpu::Buffer>,
        first: u32,
        worlds: &[GpuParticles<'_>],
    ) {
        let device = &gpu.device;
        while self.params.len() < worlds.len() {
            self.params.push(device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("tickwork gather params"),
                size: std::mem::size_of::<GatherParams>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }));
        }
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("tickwork gather"),
        });
        let per_dimension = device.limits().max_compute_workgroups_per_dimension.max(1);
        let mut first = first;
        for (world, params) in worlds.iter().zip(&self.params) {
            let groups = world.count.div_ceil(WORKGROUP);
            let x = groups.min(per_dimension);
            let y = groups.div_ceil(x.max(1));
            let uniform = GatherParams {
                first,
                count: world.count,
                groups_x: x,
                pad: 0,
            };
            first = first.saturating_add(world.count);
            if world.count == 0 {
                continue;
            }
            gpu.queue.write_buffer(params, 0, bytemuck::bytes_of(&uniform));
            let bind_group = bind_buffers(
                device,
                &self.layout,
                &[params, world.previous, world.current, world.colours, instances],
            );
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("tickwork gather"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.dispatch_workgroups(x, y, 1);
            if let Some(records) = hermite {
                let velocities = bind_buffers(device, &self.velocity_layout, &[world.velocities, records]);
                pass.set_pipeline(&self.velocity_pipeline);
                pass.set_bind_group(1, &velocities, &[]);
                pass.dispatch_workgroups(x, y, 1);
            }
        }
        gpu.queue.submit([encoder.finish()]);
    }
}

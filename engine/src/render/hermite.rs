//! The GPU side of [`Interpolation::Hermite`](crate::interpolation::Interpolation::Hermite):
//! a second buffer of velocities and the pipeline that reads it, built the
//! first time a frame asks for Hermite.
//!
//! The shader's `hermite_from_end` (common.wgsl) needs each particle's
//! current velocity besides the 32-byte record's two positions. Rather
//! than grow that record for every frame (lerp needs no velocity), the
//! velocities go into a buffer of their own, 12 bytes a particle, bound
//! at binding 2 and read by the `vs_hermite` entry point only: a lerp
//! frame uploads, binds and reads exactly what it did before, and a
//! Hermite frame uploads 44 bytes a particle instead of 32.

use bytemuck::{Pod, Zeroable};

use super::Gpu;
use super::frame_view::FrameView;
use super::renderer::{bind_buffers, entry, record_buffer, write_records};

/// One particle's current velocity as the shader reads it (12 bytes, as
/// the WGSL `Velocity`), row for row with the instance records.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub(crate) struct Velocity([f32; 3]);

/// The Hermite pipeline, its layout and the velocity buffer.
pub(crate) struct HermiteParticles {
    /// Globals, instances, velocities (bindings 0, 1, 2).
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    velocities: wgpu::Buffer,
    /// Over the current globals, instances and velocities; `None` once one
    /// of them was replaced.
    bind_group: Option<wgpu::BindGroup>,
    scratch: Vec<Velocity>,
    /// The world states whose velocities were last uploaded: (world id,
    /// revision) of each world, as the renderer keys its instances.
    uploaded: Vec<(u64, u64)>,
    upload_key: Vec<(u64, u64)>,
}

impl HermiteParticles {
    /// The layout and pipeline; `make_pipeline` builds the particle
    /// pipeline for a layout and a vertex entry point, as the lerp one is
    /// built.
    pub(crate) fn new(
        device: &wgpu::Device,
        layout_entries: &[wgpu::BindGroupLayoutEntry],
        make_pipeline: impl FnOnce(&wgpu::BindGroupLayout, &str) -> wgpu::RenderPipeline,
    ) -> Self {
        let mut entries = layout_entries.to_vec();
        entries.push(entry(
            2,
            wgpu::ShaderStages::VERTEX,
            wgpu::BufferBindingType::Storage { read_only: true },
        ));
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("tickwork particles (Hermite)"),
            entries: &entries,
        });
        let pipeline = make_pipeline(&layout, "vs_hermite");
        Self {
            layout,
            pipeline,
            velocities: record_buffer::<Velocity>(device, "tickwork velocities", 1024),
            bind_group: None,
            scratch: Vec::new(),
            uploaded: Vec::new(),
            upload_key: Vec::new(),
        }
    }

    /// Forgets the bind group (the instance buffer was replaced).
    pub(crate) fn invalidate(&mut self) {
        self.bind_group = None;
    }

    /// Forgets what was uploaded, so the next frame uploads again.
    pub(crate) fn forget_upload(&mut self) {
        self.uploaded.clear();
    }

    /// Uploads the velocities of `view`'s worlds if they changed since the
    /// last upload and makes the bind group current; returns whether the
    /// velocity buffer was replaced (the splat's bind groups then are stale).
    pub(crate) fn upload(
        &mut self,
        gpu: &Gpu,
        view: &FrameView<'_>,
        globals: &wgpu::Buffer,
        instances: &wgpu::Buffer,
    ) -> bool {
        let mut replaced = false;
        self.upload_key.clear();
        self.upload_key
            .extend(view.worlds().map(|w| (w.world.id(), w.world.revision())));
        if self.uploaded != self.upload_key {
            std::mem::swap(&mut self.uploaded, &mut self.upload_key);
            let n: usize = view.worlds().map(|w| w.world.len()).sum();
            if (n * std::mem::size_of::<Velocity>()) as u64 > self.velocities.size() {
                self.velocities = record_buffer::<Velocity>(&gpu.device, "tickwork velocities", n.next_power_of_two());
                self.bind_group = None;
                replaced = true;
            }
            if n > 0 {
                write_records(gpu, view, n, &mut self.scratch, &self.velocities, velocity_block);
            }
        }
        if self.bind_group.is_none() {
            self.bind_group = Some(bind_buffers(
                &gpu.device,
                &self.layout,
                &[globals, instances, &self.velocities],
            ));
        }
        replaced
    }

    /// The velocity buffer, for the splat's Hermite pass.
    pub(crate) fn velocities(&self) -> &wgpu::Buffer {
        &self.velocities
    }

    /// Draws `count` particles by `vs_hermite` (after [`upload`](Self::upload)).
    pub(crate) fn draw(&self, pass: &mut wgpu::RenderPass<'_>, count: u32) {
        let Some(bind_group) = &self.bind_group else {
            return;
        };
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.draw(0..4, 0..count);
    }
}

/// The velocity records of the block of four rows from row `first`, as
/// the instance records are filled.
fn velocity_block(particles: &crate::world::Particles, first: usize, records: &mut [Velocity]) {
    let v = &particles.velocity.blocks()[first / 4];
    let (x, y, z) = (v.x.to_array(), v.y.to_array(), v.z.to_array());
    for (k, record) in records.iter_mut().enumerate() {
        *record = Velocity([x[k], y[k], z[k]]);
    }
}

#[cfg(test)]
mod tests {
    use super::Velocity;
    use crate::render::renderer::Instance;

    #[test]
    fn lerp_keeps_its_32_byte_record_and_hermite_adds_12() {
        assert_eq!(std::mem::size_of::<Instance>(), 32);
        assert_eq!(std::mem::size_of::<Velocity>(), 12);
    }
}

//! The GPU side of [`Interpolation::Hermite`](crate::interpolation::Interpolation::Hermite):
//! a second buffer of velocities and the pipeline that reads it, built the
//! first time a frame asks for Hermite.
//!
//! The shader's `hermite_from_end` (common.wgsl) needs each particle's
//! current velocity besides the 32-byte record's two positions. Rather
//! than grow that record for every frame (lerp needs no velocity), the
//! velocities go into a buffer of their own, 12 bytes a particle, bound
//! as vertex buffer 1 and read by the `vs_hermite` entry point only: a lerp
//! frame uploads, binds and reads exactly what it did before, and a
//! Hermite frame uploads 44 bytes a particle instead of 32.

use bytemuck::{Pod, Zeroable};

use super::Gpu;
use super::frame_view::FrameView;
use super::records::{instance_buffer_layout, record_buffer, write_records};

/// One particle's current velocity as the shader reads it (12 bytes, as
/// the WGSL `Velocity`), row for row with the instance records.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub(crate) struct Velocity([f32; 3]);

/// The velocities as `vs_hermite`'s per-instance attribute, slot 1.
const VELOCITY_ATTRIBUTES: [wgpu::VertexAttribute; 1] = wgpu::vertex_attr_array![4 => Float32x3];

/// The Hermite pipeline and the velocity buffer.
pub(crate) struct HermiteParticles {
    /// Over the particles' layout (the globals), instances in vertex
    /// buffer 0, velocities in 1.
    pipeline: wgpu::RenderPipeline,
    velocities: wgpu::Buffer,
    scratch: Vec<Velocity>,
    /// The world states whose velocities were last uploaded: (world id,
    /// revision) of each world, as the renderer keys its instances.
    uploaded: Vec<(u64, u64)>,
    upload_key: Vec<(u64, u64)>,
}

impl HermiteParticles {
    /// The pipeline; `make_pipeline` builds the particle pipeline for a
    /// vertex entry point and its vertex buffers, as the lerp one is built.
    pub(crate) fn new(
        device: &wgpu::Device,
        make_pipeline: impl FnOnce(&str, &[Option<wgpu::VertexBufferLayout<'_>>]) -> wgpu::RenderPipeline,
    ) -> Self {
        let velocities = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<Velocity>() as u64,
            step_mode: wgpu::VertexStepMode::Instance,
            attributes: &VELOCITY_ATTRIBUTES,
        };
        let pipeline = make_pipeline("vs_hermite", &[Some(instance_buffer_layout()), Some(velocities)]);
        Self {
            pipeline,
            velocities: record_buffer::<Velocity>(device, "tickwork velocities", 1024),
            scratch: Vec::new(),
            uploaded: Vec::new(),
            upload_key: Vec::new(),
        }
    }

    /// Forgets what was uploaded, so the next frame uploads again.
    pub(crate) fn forget_upload(&mut self) {
        self.uploaded.clear();
    }

    /// Uploads the velocities of `view`'s worlds if they changed since the
    /// last upload, with room for `extra` rows after them (the GPU worlds'
    /// velocities, gathered there on the GPU); returns whether the velocity
    /// buffer was replaced (the splat's bind groups then are stale).
    pub(crate) fn upload(&mut self, gpu: &Gpu, view: &FrameView<'_>, extra: usize) -> bool {
        let mut replaced = false;
        let n: usize = view.worlds().map(|w| w.world.len()).sum();
        if ((n + extra) * std::mem::size_of::<Velocity>()) as u64 > self.velocities.size() {
            self.velocities =
                record_buffer::<Velocity>(&gpu.device, "tickwork velocities", (n + extra).next_power_of_two());
            self.uploaded.clear();
            replaced = true;
        }
        self.upload_key.clear();
        self.upload_key
            .extend(view.worlds().map(|w| (w.world.id(), w.world.revision())));
        if self.uploaded != self.upload_key {
            std::mem::swap(&mut self.uploaded, &mut self.upload_key);
            if n > 0 {
                write_records(
                    gpu,
                    view,
                    n,
                    &mut self.scratch,
                    &self.velocities,
                    velocity_block,
                    |_, _| {},
                );
            }
        }
        replaced
    }

    /// The velocity buffer, for the splat's Hermite pass.
    pub(crate) fn velocities(&self) -> &wgpu::Buffer {
        &self.velocities
    }

    /// Draws `count` particles of `instances` by `vs_hermite` (after
    /// [`upload`](Self::upload)), with the particles' `globals` group.
    pub(crate) fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        globals: &wgpu::BindGroup,
        instances: &wgpu::Buffer,
        range: std::ops::Range<u32>,
    ) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, globals, &[]);
        pass.set_vertex_buffer(0, instances.slice(..));
        pass.set_vertex_buffer(1, self.velocities.slice(..));
        pass.draw(0..4, range);
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
    use crate::render::records::Instance;

    #[test]
    fn lerp_keeps_its_32_byte_record_and_hermite_adds_12() {
        assert_eq!(std::mem::size_of::<Instance>(), 32);
        assert_eq!(std::mem::size_of::<Velocity>(), 12);
    }
}

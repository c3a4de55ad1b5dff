//! The per-particle records the renderer uploads: one 32-byte [`Instance`]
//! per particle (previous position, radius, current position, colour),
//! repacked from the world's per-axis blocks, in parallel for large worlds,
//! into a buffer the quads read as instance vertices (and the splat as
//! storage). Hermite's velocities go through the same upload
//! (`hermite.rs`).

use bytemuck::{Pod, Zeroable};
use rayon::prelude::{IndexedParallelIterator, ParallelIterator, ParallelSliceMut};

use super::Gpu;
use super::frame_view::FrameView;

/// One particle as the shader reads it (32 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub(crate) struct Instance {
    previous: [f32; 3],
    radius: f32,
    current: [f32; 3],
    colour: u32,
}

/// Rows per parallel upload job; below two of them the upload is serial.
const UPLOAD_CHUNK: usize = 32 * 1024;

/// The shader records of the block of four rows from row `first`: the
/// per-axis blocks are read as arrays, so the repack from blocks to records
/// is plain moves.
pub(crate) fn instance_block(particles: &crate::world::Particles, first: usize, records: &mut [Instance]) {
    let block = first / 4;
    let axes = |v: &tickwork_integrators::Vec3x4| [v.x.to_array(), v.y.to_array(), v.z.to_array()];
    let (p, c) = (
        axes(&particles.previous_position.blocks()[block]),
        axes(&particles.position.blocks()[block]),
    );
    for (k, record) in records.iter_mut().enumerate() {
        let i = first + k;
        *record = Instance {
            previous: [p[0][k], p[1][k], p[2][k]],
            radius: particles.radius[i],
            current: [c[0][k], c[1][k], c[2][k]],
            colour: u32::from_le_bytes(particles.colour[i]),
        };
    }
}

/// Hidden particles ([`World::set_visible`](crate::World::set_visible)),
/// and those of a world drawn as sprites, drawn fully transparent: in
/// place, so the records stay row-aligned with Hermite's velocities.
pub(crate) fn hide_instances(shown: &super::frame_view::WorldView<'_>, records: &mut [Instance]) {
    if shown.as_sprites {
        for record in records.iter_mut() {
            record.colour = 0;
        }
        return;
    }
    if let Some(hidden) = shown.world.hidden_rows() {
        for (record, hidden) in records.iter_mut().zip(hidden) {
            if hidden.0 {
                record.colour = 0;
            }
        }
    }
}

/// One record per particle of every world `view` shows, in order, into
/// `scratch` (reused), then into `buffer`: `block(particles, row, records)`
/// fills the records of the block of four rows from `row`, in parallel
/// chunks of [`UPLOAD_CHUNK`] rows for large worlds; `finish(world,
/// records)` then adjusts a world's records. The instance records
/// and Hermite's velocities are uploaded through it.
pub(crate) fn write_records<T: Pod + Default + Send>(
    gpu: &Gpu,
    view: &FrameView<'_>,
    n: usize,
    scratch: &mut Vec<T>,
    buffer: &wgpu::Buffer,
    block: impl Fn(&crate::world::Particles, usize, &mut [T]) + Sync,
    finish: impl Fn(&super::frame_view::WorldView<'_>, &mut [T]),
) {
    scratch.resize(n, T::default());
    let mut offset = 0;
    for shown in view.worlds() {
        let particles = shown.world.particles();
        let out = &mut scratch[offset..offset + particles.len()];
        // `first` is a multiple of 4 (UPLOAD_CHUNK is).
        let fill = |first: usize, out: &mut [T]| {
            for (b, records) in out.chunks_mut(4).enumerate() {
                block(particles, first + 4 * b, records);
            }
        };
        if out.len() >= 2 * UPLOAD_CHUNK {
            out.par_chunks_mut(UPLOAD_CHUNK)
                .enumerate()
                .for_each(|(chunk, out)| fill(chunk * UPLOAD_CHUNK, out));
        } else {
            fill(0, out);
        }
        finish(&shown, out);
        offset += particles.len();
    }
    gpu.queue.write_buffer(buffer, 0, bytemuck::cast_slice(scratch));
}

/// A buffer for `particles` records of type `T` (at least one), written
/// by [`write_records`]: per-instance vertex data for the quads, and a
/// storage buffer for the splat where the device has them (WebGL2 has not).
pub(crate) fn record_buffer<T>(device: &wgpu::Device, label: &str, particles: usize) -> wgpu::Buffer {
    let storage = if device.limits().max_storage_buffers_per_shader_stage > 0 {
        wgpu::BufferUsages::STORAGE
    } else {
        wgpu::BufferUsages::empty()
    };
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: (particles.max(1) * std::mem::size_of::<T>()) as u64,
        usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST | storage,
        mapped_at_creation: false,
    })
}

/// The instance records as the quads' per-instance vertex attributes
/// (`InstanceIn` in particles.wgsl), slot 0.
const INSTANCE_ATTRIBUTES: [wgpu::VertexAttribute; 4] =
    wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32, 2 => Float32x3, 3 => Uint32];

/// Slot 0's layout: one 32-byte [`Instance`] per quad.
pub(crate) fn instance_buffer_layout() -> wgpu::VertexBufferLayout<'static> {
    wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<Instance>() as u64,
        step_mode: wgpu::VertexStepMode::Instance,
        attributes: &INSTANCE_ATTRIBUTES,
    }
}

//! The vertices of lines and triangles (springs, trails, rigid-body boxes,
//! a game's own), few and built on the CPU each frame, and the vertex
//! buffer they go into, grown to a power of two when they do not fit.

use bytemuck::{Pod, Zeroable};

use super::Gpu;

/// One line vertex (16 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub(crate) struct LineVertex {
    pub position: [f32; 3],
    pub colour: [u8; 4],
}

/// Writes `vertices` into `buffer`, growing it to a power of two when they
/// do not fit; returns how many there are.
pub(crate) fn upload_vertices(gpu: &Gpu, vertices: &[LineVertex], buffer: &mut wgpu::Buffer) -> u32 {
    if vertices.is_empty() {
        return 0;
    }
    let bytes: &[u8] = bytemuck::cast_slice(vertices);
    if bytes.len() as u64 > buffer.size() {
        *buffer = vertex_buffer(&gpu.device, vertices.len().next_power_of_two());
    }
    gpu.queue.write_buffer(buffer, 0, bytes);
    vertices.len() as u32
}

/// An empty vertex buffer for `vertices` line vertices (at least one).
pub(crate) fn vertex_buffer(device: &wgpu::Device, vertices: usize) -> wgpu::Buffer {
    vertex_buffer_of::<LineVertex>(device, vertices)
}

/// An empty vertex buffer for `vertices` vertices of type `T` (at least one).
pub(crate) fn vertex_buffer_of<T>(device: &wgpu::Device, vertices: usize) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("tickwork vertices"),
        size: (vertices.max(1) * std::mem::size_of::<T>()) as u64,
        usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

//! Reading a GPU world back: its positions and velocities, into vectors or
//! into the [`World`] it steps for.

use glam::Vec3;

use super::GpuWorld;
use crate::clock::FixedStep;
use crate::device::Gpu;
use crate::gpu_step::error::GpuStepError;
use crate::world::World;

impl GpuWorld {
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
        world.store_rows(&x, &v, &previous);
        if self.behind > 0 {
            world.book_steps(self.behind, last);
            self.behind = 0;
        }
        self.revision = world.revision();
        Ok(())
    }

    /// Copies `buffers` out and waits: their `xyz`, a particle each.
    pub(super) fn read<const N: usize>(
        &self,
        gpu: &Gpu,
        buffers: [&wgpu::Buffer; N],
    ) -> Result<[Vec<Vec3>; N], GpuStepError> {
        let bytes = u64::from(self.n) * 16;
        let parts = map_words(gpu, buffers.map(|buffer| (buffer, 0, bytes)))?;
        Ok(parts.map(|part| {
            part.chunks_exact(16)
                .map(|r| Vec3::new(f32_at(r, 0), f32_at(r, 1), f32_at(r, 2)))
                .collect()
        }))
    }
}

/// Copies each `(buffer, offset, bytes)` out and waits: their bytes. A
/// page cannot wait, and is told so.
pub(super) fn map_words<const N: usize>(
    gpu: &Gpu,
    parts: [(&wgpu::Buffer, u64, u64); N],
) -> Result<[Vec<u8>; N], GpuStepError> {
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
    // Natively the answer comes once the wait (this thread's, or another
    // sharing the device) has run the callback; a page cannot wait (its
    // GPU answers once its script yields), and is told so.
    crate::platform::received_now(&receiver)
        .ok_or_else(|| {
            GpuStepError::ReadBack(
                "the GPU has not answered the read-back (a page cannot wait for one: read a GPU world back natively)"
                    .into(),
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
pub(super) fn f32_at(bytes: &[u8], k: usize) -> f32 {
    bytes
        .get(4 * k..4 * k + 4)
        .and_then(|w| w.try_into().ok())
        .map_or(0.0, f32::from_le_bytes)
}

//! A GPU world's rows following its CPU world's: the world logs each row
//! it swap-removes and adds ([`RowChange`]), this turns a step's log into
//! the moves and new records that leave the GPU's rows in the CPU's order
//! (`engine/shaders/gpu_step/rows.wgsl`), planned in O(changes), applied
//! after the step.
//!
//! Why the CPU plans it: which rows expire is known there without the
//! GPU's state (a lifetime is a birth time and a length), emission is
//! decided there (the world's seeded generator), and planning the CPU's
//! own swap-removes gives the CPU's row order, so a GPU world's checksum
//! can be the CPU's. No prefix sum, no atomics: each move is an
//! independent copy.

use std::collections::HashMap;

use super::dispatch::dispatch;
use super::error::GpuStepError;
use crate::device::{Gpu, bind_buffers, compute_pipeline, compute_storage, entry as buffer_entry, wgsl};
use crate::world::{RowChange, World};

/// Where a row's particle comes from: a row before the changes, or new.
const NEW: u32 = u32::MAX;

/// A new particle's record (`Spawn` in `rows.wgsl`): its state, its
/// previous position, its colour and the row it goes to.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct SpawnRecord {
    position: [f32; 4],
    velocity: [f32; 4],
    previous: [f32; 4],
    colour: u32,
    row: u32,
    _pad: [u32; 2],
}

const _: () = assert!(std::mem::size_of::<SpawnRecord>() == 64);

/// `Rows` in `rows.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct RowParams {
    moves: u32,
    spawns: u32,
    moves_groups_x: u32,
    spawns_groups_x: u32,
    /// The method's history records a particle (0: none).
    history: u32,
    _pad: [u32; 3],
}

/// What a log of row changes does to the rows (reused, step after step).
#[derive(Debug, Default)]
pub(super) struct RowPlan {
    /// Each row the changes touched: the row before them its particle
    /// comes from, or [`NEW`].
    origin: HashMap<u32, u32>,
    /// `(to, from)`: a surviving particle's move, in row order.
    pub moves: Vec<[u32; 2]>,
    /// New particles, in row order.
    pub spawns: Vec<SpawnRecord>,
}

impl RowPlan {
    /// Plans `log`, the changes to `before` rows that left `world`'s rows
    /// as they are now: replays the swap-removes on the touched rows only.
    /// A row's particle only ever moves down (into a removed row) and a
    /// row a particle left is only filled again by a new one, so no move
    /// reads a row another move or new record writes.
    pub fn plan(&mut self, log: &[RowChange], before: u32, world: &World) {
        self.origin.clear();
        self.moves.clear();
        self.spawns.clear();
        let mut len = before;
        for &change in log {
            match change {
                RowChange::Removed(row) => {
                    let Some(last) = len.checked_sub(1) else {
                        continue;
                    };
                    let from = self.origin.remove(&last).unwrap_or(last);
                    if row != last {
                        self.origin.insert(row, from);
                    }
                    len = last;
                }
                RowChange::Added => {
                    self.origin.insert(len, NEW);
                    len += 1;
                }
            }
        }
        let p = world.particles();
        let hidden = world.hidden_rows();
        for (&row, &from) in &self.origin {
            let r = row as usize;
            if row >= len || r >= p.len() {
                continue;
            }
            if from == NEW {
                let (x, x0, v) = (p.position.row(r), p.previous_position.row(r), p.velocity.row(r));
                let shown = hidden.is_none_or(|h| !h[r].0);
                self.spawns.push(SpawnRecord {
                    position: [x.x, x.y, x.z, p.radius[r]],
                    velocity: [v.x, v.y, v.z, p.inverse_mass[r]],
                    previous: [x0.x, x0.y, x0.z, p.radius[r]],
                    colour: if shown { u32::from_le_bytes(p.colour[r]) } else { 0 },
                    row,
                    _pad: [0; 2],
                });
            } else if from != row {
                self.moves.push([row, from]);
            }
        }
        self.moves.sort_unstable();
        self.spawns.sort_unstable_by_key(|s| s.row);
    }
}

impl RowPlan {
    /// The largest radius among the new particles (0 for none).
    pub fn max_radius(&self) -> f32 {
        self.spawns.iter().fold(0.0, |m: f32, s| m.max(s.position[3]))
    }
}

/// The state buffers the row kernels read and write.
pub(super) struct StateBuffers<'a> {
    pub positions: &'a wgpu::Buffer,
    pub velocities: &'a wgpu::Buffer,
    pub previous: &'a wgpu::Buffer,
    pub colours: &'a wgpu::Buffer,
    pub history: &'a wgpu::Buffer,
}

/// The `relocate` and `place` kernels with their buffers.
#[derive(Debug)]
pub(super) struct RowKernel {
    layout: wgpu::BindGroupLayout,
    relocate: wgpu::ComputePipeline,
    place: wgpu::ComputePipeline,
    params: wgpu::Buffer,
    moves: wgpu::Buffer,
    spawns: wgpu::Buffer,
    /// Made for the current state and plan buffers (`None` after either
    /// was replaced).
    bind_group: Option<wgpu::BindGroup>,
}

/// Records a buffer starts with room for.
const START: u64 = 256;

impl RowKernel {
    /// Builds the kernels on `device`.
    pub fn new(device: &wgpu::Device) -> Self {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("tickwork gpu rows"),
            source: wgpu::ShaderSource::Wgsl(wgsl!("gpu_step/rows.wgsl").into()),
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("tickwork gpu rows"),
            entries: &[
                buffer_entry(0, wgpu::ShaderStages::COMPUTE, wgpu::BufferBindingType::Uniform),
                compute_storage(1, false),
                compute_storage(2, false),
                compute_storage(3, false),
                compute_storage(4, false),
                compute_storage(5, true),
                compute_storage(6, true),
                compute_storage(7, false),
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("tickwork gpu rows"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = |entry_point| compute_pipeline(device, &pipeline_layout, &module, entry_point, &[]);
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("tickwork gpu rows params"),
            size: std::mem::size_of::<RowParams>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Self {
            relocate: pipeline("relocate"),
            place: pipeline("place"),
            layout,
            params,
            moves: plan_buffer(device, "tickwork gpu rows moves", START * 8),
            spawns: plan_buffer(device, "tickwork gpu rows spawns", START * 64),
            bind_group: None,
        }
    }

    /// Forgets the bind group (the state buffers were replaced).
    pub fn unbind(&mut self) {
        self.bind_group = None;
    }

    /// Records `plan` into `encoder`: its moves, then its new records, on
    /// `state` (and its history records where the method keeps them). Its records are written to the queue now, so the encoder
    /// must be submitted before the next call.
    ///
    /// # Errors
    /// [`GpuStepError::Limit`] for more changes than one dispatch takes.
    pub fn encode(
        &mut self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        plan: &RowPlan,
        state: &StateBuffers<'_>,
        history: u32,
    ) -> Result<(), GpuStepError> {
        if plan.moves.is_empty() && plan.spawns.is_empty() {
            return Ok(());
        }
        let limits = gpu.device.limits();
        let (moves, moves_groups) = dispatch(plan.moves.len(), 1, &limits)?;
        let (spawns, spawns_groups) = dispatch(plan.spawns.len(), 1, &limits)?;
        let device = &gpu.device;
        for (buffer, bytes, label) in [
            (&mut self.moves, plan.moves.len() as u64 * 8, "tickwork gpu rows moves"),
            (
                &mut self.spawns,
                plan.spawns.len() as u64 * 64,
                "tickwork gpu rows spawns",
            ),
        ] {
            if bytes > buffer.size() {
                *buffer = plan_buffer(device, label, bytes.max(2 * buffer.size()));
                self.bind_group = None;
            }
        }
        let params = RowParams {
            moves,
            spawns,
            moves_groups_x: moves_groups.0,
            spawns_groups_x: spawns_groups.0,
            history,
            _pad: [0; 3],
        };
        gpu.queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        if !plan.moves.is_empty() {
            gpu.queue
                .write_buffer(&self.moves, 0, bytemuck::cast_slice(&plan.moves));
        }
        if !plan.spawns.is_empty() {
            gpu.queue
                .write_buffer(&self.spawns, 0, bytemuck::cast_slice(&plan.spawns));
        }
        let bind_group = self.bind_group.get_or_insert_with(|| {
            let buffers = [
                &self.params,
                state.positions,
                state.velocities,
                state.previous,
                state.colours,
                &self.moves,
                &self.spawns,
                state.history,
            ];
            bind_buffers(device, &self.layout, &buffers)
        });
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("tickwork gpu rows"),
            timestamp_writes: None,
        });
        pass.set_bind_group(0, &*bind_group, &[]);
        // Every move before any new record (a dispatch's writes are seen
        // by the next).
        if moves > 0 {
            pass.set_pipeline(&self.relocate);
            pass.dispatch_workgroups(moves_groups.0, moves_groups.1, 1);
        }
        if spawns > 0 {
            pass.set_pipeline(&self.place);
            pass.dispatch_workgroups(spawns_groups.0, spawns_groups.1, 1);
        }
        Ok(())
    }
}

/// A storage buffer of `bytes` the queue writes.
fn plan_buffer(device: &wgpu::Device, label: &str, bytes: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::Particle;
    use crate::world::WorldConfig;

    /// The plan of a world's log, checked against the world itself: row
    /// by row, each row's particle is where the plan says.
    #[test]
    fn a_plan_leaves_the_rows_in_the_worlds_order() {
        let mut world = World::new(WorldConfig::default()).unwrap();
        let spawn = |world: &mut World, x: f32| {
            world
                .spawn(Particle {
                    position: glam::Vec3::new(x, 0.0, 0.0),
                    ..Particle::default()
                })
                .unwrap()
        };
        let entities: Vec<_> = (0..8).map(|k| spawn(&mut world, k as f32)).collect();
        world.row_log = Some(Vec::new());
        // Remove rows 1, 7 (the last), 3; add two; remove one of the new.
        world.despawn(entities[1]).unwrap();
        world.despawn(entities[7]).unwrap();
        world.despawn(entities[3]).unwrap();
        let a = spawn(&mut world, 100.0);
        spawn(&mut world, 101.0);
        world.despawn(a).unwrap();
        let log = world.row_log.take().unwrap();
        let mut plan = RowPlan::default();
        plan.plan(&log, 8, &world);
        // The GPU's rows before: x = 0..8. Apply the plan.
        let mut rows: Vec<f32> = (0..8).map(|k| k as f32).collect();
        rows.resize(world.len().max(8), f32::NAN);
        let before = rows.clone();
        for [to, from] in &plan.moves {
            rows[*to as usize] = before[*from as usize];
        }
        for s in &plan.spawns {
            rows[s.row as usize] = s.position[0];
        }
        rows.truncate(world.len());
        let cpu: Vec<f32> = world.particles().position.iter().map(|x| x.x).collect();
        assert_eq!(rows, cpu);
        assert_eq!(cpu, [0.0, 6.0, 2.0, 5.0, 4.0, 101.0]);
        assert_eq!(plan.moves, [[1, 6], [3, 5]]);
        assert_eq!(plan.spawns.len(), 1);
    }
}

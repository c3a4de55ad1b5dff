//! The fixed step on the GPU against the adapter's own copy of the same
//! bytes: semi-implicit Euler and RK4 (gravity, linear drag, a floor whose
//! contacts are found at the end of the step; semi-implicit Euler also with
//! them found inside it, the default) at
//! 100k, 1M and 10M particles (`TICKWORK_GPU_BENCH_SIZES=100000,1000000`
//! to choose),
//! each step reading 32 bytes a particle and writing 32, and in the same
//! run `copy_buffer_to_buffer` of the state's 32 bytes a particle (read
//! once, written once). Both report their throughput in bytes moved a
//! second, so the step's bandwidth as a fraction of the copy's is the
//! ratio of the two (`scripts/gpu-bench` prints it). Then the all-pairs
//! n-body kernel (workgroup tiles of 256) at 4k, 16k and 64k particles
//! (`TICKWORK_GPU_NBODY_SIZES`) under semi-implicit Euler and RK4, its
//! throughput in pair interactions a second (n^2 an evaluation: each
//! particle sums every other; RK4 evaluates four times a step). Then the cost of a
//! rollback-style snapshot of a GPU world at 1M particles
//! (`TICKWORK_GPU_READBACK_SIZES`): its state read back into its world and
//! the world's checksum, against the CPU world's own snapshot and checksum
//! in the same run. On lavapipe these are CPU figures and show only that
//! it runs.

use std::time::{Duration, Instant};

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec3;
use tickwork_engine::colliders::{ContactRule, Material, Plane};
use tickwork_engine::forces::{Gravity, LinearDrag, NBody};
use tickwork_engine::gpu_step::GpuWorld;
use tickwork_engine::render::Gpu;
use tickwork_engine::{Particle, World, WorldConfig};

/// A world of `n` particles in a 100 m cube, falling onto a floor whose
/// contacts are found by `rule`.
fn world(n: usize, rule: ContactRule) -> World {
    let mut world = World::new(WorldConfig {
        integrator: "semi_implicit_euler".into(),
        max_particles: n.max(1),
        ..WorldConfig::default()
    })
    .expect("a world");
    world.add_force(Gravity::EARTH);
    world.add_force(LinearDrag { rate: 0.1 });
    world.add_collider(Plane {
        contact: rule,
        ..Plane::floor(
            0.0,
            Material {
                restitution: 0.5,
                friction: 0.0,
            },
        )
    });
    for k in 0..n {
        let h = (k as u32).wrapping_mul(2_654_435_761) as f32 / u32::MAX as f32;
        world
            .spawn(Particle {
                position: Vec3::new((k % 1000) as f32 * 0.1, 1.0 + 100.0 * h, (k / 1000 % 1000) as f32 * 0.1),
                velocity: Vec3::new(1.0, 0.0, -1.0),
                radius: 0.02,
                ..Particle::default()
            })
            .expect("a particle");
    }
    world
}

/// Waits until the GPU has done all it was given.
fn finish(gpu: &Gpu) {
    gpu.device
        .poll(wgpu::PollType::wait_indefinitely())
        .expect("the GPU finishes");
}

/// The time `iters` steps take, from a GPU that has finished all it was
/// given to one that has finished them.
fn timed_steps(gpu: &Gpu, world: &mut GpuWorld, iters: u64) -> Duration {
    finish(gpu);
    let start = Instant::now();
    world
        .step(gpu, 1.0 / 60.0, u32::try_from(iters).unwrap_or(u32::MAX))
        .expect("steps");
    finish(gpu);
    start.elapsed()
}

fn sizes() -> Vec<usize> {
    std::env::var("TICKWORK_GPU_BENCH_SIZES").map_or_else(
        |_| vec![100_000, 1_000_000, 10_000_000],
        |list| list.split(',').filter_map(|s| s.trim().parse().ok()).collect(),
    )
}

fn gpu_step(c: &mut Criterion) {
    let gpu = Gpu::headless().unwrap_or_else(|e| panic!("the GPU step bench needs an adapter: {e}"));
    println!("adapter: {:?}", gpu.adapter.get_info());
    for n in sizes() {
        let cpu = world(n, ContactRule::EndOfStep);
        let mut on_gpu = match GpuWorld::new(&gpu, &cpu) {
            Ok(world) => world,
            Err(error) => {
                println!("gpu_step_{n}: not run: {error}");
                continue;
            }
        };
        let mut rk4 = cpu;
        rk4.set_integrator("rk4").expect("rk4");
        let mut on_gpu_rk4 = GpuWorld::new(&gpu, &rk4).expect("the same world under RK4");
        drop(rk4);
        // The default rule, contacts inside the step (`in_step.wgsl`).
        let mut on_gpu_in_step = GpuWorld::new(&gpu, &world(n, ContactRule::InStep)).expect("the world in step");
        let mut group = c.benchmark_group(format!("gpu_step_{n}"));
        group.throughput(Throughput::Bytes(on_gpu.bytes_per_step()));
        group.sample_size(10);
        group.warm_up_time(Duration::from_millis(500));
        group.measurement_time(Duration::from_secs(3));
        group.bench_function("semi_implicit_euler", |b| {
            b.iter_custom(|iters| timed_steps(&gpu, &mut on_gpu, iters));
        });
        group.bench_function("semi_implicit_euler_in_step", |b| {
            b.iter_custom(|iters| timed_steps(&gpu, &mut on_gpu_in_step, iters));
        });
        drop(on_gpu_in_step);
        group.bench_function("rk4", |b| {
            b.iter_custom(|iters| timed_steps(&gpu, &mut on_gpu_rk4, iters));
        });
        drop(on_gpu_rk4);
        // The same bytes copied: both state buffers into a scratch pair.
        let (positions, velocities) = on_gpu.buffers();
        let bytes = positions.size();
        let scratch = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("copy target"),
            size: 2 * bytes,
            usage: wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        group.bench_function("copy_same_bytes", |b| {
            b.iter_custom(|iters| {
                finish(&gpu);
                let start = Instant::now();
                let mut encoder = gpu.device.create_command_encoder(&Default::default());
                for _ in 0..iters {
                    encoder.copy_buffer_to_buffer(positions, 0, &scratch, 0, bytes);
                    encoder.copy_buffer_to_buffer(velocities, 0, &scratch, bytes, bytes);
                }
                gpu.queue.submit([encoder.finish()]);
                finish(&gpu);
                start.elapsed()
            });
        });
        group.finish();
    }
}

/// `n` particles of a 100 m cube pulling on one another, `method`
/// stepping them.
fn cloud(n: usize, method: &str) -> World {
    let mut world = World::new(WorldConfig {
        integrator: method.into(),
        max_particles: n.max(1),
        ..WorldConfig::default()
    })
    .expect("a world");
    world.add_force(NBody::new(1.0, 0.5));
    for k in 0..n {
        let h = |s: u32| (k as u32).wrapping_mul(s) as f32 / u32::MAX as f32;
        world
            .spawn(Particle {
                position: 100.0 * Vec3::new(h(2_654_435_761), h(2_246_822_519), h(3_266_489_917)),
                radius: 0.1,
                ..Particle::default()
            })
            .expect("a particle");
    }
    world
}

fn gpu_nbody(c: &mut Criterion) {
    let gpu = Gpu::headless().unwrap_or_else(|e| panic!("the GPU step bench needs an adapter: {e}"));
    let sizes: Vec<usize> = std::env::var("TICKWORK_GPU_NBODY_SIZES").map_or_else(
        |_| vec![4_096, 16_384, 65_536],
        |list| list.split(',').filter_map(|s| s.trim().parse().ok()).collect(),
    );
    // Semi-implicit Euler sums once a step; RK4 four times, at four
    // stages' trial positions (a round of probe and sums each).
    for (n, (method, evaluations)) in sizes
        .iter()
        .flat_map(|&n| [("semi_implicit_euler", 1), ("rk4", 4)].map(|m| (n, m)))
    {
        let name = if method == "rk4" {
            format!("gpu_nbody_rk4_{n}")
        } else {
            format!("gpu_nbody_{n}")
        };
        let mut on_gpu = match GpuWorld::new(&gpu, &cloud(n, method)) {
            Ok(world) => world,
            Err(error) => {
                println!("{name}: not run: {error}");
                continue;
            }
        };
        let mut group = c.benchmark_group(name);
        group.throughput(Throughput::Elements(evaluations * (n as u64) * (n as u64)));
        group.sample_size(10);
        group.warm_up_time(Duration::from_millis(500));
        group.measurement_time(Duration::from_secs(3));
        group.bench_function("pairs", |b| {
            b.iter_custom(|iters| timed_steps(&gpu, &mut on_gpu, iters));
        });
        group.finish();
    }
}

/// A rollback's snapshot of a GPU world: the state read back into the
/// world (`store_into`: 48 bytes a particle copied out and a wait) and the
/// world's checksum; beside it the CPU world's snapshot and checksum.
fn gpu_readback(c: &mut Criterion) {
    let gpu = Gpu::headless().unwrap_or_else(|e| panic!("the GPU step bench needs an adapter: {e}"));
    let sizes: Vec<usize> = std::env::var("TICKWORK_GPU_READBACK_SIZES").map_or_else(
        |_| vec![1_000_000],
        |list| list.split(',').filter_map(|s| s.trim().parse().ok()).collect(),
    );
    for n in sizes {
        let mut cpu = world(n, ContactRule::EndOfStep);
        let mut on_gpu = match GpuWorld::new(&gpu, &cpu) {
            Ok(world) => world,
            Err(error) => {
                println!("gpu_readback_{n}: not run: {error}");
                continue;
            }
        };
        let step = tickwork_engine::FixedStep {
            tick: 0,
            time: 0.0,
            dt: 1.0 / 60.0,
        };
        on_gpu.advance(&gpu, &mut cpu, step).expect("a step");
        let mut group = c.benchmark_group(format!("gpu_readback_{n}"));
        group.sample_size(10);
        group.warm_up_time(Duration::from_millis(500));
        group.measurement_time(Duration::from_secs(3));
        group.bench_function("store_and_checksum", |b| {
            b.iter(|| {
                on_gpu.store_into(&gpu, &mut cpu, step).expect("stored");
                cpu.state_hash()
            });
        });
        let mut snapshot = cpu.snapshot();
        group.bench_function("cpu_snapshot_and_checksum", |b| {
            b.iter(|| {
                cpu.snapshot_into(&mut snapshot);
                cpu.state_hash()
            });
        });
        group.finish();
    }
}

criterion_group!(benches, gpu_step, gpu_nbody, gpu_readback);
criterion_main!(benches);

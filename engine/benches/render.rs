//! Off-screen frame time at 1280x720 for 1k, 10k, 100k and 1M particles,
//! on whatever adapter is present (lavapipe on CI's kind of machine):
//! drawing alone (the world unchanged since the last frame: no upload),
//! the same with one quad per particle (the path below the splat threshold),
//! drawing after a step (upload of the changed columns), and with the
//! read-back of the image.
//!
//! Run: `cargo bench -p tickwork-engine --bench render`, then
//! `scripts/bench-report render` for the README table.

use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use glam::{Vec2, Vec3};
use rand::{RngExt, SeedableRng};
use tickwork_engine::render::{Camera, FrameView, Gpu, OFFSCREEN_FORMAT, OffscreenTarget, Renderer, RendererConfig};
use tickwork_engine::{Particle, World};

const WIDTH: u32 = 1280;
const HEIGHT: u32 = 720;

/// `n` particles of radius 2 cm (1.6 px) spread over a 16 m x 9 m view,
/// moving, in random colours.
fn cloud(n: usize) -> World {
    let mut rng = rand_pcg::Pcg32::seed_from_u64(7);
    let mut world = World::default();
    for _ in 0..n {
        world
            .spawn(Particle {
                position: Vec3::new(rng.random_range(-8.0..8.0), rng.random_range(-4.5..4.5), 0.0),
                velocity: Vec3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), 0.0),
                radius: 0.02,
                colour: [rng.random(), rng.random(), rng.random(), 255],
                ..Particle::default()
            })
            .expect("spawn");
    }
    world
}

fn wait(gpu: &Gpu) {
    gpu.device.poll(wgpu::PollType::wait_indefinitely()).expect("poll");
}

fn frames(c: &mut Criterion) {
    let gpu = Gpu::headless().unwrap_or_else(|e| panic!("{e}"));
    eprintln!("adapter: {}", gpu.describe());
    let camera = Camera::TwoD {
        center: Vec2::ZERO,
        height: 9.0,
    };
    let target = OffscreenTarget::new(&gpu, WIDTH, HEIGHT, 4).expect("target");
    let mut renderer = Renderer::new(&gpu, OFFSCREEN_FORMAT, RendererConfig::default()).expect("renderer");
    // The same frames with one anti-aliased quad per particle (MSAA 4x), the
    // path used below the splat threshold: the peer measured in the same run.
    let quads_config = RendererConfig {
        splat_threshold: Some(usize::MAX),
        ..RendererConfig::default()
    };
    let mut quads = Renderer::new(&gpu, OFFSCREEN_FORMAT, quads_config).expect("renderer");
    for n in [1_000, 10_000, 100_000, 1_000_000] {
        let mut world = cloud(n);
        let mut group = c.benchmark_group(format!("render_{n}"));
        group.sample_size(10);
        group.warm_up_time(Duration::from_secs(1));
        group.measurement_time(Duration::from_secs(if n >= 1_000_000 { 12 } else { 4 }));
        group.bench_function("draw", |b| {
            b.iter(|| {
                target
                    .draw(&gpu, &mut renderer, &FrameView::new(&world, 0.5, camera), false)
                    .expect("draw");
                wait(&gpu);
            });
        });
        if n <= 100_000 {
            group.bench_function("draw_quads", |b| {
                b.iter(|| {
                    target
                        .draw(&gpu, &mut quads, &FrameView::new(&world, 0.5, camera), false)
                        .expect("draw");
                    wait(&gpu);
                });
            });
        }
        group.bench_function("upload_draw", |b| {
            b.iter(|| {
                world.particles_mut(); // counts as a change: the next frame uploads
                target
                    .draw(&gpu, &mut renderer, &FrameView::new(&world, 0.5, camera), false)
                    .expect("draw");
                wait(&gpu);
            });
        });
        group.bench_function("upload_draw_readback", |b| {
            b.iter(|| {
                world.particles_mut();
                target
                    .render(&gpu, &mut renderer, &FrameView::new(&world, 0.5, camera))
                    .expect("frame")
            });
        });
        group.finish();
    }
}

criterion_group!(benches, frames);
criterion_main!(benches);

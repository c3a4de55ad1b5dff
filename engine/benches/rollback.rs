//! The rollback budget: what one GGRS frame costs a game of N particles.
//! GGRS's worst frame at a prediction window of 8 is about 1 load + 9
//! advances + 9 saves (each with a checksum) inside a 16.7 ms frame; this
//! measures each part on a falling-particle game (gravity, drag, a floor,
//! semi-implicit Euler), saving into reused buffers as the sync test does.
//!
//! Run: `cargo bench -p tickwork-engine --features netcode --bench
//! rollback`; criterion's medians come first, then a table of the same
//! parts timed again in one pass (medians of 31 runs each, interleaved),
//! with the worst frame `load + 9 (step + save + checksum)`.

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{Criterion, criterion_group, criterion_main};
use glam::Vec3;
use tickwork_engine::app::{Game, GameError, GameSession, SessionOptions, Settings, Stage};
use tickwork_engine::input::TickInput;
use tickwork_engine::{Gravity, LinearDrag, Material, Particle, Plane, World};

/// `n` particles on a lattice falling onto a floor.
#[derive(Clone)]
struct Rain(usize);

impl Game for Rain {
    fn title(&self) -> &str {
        "rain"
    }

    fn setup(&mut self, stage: &mut Stage, _: &Settings) -> Result<(), GameError> {
        let mut world = World::default();
        world.add_force(Gravity::EARTH);
        world.add_force(LinearDrag { rate: 0.1 });
        world.add_collider(Plane::floor(
            0.0,
            Material {
                restitution: 0.8,
                friction: 0.0,
            },
        ));
        for i in 0..self.0 {
            let (a, b) = ((i % 317) as f32 * 0.05, (i / 317) as f32 * 0.05);
            world.spawn(Particle {
                position: Vec3::new(a, 1.0 + b, 0.0),
                ..Particle::default()
            })?;
        }
        stage.add_world("rain", world);
        Ok(())
    }
}

fn budget(c: &mut Criterion) {
    let input = TickInput::default();
    for n in [10_000, 70_000, 100_000] {
        let mut session = GameSession::new(Rain(n), SessionOptions::default()).expect("a session");
        let mut group = c.benchmark_group(format!("rollback_{n}"));
        group.sample_size(20);
        group.warm_up_time(Duration::from_millis(300));
        group.measurement_time(Duration::from_secs(2));
        let mut saved = session.save_tick();
        let mut tick = 0;
        group.bench_function("step", |b| {
            b.iter(|| {
                session.step_tick(tick, core::slice::from_ref(&input)).expect("steps");
                tick += 1;
            });
        });
        group.bench_function("save_into", |b| {
            b.iter(|| session.save_tick_into(black_box(&mut saved)))
        });
        group.bench_function("load", |b| {
            b.iter(|| session.load_tick(black_box(&saved)).expect("loads"))
        });
        group.bench_function("checksum", |b| b.iter(|| black_box(&session).checksum()));
        group.finish();
    }
}

/// The median of 31 timings of `f`, in milliseconds.
fn median_ms(mut f: impl FnMut()) -> f64 {
    let mut times: Vec<f64> = (0..31)
        .map(|_| {
            let start = Instant::now();
            f();
            start.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

/// Prints the budget table: N, step, save, load, checksum, worst frame.
fn table(_: &mut Criterion) {
    let input = TickInput::default();
    println!("\n| particles | step | save (into reused buffers) | load | checksum | worst frame |");
    println!("|---|---|---|---|---|---|");
    for n in [10_000, 70_000, 100_000] {
        let mut session = GameSession::new(Rain(n), SessionOptions::default()).expect("a session");
        let mut saved = session.save_tick();
        let mut tick = 0;
        let step = median_ms(|| {
            session.step_tick(tick, core::slice::from_ref(&input)).expect("steps");
            tick += 1;
        });
        let save = median_ms(|| session.save_tick_into(black_box(&mut saved)));
        let load = median_ms(|| session.load_tick(black_box(&saved)).expect("loads"));
        let checksum = median_ms(|| {
            black_box(black_box(&session).checksum());
        });
        let worst = load + 9.0 * (step + save + checksum);
        println!(
            "| {n} | {step:.3} ms | {save:.3} ms | {load:.3} ms | {checksum:.3} ms | {worst:.1} ms{} |",
            if worst < 1000.0 / 60.0 { "" } else { " (over 16.7 ms)" }
        );
    }
}

criterion_group!(benches, budget, table);
criterion_main!(benches);

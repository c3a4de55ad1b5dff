//! One step of every method on f32 `Vec3A` particles under gravity plus linear
//! drag, at 1k, 100k and 1M particles, beside a plain copy of the same state
//! bytes (positions and velocities) and a hand-written semi-implicit Euler
//! loop, measured in the same run, so each method can be stated as a
//! fraction of the memory-bandwidth limit and as a cost against the loop a
//! user would write by hand.
//!
//! Run: `cargo bench -p tickwork-integrators --bench methods`, then
//! `scripts/bench-report` for the README table.

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec3A;
use tickwork_integrators::{METHODS, System, build};

/// Gravity plus linear drag, declared so that exponential Euler treats the drag
/// exactly and pointwise so that explicit methods step it in chunks.
struct GravityAndDrag;

impl System<Vec3A> for GravityAndDrag {
    #[inline]
    fn acceleration(&mut self, _t: f32, _x: &[Vec3A], v: &[Vec3A], out: &mut [Vec3A]) {
        let g = Vec3A::new(0.0, -9.81, 0.0);
        for (a, v) in out.iter_mut().zip(v) {
            *a = g - *v * 0.1;
        }
    }
    fn linear_drag(&self) -> f32 {
        0.1
    }
    fn is_pointwise(&self) -> bool {
        true
    }
}

fn state(n: usize) -> (Vec<Vec3A>, Vec<Vec3A>) {
    let x = (0..n)
        .map(|i| Vec3A::new((i % 1000) as f32, 10.0 + (i / 1000) as f32, 0.0))
        .collect();
    let v = (0..n).map(|i| Vec3A::new(1.0, (i % 7) as f32, -0.5)).collect();
    (x, v)
}

/// The fixed step of every case: 60 Hz.
const DT: f32 = 1.0 / 60.0;

/// Times `iterations` calls of `step(run, t)` at game time `t`, measuring
/// the steady state. Every 10 s of game time the run restarts from the
/// initial state (`restart`, then four warming steps, untimed): drag would
/// otherwise decay velocities into f32 subnormals over millions of steps,
/// which no game runs and which is 100x slower on every method.
fn steady<R>(
    iterations: u64,
    t: &mut f32,
    run: &mut R,
    mut restart: impl FnMut(&mut R),
    mut step: impl FnMut(&mut R, f32),
) -> Duration {
    let mut measured = Duration::ZERO;
    let mut remaining = iterations;
    while remaining > 0 {
        if *t >= 10.0 || *t == 0.0 {
            restart(run);
            *t = 0.0;
            // Warm history and caches.
            for _ in 0..4 {
                step(run, *t);
                *t += DT;
            }
        }
        let chunk = remaining.min(((10.0 - *t) / DT) as u64 + 1);
        let start = Instant::now();
        for _ in 0..chunk {
            step(run, *t);
            *t += DT;
        }
        measured += start.elapsed();
        remaining -= chunk;
    }
    measured
}

fn methods(c: &mut Criterion) {
    for n in [1_000usize, 100_000, 1_000_000] {
        let mut group = c.benchmark_group(format!("step/{n}"));
        group.throughput(Throughput::Elements(n as u64));
        if n >= 100_000 {
            group.sample_size(10);
            group.warm_up_time(Duration::from_millis(500));
            group.measurement_time(Duration::from_secs(2));
        }
        // Baselines over the same bytes (positions and velocities): a copy
        // into a second buffer, and one in-place read-modify-write pass, the
        // least traffic an in-place step can have.
        let (x, v) = state(n);
        let source: Vec<Vec3A> = x.iter().chain(&v).copied().collect();
        let mut destination = vec![Vec3A::ZERO; 2 * n];
        group.bench_function("baseline_copy", |b| {
            b.iter(|| destination.copy_from_slice(black_box(&source)));
        });
        let mut in_place = source.clone();
        let one = black_box(1.0f32);
        group.bench_function("baseline_in_place", |b| {
            b.iter(|| {
                for value in &mut in_place {
                    *value *= one;
                }
                black_box(&in_place);
            });
        });
        // What a user would write instead of calling a method: semi-implicit
        // Euler by hand over the same columns and forces, `v += (g - b v) h;
        // x += v h` in one loop (the peers' loop; bench/peers compares whole
        // engine steps).
        let (start_x, start_v) = state(n);
        let (mut hand, mut t) = ((start_x.clone(), start_v.clone()), 0.0f32);
        group.bench_function("hand_semi_implicit_euler", |b| {
            let (g, h) = (Vec3A::new(0.0, -9.81, 0.0), DT);
            b.iter_custom(|iterations| {
                steady(
                    iterations,
                    &mut t,
                    &mut hand,
                    |(x, v)| {
                        x.copy_from_slice(&start_x);
                        v.copy_from_slice(&start_v);
                    },
                    |(x, v), _| {
                        for (x, v) in x.iter_mut().zip(v.iter_mut()) {
                            *v += (g - *v * 0.1) * h;
                            *x += *v * h;
                        }
                    },
                )
            });
        });
        for info in METHODS {
            let method = build::<Vec3A>(info.name).expect("registered");
            let (mut run, mut t) = ((start_x.clone(), start_v.clone(), method), 0.0f32);
            group.bench_with_input(BenchmarkId::from_parameter(info.name), &n, |b, _| {
                b.iter_custom(|iterations| {
                    steady(
                        iterations,
                        &mut t,
                        &mut run,
                        |(x, v, method)| {
                            x.copy_from_slice(&start_x);
                            v.copy_from_slice(&start_v);
                            method.reset();
                        },
                        |(x, v, method), t| {
                            method.step(t, DT, x, v, &mut GravityAndDrag).expect("step");
                        },
                    )
                });
            });
        }
        group.finish();
    }
}

criterion_group!(benches, methods);
criterion_main!(benches);

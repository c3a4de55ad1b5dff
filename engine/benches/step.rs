//! A full fixed step of the engine (forces, integration, a ground plane,
//! ageing, bookkeeping) at 1k, 100k and 1M particles, on one thread and on
//! rayon's threads, beside a memory-bandwidth baseline over the same bytes
//! and a hand-written loop of the same physics (what a user would write
//! instead), measured in the same run; 10k particles with the collision
//! grid, of one size and with one big ball among them; and 100k particles
//! resting on a floor for minutes, whose drag-decayed velocities are
//! subnormal numbers, against the hand loop on the same state; and the two
//! contact rules (end of step, in step) on 100k particles falling, resting
//! and bouncing (restitution 0.9), in the same run.
//!
//! Run: `cargo bench -p tickwork-engine --bench step`, then
//! `scripts/bench-report engine` for the README table.
// Reference values and set-ups computed natively (never in a page): the
// platform's own functions are fine here (clippy.toml bans them in the engine).
#![allow(clippy::disallowed_methods)]

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::{Vec3, Vec3A};
use rayon::ThreadPool;
use tickwork_engine::{
    ContactRule, FixedStep, Gravity, LinearDrag, Material, Particle, Plane, SphereCollisions, World, WorldConfig,
};

/// Particles on a lattice above a floor, falling, under gravity and drag.
fn rain(n: usize, integrator: &str, collisions: bool) -> World {
    rain_with(n, integrator, collisions, WorldConfig::default().parallel_threshold)
}

/// An empty world under gravity and linear drag (0.1/s) over a floor of
/// restitution 0.5 and Coulomb `friction`, found at the end of the step:
/// the rule the peers' loops and the hand loop share (the default rule,
/// in the step, is timed against it by `engine_contact_rule_*`).
fn floor_world(config: WorldConfig, friction: f32) -> World {
    let mut w = World::new(config).expect("registered");
    w.add_force(Gravity::EARTH);
    w.add_force(LinearDrag { rate: 0.1 });
    w.add_collider(Plane {
        contact: ContactRule::EndOfStep,
        ..Plane::floor(
            0.0,
            Material {
                restitution: 0.5,
                friction,
            },
        )
    });
    w
}

/// [`rain`] with lanes from `parallel_threshold` particles.
fn rain_with(n: usize, integrator: &str, collisions: bool, parallel_threshold: usize) -> World {
    let config = WorldConfig {
        integrator: integrator.into(),
        parallel_threshold,
        ..WorldConfig::default()
    };
    let mut w = floor_world(config, 0.1);
    let side = (n as f64).cbrt().ceil() as usize;
    let spacing = if collisions { 0.05 } else { 0.02 };
    for i in 0..n {
        let (a, b, c) = (i % side, (i / side) % side, i / (side * side));
        let p = Particle {
            position: Vec3::new(a as f32, 0.5 + c as f32, b as f32) * spacing,
            velocity: Vec3::new(((i % 13) as f32 - 6.0) * 0.1, (i % 7) as f32 * 0.2, 0.0),
            radius: 0.02,
            lifetime: Some(1e6),
            ..Particle::default()
        };
        w.spawn(p).expect("valid");
    }
    if collisions {
        w.add_collider(SphereCollisions::new(Material {
            restitution: 0.3,
            friction: 0.0,
        }));
    }
    w
}

/// Steps `iters` times, rebuilding the world (untimed) every 10 s of game
/// time, before velocities under drag decay to subnormal numbers.
/// The loop runs inside the pool, so no step pays for waking a pool thread.
fn timed_steps(pool: &ThreadPool, world: &mut World, make: &(dyn Fn() -> World + Sync), iters: u64) -> Duration {
    pool.install(|| {
        let mut total = Duration::ZERO;
        for _ in 0..iters {
            if world.tick() >= 600 {
                *world = make();
            }
            let step = next_step(world);
            let start = Instant::now();
            world.step(step).expect("step");
            total += start.elapsed();
        }
        total
    })
}

/// The world's next step at 60 Hz.
fn next_step(world: &World) -> FixedStep {
    let dt = 1.0 / 60.0;
    FixedStep {
        tick: world.tick(),
        time: world.tick() as f64 * dt,
        dt,
    }
}

/// One pass over the seven columns the fused step streamed before ages became
/// birth times and chunk facts let point particles skip their masses and
/// radii: position and velocity (read, write), previous position (write),
/// age (read, write), inverse mass, radius, lifetime (read). No physics: the
/// memory floor of that layout, kept so the bench's history stays
/// comparable (today's step streams fewer bytes than this baseline).
struct Columns {
    x: Vec<Vec3A>,
    v: Vec<Vec3A>,
    previous: Vec<Vec3A>,
    age: Vec<f32>,
    inverse_mass: Vec<f32>,
    radius: Vec<f32>,
    lifetime: Vec<f32>,
}

impl Columns {
    fn new(n: usize) -> Self {
        Self {
            x: vec![Vec3A::ONE; n],
            v: vec![Vec3A::X; n],
            previous: vec![Vec3A::ZERO; n],
            age: vec![0.0; n],
            inverse_mass: vec![1.0; n],
            radius: vec![0.02; n],
            lifetime: vec![1e6; n],
        }
    }
}

// One loop on purpose: the baseline touches every byte in a single pass.
#[allow(clippy::manual_memcpy)]
fn touch(x: &mut [Vec3A], v: &mut [Vec3A], p: &mut [Vec3A], age: &mut [f32], w: &[f32], r: &[f32], l: &[f32]) {
    for i in 0..x.len() {
        p[i] = x[i];
        let s = w[i] + r[i] + l[i];
        v[i] *= 0.999_9;
        x[i] += v[i] * s * 1e-9;
        age[i] += 1.0 / 60.0;
    }
}

/// The physics of [`rain`] written by hand over `Vec3A` columns, as a user
/// without an engine would: semi-implicit Euler under gravity and linear
/// drag, the floor contact (projection, restitution, Coulomb friction) and
/// ageing, in one loop.
#[allow(clippy::too_many_arguments)]
fn hand(x: &mut [Vec3A], v: &mut [Vec3A], p: &mut [Vec3A], age: &mut [f32], r: &[f32], e: f32, mu: f32, dt: f32) {
    let g = Vec3A::new(0.0, -9.81, 0.0);
    for i in 0..x.len() {
        p[i] = x[i];
        v[i] += dt * (g - 0.1 * v[i]);
        x[i] += dt * v[i];
        age[i] += dt;
        if x[i].y < r[i] {
            x[i].y = r[i];
            let vn = v[i].y.min(0.0);
            let dvn = -(1.0 + e) * vn;
            let tangential = Vec3A::new(v[i].x, 0.0, v[i].z);
            let speed = tangential.length();
            let keep = if mu * dvn >= speed {
                0.0
            } else {
                1.0 - mu * dvn / speed.max(f32::MIN_POSITIVE)
            };
            v[i] = tangential * keep + Vec3A::new(0.0, v[i].y + dvn, 0.0);
        }
    }
}

/// [`hand`] on `threads` (1 or 2) threads, halves by `rayon::join`.
fn hand_step(threads: usize, c: &mut Columns, e: f32, mu: f32) {
    let dt = 1.0 / 60.0;
    if threads == 1 {
        hand(&mut c.x, &mut c.v, &mut c.previous, &mut c.age, &c.radius, e, mu, dt);
        return;
    }
    let half = c.x.len() / 2;
    let (x0, x1) = c.x.split_at_mut(half);
    let (v0, v1) = c.v.split_at_mut(half);
    let (p0, p1) = c.previous.split_at_mut(half);
    let (a0, a1) = c.age.split_at_mut(half);
    let (r0, r1) = c.radius.split_at(half);
    rayon::join(
        || hand(x0, v0, p0, a0, r0, e, mu, dt),
        || hand(x1, v1, p1, a1, r1, e, mu, dt),
    );
}

/// The hand loop's columns holding `world`'s state (the same start).
fn columns_of(world: &World) -> Columns {
    let p = world.particles();
    Columns {
        x: p.position.iter().collect(),
        v: p.velocity.iter().collect(),
        previous: p.previous_position.iter().collect(),
        age: vec![0.0; p.len()],
        inverse_mass: p.inverse_mass.clone(),
        radius: p.radius.clone(),
        lifetime: p.lifetime.clone(),
    }
}

/// 100k particles resting on a frictionless floor, sliding at `speed`
/// along x: after 15 minutes of drag at 0.1/s, `1e-40` m/s, a subnormal.
fn resting(speed: f32) -> World {
    let mut w = floor_world(WorldConfig::default(), 0.0);
    for i in 0..100_000 {
        w.spawn(Particle {
            position: Vec3::new((i % 316) as f32 * 0.05, 0.02, (i / 316) as f32 * 0.05),
            velocity: Vec3::new(speed, 0.0, 0.0),
            radius: 0.02,
            ..Particle::default()
        })
        .expect("valid");
    }
    w
}

fn baseline(threads: usize, c: &mut Columns) {
    let n = c.x.len();
    if threads == 1 {
        touch(
            &mut c.x,
            &mut c.v,
            &mut c.previous,
            &mut c.age,
            &c.inverse_mass,
            &c.radius,
            &c.lifetime,
        );
        return;
    }
    let half = n / 2;
    let (x0, x1) = c.x.split_at_mut(half);
    let (v0, v1) = c.v.split_at_mut(half);
    let (p0, p1) = c.previous.split_at_mut(half);
    let (a0, a1) = c.age.split_at_mut(half);
    let (w0, w1) = c.inverse_mass.split_at(half);
    let (r0, r1) = c.radius.split_at(half);
    let (l0, l1) = c.lifetime.split_at(half);
    rayon::join(
        || touch(x0, v0, p0, a0, w0, r0, l0),
        || touch(x1, v1, p1, a1, w1, r1, l1),
    );
}

fn engine_step(c: &mut Criterion) {
    let pools: Vec<(&str, ThreadPool)> = [("1t", 1), ("2t", 2)]
        .into_iter()
        .map(|(name, threads)| {
            (
                name,
                rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .expect("pool"),
            )
        })
        .collect();
    for n in [1_000usize, 100_000, 1_000_000] {
        let mut group = c.benchmark_group(format!("engine_step_{n}"));
        group.throughput(Throughput::Elements(n as u64));
        if n >= 100_000 {
            group.sample_size(10);
            group.warm_up_time(Duration::from_millis(500));
            group.measurement_time(Duration::from_secs(3));
        }
        for (name, pool) in &pools {
            let mut columns = Columns::new(n);
            group.bench_function(format!("baseline_{name}"), |b| {
                b.iter_custom(|iters| {
                    pool.install(|| {
                        let start = Instant::now();
                        for _ in 0..iters {
                            baseline(pool.current_num_threads(), black_box(&mut columns));
                        }
                        start.elapsed()
                    })
                });
            });
            let mut hand_columns = columns_of(&rain(n, "semi_implicit_euler", false));
            group.bench_function(format!("hand_{name}"), |b| {
                b.iter_custom(|iters| {
                    pool.install(|| {
                        let start = Instant::now();
                        for _ in 0..iters {
                            hand_step(pool.current_num_threads(), black_box(&mut hand_columns), 0.5, 0.1);
                        }
                        start.elapsed()
                    })
                });
            });
            for method in ["semi_implicit_euler", "rk4", "velocity_verlet"] {
                if n == 1_000_000 && method == "velocity_verlet" && *name == "2t" {
                    continue; // history methods step the whole slice on one thread
                }
                let make = || rain(n, method, false);
                let mut world = make();
                group.bench_function(format!("{method}_{name}"), |b| {
                    b.iter_custom(|iters| timed_steps(pool, &mut world, &make, iters));
                });
            }
        }
        group.finish();
    }
    let mut group = c.benchmark_group("engine_collisions_10000");
    group.throughput(Throughput::Elements(10_000));
    let make = || rain(10_000, "semi_implicit_euler", true);
    let mut world = make();
    let (_, pool) = &pools[0];
    group.bench_function("semi_implicit_euler_grid_1t", |b| {
        b.iter_custom(|iters| timed_steps(pool, &mut world, &make, iters));
    });
    // The same pile with one ball 50 times a grain's radius: one cell size
    // set by the ball made this quadratic; the hierarchical grid keeps it
    // near the uniform pile's cost.
    let make_mixed = || {
        let mut w = rain(10_000, "semi_implicit_euler", true);
        w.spawn(Particle {
            position: Vec3::new(0.5, 3.0, 0.5),
            radius: 1.0,
            mass: 100.0,
            ..Particle::default()
        })
        .expect("valid");
        w
    };
    let mut world = make_mixed();
    group.bench_function("semi_implicit_euler_grid_mixed_sizes_1t", |b| {
        b.iter_custom(|iters| timed_steps(pool, &mut world, &make_mixed, iters));
    });
    // Two spheres of radius 1e30 far off (any ratio of radii): each size
    // on a level of its own, so about the uniform pile's cost again (a
    // grid of 24 levels put every grain in one cell: quadratic).
    let make_giants = || {
        let mut w = rain(10_000, "semi_implicit_euler", true);
        for x in [1e31, -1e31] {
            w.spawn(Particle {
                position: Vec3::new(x, 0.0, 0.0),
                radius: 1e30,
                mass: 1e6,
                ..Particle::default()
            })
            .expect("valid");
        }
        w
    };
    let mut world = make_giants();
    group.bench_function("semi_implicit_euler_grid_giants_1t", |b| {
        b.iter_custom(|iters| timed_steps(pool, &mut world, &make_giants, iters));
    });
    group.finish();
}

/// Resting for minutes: the engine flushes subnormal velocities every 64
/// steps; a hand loop keeps multiplying them, about 100 times slower per
/// operation. Both beside the same state sliding at a normal 1 mm/s.
fn resting_minutes(c: &mut Criterion) {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().expect("pool");
    let mut group = c.benchmark_group("engine_resting_100000");
    group.throughput(Throughput::Elements(100_000));
    group.sample_size(10);
    group.warm_up_time(Duration::from_millis(500));
    group.measurement_time(Duration::from_secs(3));
    for (name, speed) in [("sliding", 1e-3_f32), ("minutes", 1e-40)] {
        let make = move || resting(speed);
        let mut world = make();
        group.bench_function(format!("semi_implicit_euler_{name}_1t"), |b| {
            b.iter_custom(|iters| timed_steps(&pool, &mut world, &make, iters));
        });
        let mut columns = columns_of(&make());
        group.bench_function(format!("hand_{name}_1t"), |b| {
            b.iter_custom(|iters| {
                // The hand loop's state never leaves the subnormal range:
                // `1e-40 (1 - b h)` rounds back to a subnormal.
                let start = Instant::now();
                for _ in 0..iters {
                    hand_step(1, black_box(&mut columns), 0.5, 0.0);
                }
                start.elapsed()
            });
        });
    }
    group.finish();
}

/// 100k particles under gravity and drag over a floor of restitution `e`
/// whose contacts follow `rule`: `falling` from 1 000 m (no contact in the
/// 600 steps before the world is made again: 10 s fall less than 500 m), `resting` on the floor, or `bouncing` from up to 5 m;
/// `resting_on_a_box`: resting on the top of a solid box (200 m wide) instead.
fn floor_case(case: &str, rule: ContactRule) -> World {
    let e = if case == "bouncing" { 0.9 } else { 0.5 };
    let mut w = World::new(WorldConfig::default()).expect("registered");
    w.add_force(Gravity::EARTH);
    w.add_force(LinearDrag { rate: 0.1 });
    let material = Material {
        restitution: e,
        friction: 0.0,
    };
    if case == "resting_on_a_box" {
        // The floor is the top of a solid box instead.
        w.add_collider(tickwork_engine::BoxCollider {
            contact: rule,
            ..tickwork_engine::BoxCollider::solid(
                Vec3::new(-100.0, -1.0, -100.0),
                Vec3::new(100.0, 0.0, 100.0),
                material,
            )
        });
    } else {
        w.add_collider(Plane {
            contact: rule,
            ..Plane::floor(0.0, material)
        });
    }
    for i in 0..100_000u32 {
        let (a, b) = ((i % 316) as f32 * 0.05, (i / 316) as f32 * 0.05);
        let h = (i.wrapping_mul(2_654_435_761) >> 8) as f32 / (1u32 << 24) as f32;
        let (position, velocity) = match case {
            "falling" => (Vec3::new(a, 1000.0 + 10.0 * h, b), Vec3::new(1.0, 0.0, -1.0)),
            "resting" | "resting_on_a_box" => (Vec3::new(a, 0.02, b), Vec3::new(1e-3, 0.0, 0.0)),
            _ => (Vec3::new(a, 0.1 + 5.0 * h, b), Vec3::new(1.0 - 2.0 * h, 0.0, 0.5)),
        };
        w.spawn(Particle {
            position,
            velocity,
            radius: 0.02,
            ..Particle::default()
        })
        .expect("valid");
    }
    w
}

/// The contact rules side by side: the cost of finding contacts inside
/// the step where nothing touches (falling), where everything rests, and
/// where everything bounces.
fn contact_rules(c: &mut Criterion) {
    let mut group = c.benchmark_group("engine_contact_rule_100000");
    group.throughput(Throughput::Elements(100_000));
    group.sample_size(10);
    group.warm_up_time(Duration::from_millis(500));
    group.measurement_time(Duration::from_secs(3));
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool");
        for case in ["falling", "resting", "bouncing", "resting_on_a_box"] {
            for (name, rule) in [
                ("end_of_step", ContactRule::EndOfStep),
                ("in_step", ContactRule::InStep),
            ] {
                let make = move || floor_case(case, rule);
                let mut world = make();
                group.bench_function(format!("{name}_{case}_{threads}t"), |b| {
                    b.iter_custom(|iters| timed_steps(&pool, &mut world, &make, iters));
                });
            }
        }
    }
    group.finish();
}

/// Where two lanes start to pay: the same step on a two-thread pool with
/// one lane and with two, from 4k to 64k particles (`parallel_threshold`
/// is the smallest count at which two win).
fn lanes(c: &mut Criterion) {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().expect("pool");
    for n in [4_096usize, 16_384, 32_768, 65_536] {
        let mut group = c.benchmark_group(format!("engine_lanes_{n}"));
        group.throughput(Throughput::Elements(n as u64));
        group.sample_size(20);
        group.warm_up_time(Duration::from_millis(500));
        group.measurement_time(Duration::from_secs(2));
        for (name, threshold) in [("1_lane", usize::MAX), ("2_lanes", 0)] {
            let make = move || rain_with(n, "semi_implicit_euler", false, threshold);
            let mut world = make();
            group.bench_function(name, |b| {
                b.iter_custom(|iters| timed_steps(&pool, &mut world, &make, iters));
            });
        }
        group.finish();
    }
}

/// The `crowd` scene: 100k spheres settled in a box, every one touching
/// several others (the sphere grid's worst honest case), 1 and 2 threads.
/// Timed from tick 60, when the pile has landed and the candidate pairs
/// per sphere stay the same (22.4), so every sample times the same work.
fn crowd(c: &mut Criterion) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/scenes/crowd.ron");
    let scene = tickwork_engine::Scene::load(&path).expect("the crowd scene");
    let mut group = c.benchmark_group("engine_crowd_100000");
    group.throughput(Throughput::Elements(100_000));
    group.sample_size(10);
    group.warm_up_time(Duration::from_millis(500));
    group.measurement_time(Duration::from_secs(5));
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool");
        let make = || {
            let mut world = scene.build().expect("builds").0;
            pool.install(|| {
                while world.tick() < 60 {
                    world.step(next_step(&world)).expect("step");
                }
            });
            world
        };
        let mut world = make();
        group.bench_function(format!("{threads}t"), |b| {
            b.iter_custom(|iters| timed_steps(&pool, &mut world, &make, iters));
        });
    }
    group.finish();
}

/// 100k particles falling from 1 km (none lands within the 10 s a world
/// lives here) and 1 000 resting on the floor, which projects them back
/// every step: 1% of the particles lose their history each step. History
/// methods restart only those with RK4, so they cost about what a
/// one-evaluation method costs, not what RK4 does (both shown beside them).
fn history_on_a_floor(c: &mut Criterion) {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().expect("pool");
    let mut group = c.benchmark_group("engine_history_101000");
    group.throughput(Throughput::Elements(101_000));
    group.sample_size(10);
    group.warm_up_time(Duration::from_millis(500));
    group.measurement_time(Duration::from_secs(3));
    for method in [
        "semi_implicit_euler",
        "position_verlet",
        "beeman",
        "adams_bashforth4",
        "rk4",
    ] {
        let make = move || {
            let config = WorldConfig {
                integrator: method.into(),
                ..WorldConfig::default()
            };
            let mut w = floor_world(config, 0.0);
            for i in 0..101_000 {
                let (a, b) = ((i % 317) as f32 * 0.05, (i / 317) as f32 * 0.05);
                let y = if i % 101 == 0 { 0.02 } else { 1000.0 };
                w.spawn(Particle {
                    position: Vec3::new(a, y, b),
                    radius: 0.02,
                    ..Particle::default()
                })
                .expect("valid");
            }
            w
        };
        let mut world = make();
        group.bench_function(format!("{method}_1pct_on_floor_1t"), |b| {
            b.iter_custom(|iters| timed_steps(&pool, &mut world, &make, iters));
        });
    }
    group.finish();
}

/// FNV-1a a byte at a time over a world's particle columns: what
/// `state_hash` was before it fed whole runs to xxh3 (the reference the
/// new hash is measured against, in the same run).
fn fnv_columns(w: &World) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut bytes = |bytes: &[u8]| {
        for &b in bytes {
            h = (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3);
        }
    };
    let p = w.particles();
    for column in [&p.position, &p.velocity, &p.previous_position] {
        for x in column.iter() {
            for v in x.to_array() {
                bytes(&v.to_le_bytes());
            }
        }
    }
    for column in [&p.inverse_mass, &p.radius, &p.lifetime] {
        for v in column {
            bytes(&v.to_le_bytes());
        }
    }
    for v in &p.born {
        bytes(&v.to_le_bytes());
    }
    h
}

/// The state hash (what a rollback session checksums every frame) at 1k and
/// 100k particles, beside the byte-wise FNV it replaced and a copy of the
/// same columns' bytes (the memory-bandwidth reference), in one run.
fn checksum(c: &mut Criterion) {
    for n in [1_000, 100_000] {
        let world = rain(n, "semi_implicit_euler", false);
        let mut group = c.benchmark_group(format!("engine_checksum_{n}"));
        group.throughput(Throughput::Elements(n as u64));
        group.sample_size(20);
        group.warm_up_time(Duration::from_millis(300));
        group.measurement_time(Duration::from_secs(2));
        group.bench_function("state_hash", |b| b.iter(|| black_box(&world).state_hash()));
        group.bench_function("fnv_bytewise_columns", |b| b.iter(|| fnv_columns(black_box(&world))));
        let p = world.particles();
        let source: Vec<f32> = p
            .position
            .iter()
            .chain(p.velocity.iter())
            .chain(p.previous_position.iter())
            .flat_map(|x| x.to_array())
            .chain(p.inverse_mass.iter().chain(&p.radius).chain(&p.lifetime).copied())
            .collect();
        let mut copy = vec![0.0f32; source.len()];
        group.bench_function("copy_same_bytes", |b| {
            b.iter(|| copy.copy_from_slice(black_box(&source)));
        });
        group.finish();
    }
}

criterion_group!(
    benches,
    engine_step,
    resting_minutes,
    contact_rules,
    lanes,
    crowd,
    history_on_a_floor,
    checksum
);
criterion_main!(benches);

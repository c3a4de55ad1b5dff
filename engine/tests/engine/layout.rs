//! The per-axis layout (four particles per block) against the row path:
//! every pointwise force and collider, with and without a block kernel,
//! stepped fused (one lane and two) and plain, must give the same bits.
// Reference values and set-ups computed natively (never in a page): the
// platform's own functions are fine here (clippy.toml bans them in the engine).
#![allow(clippy::disallowed_methods)]

use glam::Vec3;
use tickwork_engine::{
    Attractor, BoxCollider, Emitter, FixedStep, Gravity, LinearDrag, Material, Particle, Plane, QuadraticDrag, World,
    WorldConfig,
};

use crate::support;
use support::ForcePlainPath;

/// 1 003 particles (a part-filled last block), some immovable, some with
/// lifetimes (despawns move rows between blocks), an emitter adding more;
/// affine forces and two that are not (their rows go through scratch); an
/// axis floor with friction and a frictionless wall (block kernels), a
/// tilted plane and a box (row fallback).
fn scene(method: &str, threshold: usize, plain: bool) -> World {
    let mut w = World::new(WorldConfig {
        integrator: method.into(),
        parallel_threshold: threshold,
        seed: 11,
        ..WorldConfig::default()
    })
    .expect("known method");
    w.add_force(Gravity::EARTH);
    w.add_force(LinearDrag { rate: 0.3 });
    w.add_force(QuadraticDrag { coefficient: 0.02 });
    w.add_force(Attractor {
        position: Vec3::new(0.0, 3.0, 0.0),
        gm: 4.0,
        softening: 0.5,
    });
    w.add_collider(Plane::floor(
        0.0,
        Material {
            restitution: 0.7,
            friction: 0.3,
        },
    ));
    w.add_collider(Plane {
        normal: Vec3::NEG_X,
        offset: -4.0,
        material: Material {
            restitution: 0.9,
            friction: 0.0,
        },
        speed: 0.0,
        ..Plane::default()
    });
    w.add_collider(Plane {
        normal: Vec3::new(1.0, 1.0, 0.0).normalize(),
        offset: -3.0,
        material: Material::default(),
        speed: 0.0,
        ..Plane::default()
    });
    w.add_collider(BoxCollider {
        min: Vec3::splat(-5.0),
        max: Vec3::splat(5.0),
        inside: true,
        material: Material::default(),
        velocity: Vec3::ZERO,
        ..BoxCollider::default()
    });
    if plain {
        w.add_collider(ForcePlainPath);
    }
    w.add_emitter(Emitter {
        rate: 600.0,
        lifetime: 0.5,
        position: Vec3::new(1.0, 2.0, 0.0),
        speed: 3.0,
        ..Emitter::default()
    })
    .expect("valid emitter");
    for k in 0..1003u32 {
        let f = k as f32;
        w.spawn(Particle {
            position: Vec3::new((f * 0.37).sin() * 4.5, 0.2 + (f * 0.11) % 4.0, (f * 0.23).cos() * 4.5),
            velocity: Vec3::new((f * 0.7).cos() * 2.0, (f * 0.3).sin(), (f * 0.5).sin() * 2.0),
            radius: 0.02 * (k % 5) as f32,
            mass: 1.0 + (k % 3) as f32,
            immovable: k % 97 == 0,
            lifetime: (k % 7 == 0).then_some(0.2 + (k % 11) as f32 * 0.1),
            ..Particle::default()
        })
        .expect("valid");
    }
    w
}

fn run(method: &str, threshold: usize, plain: bool, threads: usize) -> (Vec<u64>, u32) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("pool");
    pool.install(|| {
        let mut w = scene(method, threshold, plain);
        let mut hashes = Vec::new();
        let mut lanes = 0;
        for tick in 0..150 {
            let report = w
                .step(FixedStep {
                    tick,
                    time: tick as f64 / 60.0,
                    dt: 1.0 / 60.0,
                })
                .expect("a finite step");
            lanes = lanes.max(report.fused_lanes);
            hashes.push(support::hash_without_plain_path(&mut w));
        }
        (hashes, lanes)
    })
}

#[test]
fn fused_blocks_and_plain_rows_agree_bit_for_bit_on_every_pointwise_kind() {
    for method in ["semi_implicit_euler", "rk4", "explicit_euler", "implicit_drag_euler"] {
        let (plain, plain_lanes) = run(method, usize::MAX, true, 1);
        let (one, one_lanes) = run(method, usize::MAX, false, 1);
        let (two, two_lanes) = run(method, 512, false, 2);
        // Rows above the threshold: gathers, pointwise colliders and the
        // check on rayon's threads.
        let (plain_two, plain_two_lanes) = run(method, 512, true, 2);
        assert_eq!(
            (plain_lanes, one_lanes, two_lanes, plain_two_lanes),
            (0, 1, 2, 0),
            "{method}: the paths that ran"
        );
        let first_difference = |a: &[u64]| a.iter().zip(&plain).position(|(a, b)| a != b);
        assert_eq!(
            first_difference(&plain_two),
            None,
            "{method}: rows on two threads vs one"
        );
        assert_eq!(first_difference(&one), None, "{method}: one lane of blocks vs rows");
        assert_eq!(first_difference(&two), None, "{method}: two lanes of blocks vs rows");
    }
}

#[test]
fn lanes_left_without_work_by_whole_chunks_report_nothing_stale() {
    // 3 threads, 2 600 rows: three lanes of 1 024 rows; the third one's
    // particles expire. Then 2 048 rows make two parts for three lanes: the
    // idle third lane must not hand back its old expired rows.
    let pool = rayon::ThreadPoolBuilder::new().num_threads(3).build().expect("pool");
    pool.install(|| {
        let mut w = World::new(WorldConfig {
            parallel_threshold: 512,
            ..WorldConfig::default()
        })
        .expect("known method");
        w.add_force(Gravity::EARTH);
        for k in 0..2600 {
            w.spawn(Particle {
                position: Vec3::new(k as f32 * 0.01, 10.0, 0.0),
                lifetime: (k >= 2048).then_some(0.05),
                ..Particle::default()
            })
            .expect("valid");
        }
        let mut lanes = Vec::new();
        for tick in 0..10 {
            let step = FixedStep {
                tick,
                time: tick as f64 / 60.0,
                dt: 1.0 / 60.0,
            };
            lanes.push(w.step(step).expect("a step").fused_lanes);
        }
        assert_eq!(w.particles().len(), 2048, "exactly the short-lived ones expired");
        assert_eq!((lanes[0], lanes[9]), (3, 2), "lanes that ran");
    });
}

/// A scene whose chunks start with different facts (chunks of 512 rows):
/// chunk 0 movable points, one immovable particle in chunk 1, radii in
/// chunk 2, chunks 3 and 4 (2 048..2 300, part-filled) movable points.
fn facts_scene(threshold: usize, plain: bool) -> World {
    let mut w = World::new(WorldConfig {
        parallel_threshold: threshold,
        ..WorldConfig::default()
    })
    .expect("known method");
    w.add_force(Gravity::EARTH);
    w.add_force(LinearDrag { rate: 0.1 });
    w.add_collider(Plane::floor(
        0.5,
        Material {
            restitution: 0.6,
            friction: 0.4,
        },
    ));
    w.add_collider(Plane {
        normal: Vec3::X,
        offset: -1.0,
        material: Material {
            restitution: 0.8,
            friction: 0.0,
        },
        speed: 0.0,
        ..Plane::default()
    });
    if plain {
        w.add_collider(ForcePlainPath);
    }
    for k in 0..2300u32 {
        let f = k as f32;
        w.spawn(Particle {
            position: Vec3::new((f * 0.37).sin() * 2.0, 0.6 + (f * 0.11) % 1.0, (f * 0.23).cos()),
            velocity: Vec3::new((f * 0.7).cos() * 3.0, (f * 0.3).sin(), (f * 0.5).sin()),
            radius: if (1024..1536).contains(&k) { 0.05 } else { 0.0 },
            immovable: k == 700,
            ..Particle::default()
        })
        .expect("valid");
    }
    w
}

/// Steps the facts scene 90 times, each change on the way turning a chunk
/// of movable points (the kernels' short path) into one that is not, so a
/// missed update would take the short path wrongly: an edit through
/// `particles_mut` makes row 1 600 immovable (at rest) and gives row 1 610 a
/// radius (tick 20, chunk 3); a spawn puts a sphere into chunk 4 (tick 40);
/// a despawn in chunk 0 moves that sphere, the last row, into it (tick 60).
/// The state hash after each step.
fn facts_run(threshold: usize, plain: bool, threads: usize) -> (Vec<u64>, u32) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("pool");
    pool.install(|| {
        let mut w = facts_scene(threshold, plain);
        let (mut hashes, mut lanes) = (Vec::new(), 0);
        let (mut pinned, mut sphere) = (None, None);
        for tick in 0..90 {
            match tick {
                20 => {
                    // Immovable: no force or contact moves it (and no
                    // velocity is left to carry it).
                    let p = w.particles_mut();
                    p.inverse_mass[1600] = 0.0;
                    p.velocity.set(1600, glam::Vec3A::ZERO);
                    p.radius[1610] = 0.1;
                    pinned = p.position.get(1600);
                }
                40 => {
                    let ball = Particle {
                        position: Vec3::new(0.0, 0.55, 0.0),
                        velocity: Vec3::new(0.0, -2.0, 0.0),
                        radius: 0.2,
                        ..Particle::default()
                    };
                    sphere = Some(w.spawn(ball).expect("valid"));
                }
                60 => {
                    let in_chunk_0 = w.entities().rows()[100];
                    w.despawn(in_chunk_0).expect("live");
                    let sphere = sphere.expect("spawned");
                    assert_eq!(w.row(sphere), Ok(100), "the sphere moved into chunk 0");
                }
                _ => {}
            }
            let step = FixedStep {
                tick,
                time: tick as f64 / 60.0,
                dt: 1.0 / 60.0,
            };
            lanes = lanes.max(w.step(step).expect("a finite step").fused_lanes);
            hashes.push(support::hash_without_plain_path(&mut w));
        }
        // The changes took effect (a stale fact would have let row 1 600
        // fall and the sphere sink to the floor's plane).
        assert_eq!(w.particles().position.get(1600), pinned, "row 1 600 became immovable");
        let sphere = w.position(sphere.expect("spawned")).expect("live");
        assert!(sphere.y > 0.69, "the sphere rests on its radius: {sphere}");
        (hashes, lanes)
    })
}

#[test]
fn chunk_facts_follow_spawns_despawns_and_edits() {
    let (plain, plain_lanes) = facts_run(usize::MAX, true, 1);
    let (one, one_lanes) = facts_run(usize::MAX, false, 1);
    let (two, two_lanes) = facts_run(512, false, 2);
    assert_eq!((plain_lanes, one_lanes, two_lanes), (0, 1, 2), "the paths that ran");
    let first_difference = |a: &[u64]| a.iter().zip(&plain).position(|(a, b)| a != b);
    assert_eq!(first_difference(&one), None, "one lane of blocks vs rows");
    assert_eq!(first_difference(&two), None, "two lanes of blocks vs rows");
}

//! Sensors and overlap queries: which particles overlap a volume, reported
//! per step with when the overlap began and ended, pushing nothing.

use glam::Vec3;
use tickwork_engine::clock::FixedStep;
use tickwork_engine::{
    Entity, Overlap, OverlapPhase, Particle, Sensor, SensorError, SensorShape, SimulationError, World, WorldConfig,
};

fn step(w: &mut World) {
    let tick = w.tick();
    w.step(FixedStep {
        tick,
        time: tick as f64 / 10.0,
        dt: 0.1,
    })
    .expect("steps");
}

fn overlap(sensor: tickwork_engine::SensorId, entity: Entity, phase: OverlapPhase) -> Overlap {
    Overlap { sensor, entity, phase }
}

/// A particle moving at 1 m/s along x from x = -2 (radius 0.1) through a
/// trigger ball of radius 0.45 at the origin: the overlap begins when the
/// gap closes (|x| < 0.55), stays, ends, and the particle moves as if the
/// sensor were not there.
#[test]
fn a_particle_entering_and_leaving_a_trigger_is_reported_once_each_way() {
    let mut w = World::default();
    let zone = w.add_sensor(Sensor::sphere(Vec3::ZERO, 0.45)).expect("valid");
    let p = w
        .spawn(Particle {
            position: Vec3::new(-2.0, 0.0, 0.0),
            velocity: Vec3::X,
            radius: 0.1,
            ..Particle::default()
        })
        .expect("valid");
    let mut phases = Vec::new();
    for _ in 0..40 {
        step(&mut w);
        let x = w.position(p).expect("live").x;
        for o in w.overlaps() {
            assert_eq!((o.sensor, o.entity), (zone, p));
            phases.push((w.tick(), o.phase));
        }
        let inside = x.abs() < 0.55;
        let reported = w.overlaps().iter().any(|o| o.phase != OverlapPhase::Ended);
        assert_eq!(inside, reported, "at x = {x}");
    }
    // x = -2 + 0.1 k after k steps: inside for k = 15 ..= 25 (x from -0.5
    // to 0.5), ended at 26.
    let began: Vec<_> = phases.iter().filter(|(_, ph)| *ph == OverlapPhase::Began).collect();
    let ended: Vec<_> = phases.iter().filter(|(_, ph)| *ph == OverlapPhase::Ended).collect();
    assert_eq!(began, [&(15, OverlapPhase::Began)]);
    assert_eq!(ended, [&(26, OverlapPhase::Ended)]);
    assert_eq!(phases.len(), 12, "began, 10 stays, ended: {phases:?}");
    // Nothing pushed it: it moved 4 m in 40 steps at 1 m/s.
    assert!((w.position(p).expect("live").x - 2.0).abs() < 1e-5);
    assert_eq!(w.velocity(p).expect("live"), Vec3::X);
}

#[test]
fn a_sensor_following_an_entity_reports_the_others_and_ends_with_it() {
    let mut w = World::default();
    let ship = w
        .spawn(Particle {
            radius: 0.2,
            ..Particle::default()
        })
        .expect("valid");
    let near = w
        .spawn(Particle {
            position: Vec3::new(0.0, 0.9, 0.0),
            ..Particle::default()
        })
        .expect("valid");
    let far = w
        .spawn(Particle {
            position: Vec3::new(0.0, 5.0, 0.0),
            ..Particle::default()
        })
        .expect("valid");
    let pickup = w.add_sensor(Sensor::around(ship, 1.0)).expect("valid");
    step(&mut w);
    assert_eq!(
        w.overlaps(),
        [overlap(pickup, near, OverlapPhase::Began)],
        "not the ship itself"
    );
    // The ship moves next to the far one; the near one drops out.
    w.teleport(ship, Vec3::new(0.0, 4.5, 0.0)).expect("live");
    step(&mut w);
    let mut expected = [
        overlap(pickup, near, OverlapPhase::Ended),
        overlap(pickup, far, OverlapPhase::Began),
    ];
    expected.sort_by_key(|o| o.entity.to_bits());
    assert_eq!(w.overlaps(), expected);
    // Despawning the ship ends its sensor's overlaps, and it reports no more.
    w.despawn(ship).expect("live");
    step(&mut w);
    assert_eq!(w.overlaps(), [overlap(pickup, far, OverlapPhase::Ended)]);
    step(&mut w);
    assert!(w.overlaps().is_empty());
    assert!(w.sensor(pickup).is_ok(), "the sensor stays");
}

#[test]
fn a_despawned_particle_ends_its_overlap_and_boxes_overlap_by_the_radius() {
    let mut w = World::default();
    let room = w
        .add_sensor(Sensor::cuboid(Vec3::new(-1.0, -1.0, -1.0), Vec3::new(1.0, 1.0, 1.0)))
        .expect("valid");
    let inside = w.spawn(Particle::default()).expect("valid");
    let grazing = w
        .spawn(Particle {
            position: Vec3::new(1.2, 0.0, 0.0),
            radius: 0.25,
            ..Particle::default()
        })
        .expect("valid");
    let outside = w
        .spawn(Particle {
            position: Vec3::new(1.2, 0.0, 0.0),
            radius: 0.15,
            ..Particle::default()
        })
        .expect("valid");
    step(&mut w);
    let entities: Vec<Entity> = w.overlaps().iter().map(|o| o.entity).collect();
    assert!(entities.contains(&inside) && entities.contains(&grazing) && !entities.contains(&outside));
    w.despawn(inside).expect("live");
    step(&mut w);
    assert_eq!(
        w.overlaps()
            .iter()
            .map(|o| (o.entity, o.phase))
            .collect::<Vec<_>>()
            .len(),
        2
    );
    assert!(w.overlaps().contains(&overlap(room, inside, OverlapPhase::Ended)));
    assert!(w.overlaps().contains(&overlap(room, grazing, OverlapPhase::Stays)));
    // The queries answer the same rule now, in row order.
    let found: Vec<Entity> = w.in_box(Vec3::splat(-1.0), Vec3::splat(1.0)).collect();
    assert_eq!(found, [grazing]);
    let found: Vec<Entity> = w.within(Vec3::new(1.2, 0.0, 0.0), 0.01).collect();
    assert_eq!(found.len(), 2, "both particles at x = 1.2");
    assert_eq!(w.within(Vec3::ZERO, f32::NAN).count(), 0, "a NaN radius finds none");
}

#[test]
fn overlaps_are_the_same_on_any_threads_and_kept_by_snapshots() {
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool")
            .install(|| {
                let mut w = World::new(WorldConfig {
                    parallel_threshold: 64,
                    ..WorldConfig::default()
                })
                .expect("valid");
                w.add_force(tickwork_engine::Gravity::EARTH);
                for k in 0..3 {
                    w.add_sensor(Sensor::sphere(Vec3::new(k as f32 - 1.0, 0.0, 0.0), 0.4))
                        .expect("valid");
                }
                for k in 0..5_000 {
                    let f = k as f32;
                    w.spawn(Particle {
                        position: Vec3::new(
                            tickwork_engine::math::sin(f * 0.37) * 2.0,
                            (f * 0.11).fract() * 4.0,
                            0.0,
                        ),
                        radius: 0.01,
                        ..Particle::default()
                    })
                    .expect("valid");
                }
                let mut log = Vec::new();
                let mut saved = None;
                for _ in 0..12 {
                    step(&mut w);
                    log.extend_from_slice(w.overlaps());
                    if w.tick() == 6 {
                        saved = Some(w.clone());
                    }
                }
                // Restored, the world goes on with the same overlaps.
                let mut again = saved.expect("saved");
                let mut replayed = Vec::new();
                for _ in 6..12 {
                    step(&mut again);
                    replayed.extend_from_slice(again.overlaps());
                }
                assert_eq!(again.state_hash(), w.state_hash(), "restored and run on");
                (log, replayed, w.state_hash())
            })
    };
    let one = run(1);
    assert!(one.0.iter().any(|o| o.phase == OverlapPhase::Began));
    assert!(
        one.0.iter().any(|o| o.phase == OverlapPhase::Ended),
        "they fall through"
    );
    assert!(one.0.ends_with(&one.1), "the restored run's overlaps");
    assert_eq!(one, run(2));
}

#[test]
fn bad_sensors_and_too_many_pairs_are_errors_naming_them() {
    let mut w = World::new(WorldConfig {
        max_pairs: 1_000,
        ..WorldConfig::default()
    })
    .expect("valid");
    let error = w.add_sensor(Sensor::sphere(Vec3::ZERO, -1.0)).expect_err("negative");
    assert_eq!(
        error,
        SensorError::Invalid {
            field: "radius",
            value: -1.0
        }
    );
    assert!(error.to_string().contains("sensor radius is -1"), "{error}");
    let nan = Sensor {
        shape: SensorShape::Box {
            half_extents: Vec3::new(1.0, f32::NAN, 1.0),
        },
        ..Sensor::sphere(Vec3::ZERO, 1.0)
    };
    assert!(matches!(
        w.add_sensor(nan),
        Err(SensorError::Invalid {
            field: "half_extents",
            ..
        })
    ));
    let id = w.add_sensor(Sensor::sphere(Vec3::ZERO, 1.0)).expect("valid");
    w.remove_sensor(id).expect("there");
    assert_eq!(w.sensor(id), Err(SensorError::Unknown { id }));
    for _ in 0..2 {
        w.add_sensor(Sensor::sphere(Vec3::ZERO, 1.0)).expect("valid");
    }
    for _ in 0..501 {
        w.spawn(Particle::default()).expect("valid");
    }
    let tick = w.tick();
    let error = w
        .step(FixedStep {
            tick,
            time: 0.0,
            dt: 0.1,
        })
        .expect_err("1 002 pairs");
    assert!(matches!(
        error,
        SimulationError::SensorPairLimit {
            sensors: 2,
            particles: 501,
            pairs: 1_002,
            limit: 1_000,
            ..
        }
    ));
    assert!(error.to_string().contains("WorldConfig::max_pairs"), "{error}");
}

#[test]
fn a_placeholder_sensor_handle_is_an_error_naming_it() {
    // A game's field before set-up: `SensorId::default()`, as a collider's.
    #[derive(Default)]
    struct Fields {
        trigger: tickwork_engine::SensorId,
    }
    let w = World::new(WorldConfig::default()).expect("a world");
    let fields = Fields::default();
    assert_eq!(fields.trigger, tickwork_engine::SensorId::PLACEHOLDER);
    let error = w.sensor(fields.trigger).expect_err("no such sensor");
    assert!(matches!(error, SensorError::Unknown { .. }), "{error:?}");
    assert_eq!(
        error.to_string(),
        "SensorId::PLACEHOLDER (a handle set before any sensor was added) is not in this world (removed, or \
         another world's)"
    );
}

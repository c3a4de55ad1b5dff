//! 2D headings: stepped by the world from their spin, wrapped, kept with
//! their entity through despawns, hashed only where present; visibility.

use glam::Vec3;
use tickwork_engine::clock::FixedStep;
use tickwork_engine::{Heading, Particle, World, WorldError};

fn step(w: &mut World, dt: f64) {
    let tick = w.tick();
    w.step(FixedStep {
        tick,
        time: tick as f64 * dt,
        dt,
    })
    .expect("steps");
}

#[test]
fn a_spinning_entity_turns_by_its_spin_and_stays_within_a_turn() {
    let mut w = World::default();
    let rock = w.spawn(Particle::default()).expect("valid");
    let still = w.spawn(Particle::default()).expect("valid");
    w.set_heading(rock, Heading::new(0.0, 1.0)).expect("live");
    for _ in 0..60 {
        step(&mut w, 1.0 / 60.0);
    }
    let h = w.heading(rock).expect("live");
    assert!((h.angle - 1.0).abs() < 1e-5, "1 rad after 1 s at 1 rad/s: {}", h.angle);
    assert!((h.interpolated(0.5) - (1.0 - 0.5 / 60.0)).abs() < 1e-5);
    assert_eq!(w.heading(still).expect("live"), Heading::default(), "no spin, angle 0");
    // After 4 s: 4 rad, wrapped to 4 - 2 pi.
    for _ in 60..240 {
        step(&mut w, 1.0 / 60.0);
    }
    let h = w.heading(rock).expect("live");
    let expected = 4.0 - core::f32::consts::TAU;
    assert!((h.angle - expected).abs() < 1e-4, "{} against {expected}", h.angle);
    let (cos, sin) = (
        tickwork_engine::math::cos(expected),
        tickwork_engine::math::sin(expected),
    );
    assert!((h.direction() - glam::Vec2::new(cos, sin)).length() < 1e-4);
}

#[test]
fn headings_follow_their_entities_and_are_hashed_only_where_set() {
    let make = || {
        let mut w = World::default();
        let entities: Vec<_> = (0..3)
            .map(|k| {
                w.spawn(Particle {
                    position: Vec3::new(k as f32, 0.0, 0.0),
                    ..Particle::default()
                })
                .expect("valid")
            })
            .collect();
        (w, entities)
    };
    let (plain, _) = make();
    let (mut turned, e) = make();
    let before = turned.state_hash();
    assert_eq!(before, plain.state_hash(), "the same worlds");
    turned.set_heading(e[2], Heading::new(0.5, -2.0)).expect("live");
    assert_ne!(turned.state_hash(), before, "a heading is state");
    // The first despawned: the last row moves into its place, its heading
    // with it.
    turned.despawn(e[0]).expect("live");
    assert_eq!(turned.heading(e[2]).expect("live"), Heading::new(0.5, -2.0));
    assert_eq!(turned.heading(e[1]).expect("live"), Heading::default());
    // Bad values name the field.
    let error = turned
        .set_heading(e[1], Heading::new(0.0, f32::NAN))
        .expect_err("a NaN spin");
    assert!(matches!(error, WorldError::Invalid { .. }));
    assert!(error.to_string().contains("heading.spin"), "{error}");
    // Visibility is state too, and follows the entity.
    let hash = turned.state_hash();
    assert!(turned.is_visible(e[1]).expect("live"));
    turned.set_visible(e[1], false).expect("live");
    assert!(!turned.is_visible(e[1]).expect("live"));
    assert!(turned.is_visible(e[2]).expect("live"));
    assert_ne!(turned.state_hash(), hash);
}

#[test]
fn an_entity_is_drawn_between_its_last_two_positions() {
    let mut w = World::default();
    let e = w
        .spawn(Particle {
            velocity: Vec3::X,
            ..Particle::default()
        })
        .expect("valid");
    step(&mut w, 0.5);
    assert_eq!(w.drawn_position(e, 0.0).expect("live"), Vec3::ZERO);
    assert_eq!(w.drawn_position(e, 0.5).expect("live"), Vec3::new(0.25, 0.0, 0.0));
    assert_eq!(w.drawn_position(e, 1.0).expect("live"), Vec3::new(0.5, 0.0, 0.0));
}

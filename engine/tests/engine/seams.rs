//! Seams between flush boxes (issue 43's probes): a ball sliding across
//! the joint of two boxes whose faces are flush, at rest or kinematic
//! within `SEAM_TOLERANCE`, does not catch on the next box's edge; a real
//! step or wall still stops it.

use glam::Vec3;
use tickwork_engine::colliders::seams::SEAM_TOLERANCE;
use tickwork_engine::{BoxCollider, FixedClock, Gravity, Material, Particle, Plane, World};

const SLIPPERY: Material = Material {
    restitution: 0.0,
    friction: 0.0,
};

/// A solid box from `min` to `max` (2D: z from -1 to 1) moving at `velocity`.
fn block(min: [f32; 2], max: [f32; 2], velocity: Vec3) -> BoxCollider {
    BoxCollider {
        velocity,
        ..BoxCollider::solid(
            Vec3::new(min[0], min[1], -1.0),
            Vec3::new(max[0], max[1], 1.0),
            SLIPPERY,
        )
    }
}

/// Where a ball of radius 0.4 ends, sliding at 6 m/s from x = 1 along a box
/// from x 0 to 10 onto `next` (from x 10 on), for `seconds`.
fn slide(next: BoxCollider, seconds: u32) -> Vec3 {
    let mut world = World::default();
    world.add_force(Gravity::EARTH);
    world.add_collider(block([0.0, -1.0], [10.0, 0.0], Vec3::ZERO));
    world.add_collider(next);
    let ball = world
        .spawn(Particle {
            position: Vec3::new(1.0, 0.4, 0.0),
            velocity: Vec3::new(6.0, 0.0, 0.0),
            radius: 0.4,
            ..Particle::default()
        })
        .expect("spawned");
    let mut clock = FixedClock::default();
    for step in clock.step(60 * seconds).fixed_steps() {
        world.step(step).expect("steps");
    }
    world.position(ball).expect("there")
}

#[test]
fn a_ball_slides_across_the_seam_onto_a_flush_box_at_rest_or_moving() {
    for (what, velocity) in [
        ("at rest", Vec3::ZERO),
        ("rising at 1 mm/s", Vec3::new(0.0, 0.001, 0.0)),
        ("sinking at 1 mm/s", Vec3::new(0.0, -0.001, 0.0)),
    ] {
        let end = slide(block([10.0, -1.0], [17.0, 0.0], velocity), 2);
        // 2 s at 6 m/s from x = 1: x = 13, on the second box.
        assert!((end.x - 13.0).abs() < 1e-3, "{what}: stopped at x = {}", end.x);
        assert!(
            (end.y - 0.4 - velocity.y * 2.0).abs() < 2e-3,
            "{what}: on its top: {end}"
        );
    }
}

#[test]
fn a_step_higher_than_the_tolerance_still_stops_a_sliding_ball() {
    let step = 2.0 * SEAM_TOLERANCE;
    let end = slide(block([10.0, -1.0], [17.0, step], Vec3::ZERO), 2);
    assert!((end.x - 9.6).abs() < 1e-3, "stopped at the step's face: {end}");
}

/// The highest a ball of radius 0.4 gets, thrown up at 8.5 m/s while
/// pushed at 0.5 m/s against a wall at x = 1 made of `boxes`.
fn apex_against(boxes: &[([f32; 2], [f32; 2])]) -> f32 {
    let mut world = World::default();
    world.add_force(Gravity::EARTH);
    world.add_collider(Plane::floor(0.0, SLIPPERY));
    for &(min, max) in boxes {
        world.add_collider(block(min, max, Vec3::ZERO));
    }
    let ball = world
        .spawn(Particle {
            position: Vec3::new(0.6, 0.4, 0.0),
            velocity: Vec3::new(0.5, 8.5, 0.0),
            radius: 0.4,
            ..Particle::default()
        })
        .expect("spawned");
    let mut clock = FixedClock::default();
    let mut apex = f32::MIN;
    for step in clock.step(120).fixed_steps() {
        world.step(step).expect("steps");
        apex = apex.max(world.position(ball).expect("there").y);
    }
    apex
}

#[test]
fn a_jump_along_a_wall_of_stacked_boxes_rises_as_high_as_along_one_box() {
    let one = apex_against(&[([1.0, 0.0], [2.0, 6.0])]);
    let stacked = apex_against(&[([1.0, 0.0], [2.0, 1.0]), ([1.0, 1.0], [2.0, 6.0])]);
    // 0.4 + 8.5^2 / 2g = 4.08 m, less the method's step.
    assert!(one > 3.9, "{one}");
    assert!((stacked - one).abs() < 1e-3, "stacked {stacked} against one {one}");
}

#[test]
fn a_box_moving_sideways_is_hit_where_it_is_at_the_instant() {
    // A box 1 m wide moving right at 30 m/s (0.5 m a step) under a
    // particle falling at 30 m/s just beyond its leading edge: when the
    // particle reaches the top's height (a tenth into the step) the box is
    // not under it yet; its leading face then sweeps into the particle,
    // below the top, and carries it along. It must not bounce off the top
    // of a box that was not there.
    let mut world = World::default();
    world.add_collider(block([0.0, -1.0], [1.0, 0.0], Vec3::new(30.0, 0.0, 0.0)));
    let p = world
        .spawn(Particle {
            position: Vec3::new(1.3, 0.05, 0.0),
            velocity: Vec3::new(0.0, -30.0, 0.0),
            ..Particle::default()
        })
        .expect("spawned");
    let mut clock = FixedClock::default();
    for step in clock.step(1).fixed_steps() {
        world.step(step).expect("steps");
    }
    let v = world.velocity(p).expect("there");
    assert!(v.y < 0.0, "no bounce off a top that was elsewhere: {v}");
    assert!((v.x - 30.0).abs() < 1e-3, "carried by the leading face: {v}");
}

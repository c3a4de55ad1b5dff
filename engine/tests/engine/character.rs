//! Kinematic characters: landing, standing, running over seams, stepping
//! up and down, riding platforms, coyote time and jump buffering,
//! ceilings, planes and containers, snapshots and the state hash, sensors,
//! and bad input; each against positions worked out by hand.

use glam::{Vec2, Vec3};
use tickwork_engine::character::MAX_CHARACTERS;
use tickwork_engine::{
    BoxCollider, Character, CharacterConfig, CharacterError, CharacterId, ColliderId, FixedStep, Material, Plane,
    Sensor, World,
};

const DT: f32 = 1.0 / 60.0;
const H: Vec2 = Vec2::new(0.3, 0.45);
const SKIN: f32 = 0.005;

/// A static solid box from `min` to `max` (z from -1 to 1).
fn block(world: &mut World, min: Vec2, max: Vec2) -> ColliderId {
    world.add_collider(BoxCollider::solid(
        min.extend(-1.0),
        max.extend(1.0),
        Material::default(),
    ))
}

/// A kinematic box moving at `velocity`.
fn platform(world: &mut World, min: Vec2, max: Vec2, velocity: Vec2) -> ColliderId {
    world.add_collider(BoxCollider {
        velocity: velocity.extend(0.0),
        ..BoxCollider::solid(min.extend(-1.0), max.extend(1.0), Material::default())
    })
}

/// A character standing at `x` on ground whose top is at `top`.
fn standing(world: &mut World, x: f32, top: f32) -> CharacterId {
    world
        .add_character(Character::new(
            Vec2::new(x, top + H.y + SKIN),
            CharacterConfig::default(),
        ))
        .expect("a character")
}

/// Steps `world` once at tick `tick`.
fn step(world: &mut World) {
    let tick = world.tick();
    world
        .step(FixedStep {
            tick,
            time: tick as f64 / 60.0,
            dt: f64::from(DT),
        })
        .expect("steps");
}

fn at(world: &World, id: CharacterId) -> Vec2 {
    world.character(id).expect("there").position
}

#[test]
fn a_fall_ends_on_the_box_below_a_skin_above_it_and_standing_reports_the_ground_every_step() {
    let mut world = World::default();
    let floor = block(&mut world, Vec2::new(-5.0, -1.0), Vec2::new(5.0, 0.0));
    let hero = world
        .add_character(Character::new(Vec2::new(0.0, 3.0), CharacterConfig::default()))
        .expect("added");
    for _ in 0..60 {
        step(&mut world);
    }
    let c = world.character(hero).expect("there");
    assert!((c.position.y - (H.y + SKIN)).abs() < 1e-6, "{}", c.position);
    assert_eq!(c.position.x, 0.0);
    for _ in 0..120 {
        step(&mut world);
        let c = world.character(hero).expect("there");
        let ground = c.ground().expect("standing: ground every step");
        assert_eq!(
            (ground.collider, ground.normal, ground.velocity),
            (floor, Vec2::Y, Vec2::ZERO)
        );
        assert_eq!(c.velocity, Vec2::ZERO);
        assert!((c.position.y - (H.y + SKIN)).abs() < 1e-6);
    }
}

#[test]
fn running_over_seams_of_flush_boxes_static_or_moving_never_stops() {
    for kinematic in [None, Some(Vec2::new(0.0, 0.001)), Some(Vec2::new(0.0, -0.001))] {
        let mut world = World::default();
        // Ten 1 m boxes side by side, tops at 0; every other one moving at
        // 1 mm/s if `kinematic`.
        for k in 0..10 {
            let (min, max) = (Vec2::new(k as f32 - 1.0, -1.0), Vec2::new(k as f32, 0.0));
            match kinematic {
                Some(v) if k % 2 == 1 => platform(&mut world, min, max, v),
                _ => block(&mut world, min, max),
            };
        }
        let hero = standing(&mut world, -0.5, 0.0);
        for n in 0..80 {
            let before = at(&world, hero);
            world.character_mut(hero).expect("there").run(6.0);
            step(&mut world);
            let c = world.character(hero).expect("there");
            assert!(
                c.wall().is_none(),
                "{kinematic:?}: stopped at step {n}, x {}",
                c.position.x
            );
            assert!(
                c.grounded(),
                "{kinematic:?}: in the air at step {n}, x {}",
                c.position.x
            );
            assert!((c.position.x - before.x - 0.1).abs() < 1e-5, "{kinematic:?}: step {n}");
        }
        assert!(at(&world, hero).x > 7.4, "{kinematic:?}");
    }
}

/// The highest the character's centre gets after a jump at 9 m/s, from
/// standing at `x` on a floor at 0 beside a wall of `boxes` stacked boxes
/// at x 1..2 (none: no wall), pressing right all the way.
fn jump_apex(boxes: usize, x: f32) -> f32 {
    let mut world = World::default();
    block(&mut world, Vec2::new(-5.0, -1.0), Vec2::new(5.0, 0.0));
    for k in 0..boxes {
        block(
            &mut world,
            Vec2::new(1.0, k as f32 * 1.0),
            Vec2::new(2.0, k as f32 + 1.0),
        );
    }
    let hero = standing(&mut world, x, 0.0);
    world.character_mut(hero).expect("there").jump(9.0);
    let mut apex = f32::MIN;
    for _ in 0..60 {
        world.character_mut(hero).expect("there").run(3.0);
        step(&mut world);
        apex = apex.max(at(&world, hero).y);
    }
    apex
}

#[test]
fn a_jump_against_a_wall_of_stacked_boxes_rises_as_high_as_in_the_open() {
    let open = jump_apex(0, 0.7 - SKIN);
    let pressed = jump_apex(3, 1.0 - H.x - SKIN);
    // v^2 / 2g = 81 / 60 = 1.35 m over its standing height, less the
    // semi-implicit Euler's half step.
    assert!((open - (H.y + SKIN) - 1.35).abs() < 0.1, "{open}");
    assert_eq!(pressed, open, "the seams at 1 m and 2 m do not catch it");
}

#[test]
fn an_edge_below_the_step_height_is_climbed_and_a_higher_one_stops_it() {
    for (rise, climbs) in [(0.2, true), (0.3, false)] {
        let mut world = World::default();
        block(&mut world, Vec2::new(-5.0, -1.0), Vec2::new(1.0, 0.0));
        let ledge = block(&mut world, Vec2::new(1.0, -1.0), Vec2::new(5.0, rise));
        let hero = standing(&mut world, 0.0, 0.0);
        for _ in 0..30 {
            world.character_mut(hero).expect("there").run(4.0);
            step(&mut world);
        }
        let c = world.character(hero).expect("there");
        if climbs {
            assert!(c.position.x > 1.5, "{rise}: {}", c.position);
            assert!(
                (c.position.y - (rise + H.y + SKIN)).abs() < 1e-5,
                "{rise}: {}",
                c.position
            );
            assert_eq!(c.ground().map(|g| g.collider), Some(ledge));
        } else {
            assert!(
                (c.position.x - (1.0 - H.x - SKIN)).abs() < 1e-5,
                "{rise}: {}",
                c.position
            );
            assert_eq!(c.wall().map(|w| (w.collider, w.normal)), Some((ledge, Vec2::NEG_X)));
        }
    }
}

#[test]
fn walking_down_a_step_stays_grounded_and_off_a_ledge_falls() {
    for (drop, snaps) in [(0.2, true), (1.0, false)] {
        let mut world = World::default();
        block(&mut world, Vec2::new(-5.0, -2.0), Vec2::new(1.0, 0.0));
        block(&mut world, Vec2::new(1.0, -2.0), Vec2::new(5.0, -drop));
        let hero = standing(&mut world, 0.0, 0.0);
        let mut airborne = 0;
        for _ in 0..50 {
            world.character_mut(hero).expect("there").run(3.0);
            step(&mut world);
            airborne += usize::from(!world.character(hero).expect("there").grounded());
        }
        let c = world.character(hero).expect("there");
        assert!(
            (c.position.y - (-drop + H.y + SKIN)).abs() < 1e-5,
            "{drop}: {}",
            c.position
        );
        if snaps {
            assert_eq!(airborne, 0, "snapped down the {drop} m step");
        } else {
            assert!(airborne > 5, "fell {drop} m in {airborne} steps");
        }
    }
}

#[test]
fn a_moving_platform_carries_what_stands_on_it_across_and_up() {
    let mut world = World::default();
    let across = platform(
        &mut world,
        Vec2::new(-1.0, -0.5),
        Vec2::new(1.0, 0.0),
        Vec2::new(2.0, 0.0),
    );
    let hero = standing(&mut world, 0.0, 0.0);
    for _ in 0..30 {
        step(&mut world);
        let ground = *world.character(hero).expect("there").ground().expect("riding");
        assert_eq!((ground.collider, ground.velocity), (across, Vec2::new(2.0, 0.0)));
    }
    // The first step stood it on the platform; 29 more carried it 2 m/s.
    assert!(
        (at(&world, hero).x - 29.0 * 2.0 * DT).abs() < 1e-4,
        "{}",
        at(&world, hero)
    );
    let mut world = World::default();
    let lift = platform(
        &mut world,
        Vec2::new(-1.0, -0.5),
        Vec2::new(1.0, 0.0),
        Vec2::new(0.0, 1.0),
    );
    let hero = standing(&mut world, 0.0, 0.0);
    for n in 1..=60 {
        step(&mut world);
        let c = world.character(hero).expect("there");
        assert_eq!(c.ground().map(|g| g.collider), Some(lift), "step {n}");
        let top = n as f32 * DT;
        assert!(
            (c.position.y - (top + H.y + SKIN)).abs() < 1e-4,
            "step {n}: {}",
            c.position
        );
    }
}

#[test]
fn coyote_time_takes_a_late_jump_and_a_buffered_jump_is_taken_on_landing() {
    // Off a ledge at x = 1 running at 6 m/s (0.1 m a step), no snap.
    let late = |steps_late: u32| {
        let mut world = World::default();
        block(&mut world, Vec2::new(-5.0, -1.0), Vec2::new(1.0, 0.0));
        let hero = world
            .add_character(Character::new(
                Vec2::new(0.0, H.y + SKIN),
                CharacterConfig {
                    snap_distance: 0.0,
                    ..CharacterConfig::default()
                },
            ))
            .expect("added");
        let mut left_at = None;
        for n in 0..40u32 {
            let c = world.character_mut(hero).expect("there");
            c.run(6.0);
            if left_at.is_some_and(|t: u32| n == t + steps_late) {
                c.jump(9.0);
            }
            step(&mut world);
            let c = world.character(hero).expect("there");
            if left_at.is_none() && !c.grounded() {
                left_at = Some(n);
            }
            if c.jumped() {
                return true;
            }
        }
        false
    };
    assert!(late(1) && late(5) && late(6), "within the 6 steps of coyote time");
    assert!(!late(7), "past them");
    // Pressed 4 steps before landing: kept and taken on landing.
    let fall = |press_at: Option<u32>| {
        let mut world = World::default();
        block(&mut world, Vec2::new(-5.0, -1.0), Vec2::new(5.0, 0.0));
        let hero = world
            .add_character(Character::new(Vec2::new(0.0, 2.0), CharacterConfig::default()))
            .expect("added");
        for n in 0..80u32 {
            if press_at == Some(n) {
                world.character_mut(hero).expect("there").jump(9.0);
            }
            step(&mut world);
            let c = world.character(hero).expect("there");
            if press_at.is_none() && c.grounded() || c.jumped() {
                return n;
            }
        }
        panic!("neither landed nor jumped")
    };
    let landed = fall(None);
    assert_eq!(fall(Some(landed - 4)), landed + 1, "taken the step after landing");
    assert_eq!(fall(Some(landed)), landed + 1);
}

#[test]
fn a_ceiling_stops_a_rise_and_is_reported() {
    let mut world = World::default();
    block(&mut world, Vec2::new(-5.0, -1.0), Vec2::new(5.0, 0.0));
    let roof = block(&mut world, Vec2::new(-5.0, 1.5), Vec2::new(5.0, 2.0));
    let hero = standing(&mut world, 0.0, 0.0);
    world.character_mut(hero).expect("there").jump(9.0);
    let mut hit = None;
    for _ in 0..30 {
        step(&mut world);
        let c = world.character(hero).expect("there");
        if let Some(touch) = c.ceiling() {
            hit = Some((touch.collider, touch.normal, c.position.y, c.velocity.y));
            break;
        }
    }
    let (collider, normal, y, vy) = hit.expect("hit the ceiling");
    assert_eq!((collider, normal, vy), (roof, Vec2::NEG_Y, 0.0));
    assert!((y - (1.5 - H.y - SKIN)).abs() < 1e-5, "{y}");
}

#[test]
fn planes_and_containers_hold_it_too() {
    let mut world = World::default();
    world.add_collider(Plane::floor(-2.0, Material::default()));
    world.add_collider(BoxCollider::container(
        Vec3::new(-3.0, -10.0, -1.0),
        Vec3::new(3.0, 10.0, 1.0),
        Material::default(),
    ));
    let hero = world
        .add_character(Character::new(Vec2::new(0.0, 1.0), CharacterConfig::default()))
        .expect("added");
    for _ in 0..120 {
        world.character_mut(hero).expect("there").run(-5.0);
        step(&mut world);
    }
    let c = world.character(hero).expect("there");
    assert!(
        (c.position - Vec2::new(-3.0 + H.x + SKIN, -2.0 + H.y + SKIN))
            .abs()
            .max_element()
            < 1e-5,
        "{}",
        c.position
    );
    assert!(c.grounded() && c.wall().is_some());
}

#[test]
fn snapshots_rollbacks_and_the_state_hash_cover_characters() {
    let mut world = World::default();
    block(&mut world, Vec2::new(-5.0, -1.0), Vec2::new(5.0, 0.0));
    let hero = standing(&mut world, 0.0, 0.0);
    let run = |world: &mut World, from: usize| {
        for n in from..40 {
            let c = world.character_mut(hero).expect("there");
            c.run(if n % 10 < 5 { 3.0 } else { -2.0 });
            if n == 12 {
                c.jump(8.0);
            }
            step(world);
        }
    };
    let mut replay = world.clone();
    let before = world.state_hash();
    run(&mut world, 0);
    let end = (world.state_hash(), world.character(hero).expect("there").clone());
    assert_ne!(before, end.0, "the hash sees the character move");
    run(&mut replay, 0);
    assert_eq!(
        (replay.state_hash(), replay.character(hero).expect("there").clone()),
        end
    );
    // Rolled back to step 10 (a jump buffered then) and re-run.
    let mut world = replay.clone();
    let mut again = World::default();
    block(&mut again, Vec2::new(-5.0, -1.0), Vec2::new(5.0, 0.0));
    let hero2 = standing(&mut again, 0.0, 0.0);
    assert_eq!(hero2, hero);
    for n in 0..10 {
        again
            .character_mut(hero)
            .expect("there")
            .run(if n % 10 < 5 { 3.0 } else { -2.0 });
        step(&mut again);
    }
    let saved = again.snapshot();
    run(&mut again, 10);
    world.restore(&saved);
    run(&mut world, 10);
    assert_eq!(world.state_hash(), end.0, "a rollback re-runs to the same state");
    // Only the character differs: the hash sees its buffered jump.
    let mut a = replay.clone();
    let b = replay.clone();
    a.character_mut(hero).expect("there").jump(1.0);
    assert_ne!(a.state_hash(), b.state_hash());
}

#[test]
fn sensors_touching_a_character_are_listed() {
    let mut world = World::default();
    let coin = world
        .add_sensor(Sensor::cuboid(Vec3::new(0.2, 0.2, -0.5), Vec3::new(0.6, 0.6, 0.5)))
        .expect("a coin");
    let far = world
        .add_sensor(Sensor::sphere(Vec3::new(5.0, 0.0, 0.0), 1.0))
        .expect("far");
    let near = world
        .add_sensor(Sensor::sphere(Vec3::new(0.0, 1.0, 0.0), 0.6))
        .expect("near");
    let hero = world
        .add_character(Character::new(Vec2::ZERO, CharacterConfig::default()))
        .expect("added");
    let touching: Vec<_> = world.sensors_touching(hero).expect("there").collect();
    assert_eq!(touching, [coin, near]);
    assert!(!touching.contains(&far));
}

#[test]
fn bad_characters_are_refused_with_the_field_and_range() {
    let mut world = World::default();
    let bad = |config: CharacterConfig| {
        Character::new(Vec2::ZERO, config)
            .validate()
            .expect_err("refused")
            .to_string()
    };
    assert_eq!(
        bad(CharacterConfig {
            half_extents: Vec2::new(0.0, 1.0),
            ..CharacterConfig::default()
        }),
        "character half_extents is 0: it must be finite, above 0"
    );
    assert_eq!(
        bad(CharacterConfig {
            skin: 0.5,
            ..CharacterConfig::default()
        }),
        "character skin is 0.5: it must be above 0, at most a tenth of the smaller half extent"
    );
    let hero = world
        .add_character(Character::new(Vec2::ZERO, CharacterConfig::default()))
        .expect("added");
    world.character_mut(hero).expect("there").position.x = f32::NAN;
    let error = world
        .step(FixedStep {
            tick: 0,
            time: 0.0,
            dt: f64::from(DT),
        })
        .expect_err("a NaN place");
    assert_eq!(
        error.to_string(),
        "step 0: character #0: character position is NaN: it must be finite"
    );
    assert_eq!(world.tick(), 0, "refused before the step changed anything");
    world.remove_character(hero).expect("removed");
    assert_eq!(
        world.character(hero).expect_err("gone"),
        CharacterError::Unknown { id: hero }
    );
    for _ in 0..MAX_CHARACTERS {
        world
            .add_character(Character::new(Vec2::ZERO, CharacterConfig::default()))
            .expect("room");
    }
    let error = world
        .add_character(Character::new(Vec2::ZERO, CharacterConfig::default()))
        .expect_err("full");
    assert!(
        error
            .to_string()
            .contains("at most 256 characters (tickwork::engine::character::MAX_CHARACTERS)")
    );
}

#[test]
fn a_container_holds_only_what_is_inside_it_and_a_nan_jump_is_refused() {
    // Beside a container (a room to the right), the character walks away
    // from it and jumps: the room's walls are not in its way.
    let mut world = World::default();
    block(&mut world, Vec2::new(-5.0, -1.0), Vec2::new(5.0, 0.0));
    world.add_collider(BoxCollider::container(
        Vec3::new(1.0, 0.0, -1.0),
        Vec3::new(4.0, 3.0, 1.0),
        Material::default(),
    ));
    let hero = standing(&mut world, 0.0, 0.0);
    world.character_mut(hero).expect("there").jump(9.0);
    let mut apex = f32::MIN;
    for _ in 0..30 {
        world.character_mut(hero).expect("there").run(-3.0);
        step(&mut world);
        apex = apex.max(at(&world, hero).y);
    }
    assert!(at(&world, hero).x < -1.4, "walked away: {}", at(&world, hero));
    assert!(apex > 1.5, "jumped beside the room: {apex}");
    world.character_mut(hero).expect("there").jump(f32::NAN);
    let error = world
        .step(FixedStep {
            tick: world.tick(),
            time: 1.0,
            dt: f64::from(DT),
        })
        .expect_err("a NaN jump");
    assert!(
        error
            .to_string()
            .contains("character jump speed is NaN: it must be finite"),
        "{error}"
    );
}

#[test]
fn a_teleport_leaves_the_ground_and_its_coyote_time_behind() {
    let mut world = World::default();
    block(&mut world, Vec2::new(-5.0, -1.0), Vec2::new(5.0, 0.0));
    let hero = standing(&mut world, 0.0, 0.0);
    step(&mut world);
    assert!(world.character(hero).expect("there").can_jump());
    let c = world.character_mut(hero).expect("there");
    c.teleport(Vec2::new(0.0, 5.0));
    assert!(!c.can_jump() && !c.grounded(), "in the air at once");
    assert_eq!(c.drawn_position(0.0), Vec2::new(0.0, 5.0), "drawn there, not swept");
}

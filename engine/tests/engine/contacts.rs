//! Contact events and collider handles: what a game reads after a step to
//! know which brick the ball hit, checked against the physics of the hit;
//! the same list on the fused and plain paths and on any number of lanes;
//! kinematic boxes; and handles that change, remove and refuse.
// Reference values and set-ups computed natively (never in a page): the
// platform's own functions are fine here (clippy.toml bans them in the engine).
#![allow(clippy::disallowed_methods)]

use crate::support;

use glam::Vec3;
use tickwork_engine::clock::FixedStep;
use tickwork_engine::{
    BoxCollider, ColliderError, Contact, Gravity, Material, Particle, Plane, SphereCollisions, Touched, World,
    WorldConfig,
};

use support::ForcePlainPath;

const DT: f64 = 1.0 / 60.0;

fn step(w: &mut World) {
    let tick = w.tick();
    w.step(FixedStep {
        tick,
        time: tick as f64 * DT,
        dt: DT,
    })
    .expect("the step succeeds");
}

/// A ball of radius 0.1 at rest half a metre up (no gravity).
fn resting_ball(w: &mut World) -> tickwork_engine::Entity {
    w.spawn(Particle {
        position: Vec3::new(0.0, 0.5, 0.0),
        radius: 0.1,
        ..Particle::default()
    })
    .expect("valid")
}

fn bouncy() -> Material {
    Material {
        restitution: 0.8,
        friction: 0.0,
    }
}

#[test]
fn a_ball_hitting_the_floor_reports_one_contact_with_the_impulse_it_received() {
    // At the end of the step (the in-step rule's contacts, with their
    // instant, are `in_step.rs`'s).
    let mut w = World::default();
    w.add_force(Gravity::EARTH);
    let floor = w.add_collider(Plane {
        contact: tickwork_engine::colliders::ContactRule::EndOfStep,
        ..Plane::floor(0.0, bouncy())
    });
    w.report_contacts(floor).expect("the floor is in the world");
    let ball = w
        .spawn(Particle {
            position: Vec3::new(0.5, 1.0, 0.0),
            radius: 0.1,
            mass: 2.0,
            ..Particle::default()
        })
        .expect("valid");
    let mut hits = Vec::new();
    for _ in 0..60 {
        let before = w.velocity(ball).expect("alive");
        step(&mut w);
        if let [contact] = w.contacts() {
            hits.push((before, w.velocity(ball).expect("alive"), *contact));
        } else {
            assert!(w.contacts().is_empty(), "at most one contact: {:?}", w.contacts());
        }
    }
    let [(before, after, contact)] = hits[..] else {
        panic!("one bounce in a second from 1 m, got {} contacts", hits.len());
    };
    assert_eq!(contact.entity, ball);
    assert_eq!(contact.touched, Touched::Collider(floor));
    assert!((contact.normal - Vec3::Y).length() < 1e-6, "normal {}", contact.normal);
    // The point is on the floor, under the ball.
    assert!(
        contact.point.y.abs() < 1e-5 && (contact.point.x - 0.5).abs() < 1e-4,
        "{}",
        contact.point
    );
    // The ball's speed before the contact is that of the step's end
    // (semi-implicit Euler: v + g dt, then the bounce): J = m (v' - v).
    let arriving = before.y - 9.81 * DT as f32;
    let expected = 2.0 * (after.y - arriving);
    assert!(
        (contact.impulse - expected).abs() < 1e-3 * expected,
        "impulse {} against m dv = {expected}",
        contact.impulse
    );
    // e = 0.8: the ball leaves at 0.8 of its arrival speed; J = m (1 + e) |v|.
    assert!((contact.impulse - 2.0 * 1.8 * arriving.abs()).abs() < 1e-3 * contact.impulse);
}

/// 2 000 particles raining on a floor and a box, with a second floor that
/// does not report: the contacts of every step are the same on the fused
/// path on one lane or two (four chunks), and on the plain path, and reporting changes
/// no bit of the motion.
#[test]
fn contacts_are_the_same_on_every_path_and_change_no_bit() {
    let build = |threshold: usize, plain: bool, report: bool| {
        let mut w = World::new(WorldConfig {
            parallel_threshold: threshold,
            ..WorldConfig::default()
        })
        .expect("default method");
        w.add_force(Gravity::EARTH);
        let floor = w.add_collider(Plane::floor(0.0, bouncy()));
        let obstacle = w.add_collider(BoxCollider::solid(
            Vec3::new(-0.5, 0.0, -0.5),
            Vec3::new(0.5, 0.3, 0.5),
            bouncy(),
        ));
        w.add_collider(Plane::floor(-1.0, bouncy()));
        if plain {
            w.add_collider(ForcePlainPath);
        }
        if report {
            w.report_contacts(floor).expect("in the world");
            w.report_contacts(obstacle).expect("in the world");
        }
        for k in 0..2000u32 {
            let f = k as f32;
            w.spawn(Particle {
                position: Vec3::new((f * 0.37).sin() * 2.0, 0.4 + (f * 0.11) % 1.5, (f * 0.23).cos()),
                velocity: Vec3::new((f * 0.7).cos(), 0.0, (f * 0.5).sin()),
                radius: 0.01 * (k % 3) as f32,
                ..Particle::default()
            })
            .expect("valid");
        }
        w
    };
    let mut serial = build(usize::MAX, false, true);
    let mut lanes = build(0, false, true);
    let mut plain = build(usize::MAX, true, true);
    let mut silent = build(0, false, false);
    let obstacle = serial.colliders().nth(1).expect("three colliders").0;
    let mut seen = 0;
    let mut with_box = 0;
    for _ in 0..40 {
        for w in [&mut serial, &mut lanes, &mut plain, &mut silent] {
            step(w);
        }
        let contacts: &[Contact] = serial.contacts();
        assert_eq!(contacts, lanes.contacts(), "tick {}", serial.tick());
        assert_eq!(contacts, plain.contacts(), "tick {}", serial.tick());
        assert!(silent.contacts().is_empty());
        // The canonical order: by collider, then by row.
        let key = |c: &Contact| {
            let Touched::Collider(id) = c.touched else {
                panic!("no pairs here")
            };
            (id, serial.row(c.entity).expect("alive"))
        };
        assert!(contacts.windows(2).all(|p| key(&p[0]) < key(&p[1])));
        seen += contacts.len();
        with_box += contacts
            .iter()
            .filter(|c| c.touched == Touched::Collider(obstacle))
            .count();
        for (a, b) in serial
            .particles()
            .position
            .iter()
            .zip(silent.particles().position.iter())
        {
            assert_eq!(a.to_array().map(f32::to_bits), b.to_array().map(f32::to_bits));
        }
    }
    assert!(seen > 1000, "particles landed: {seen} contacts");
    assert!(with_box > 10, "some hit the box: {with_box}");
}

#[test]
fn colliding_spheres_report_the_pair_once_with_equal_and_opposite_impulses() {
    let mut w = World::default();
    let spheres = w.add_collider(SphereCollisions::new(Material {
        restitution: 1.0,
        friction: 0.0,
    }));
    w.report_contacts(spheres).expect("in the world");
    let left = w
        .spawn(Particle {
            position: Vec3::new(-0.5, 0.0, 0.0),
            velocity: Vec3::new(3.0, 0.0, 0.0),
            radius: 0.25,
            ..Particle::default()
        })
        .expect("valid");
    let right = w
        .spawn(Particle {
            position: Vec3::new(0.5, 0.0, 0.0),
            velocity: Vec3::new(-3.0, 0.0, 0.0),
            radius: 0.25,
            ..Particle::default()
        })
        .expect("valid");
    let mut pairs = Vec::new();
    for _ in 0..30 {
        step(&mut w);
        pairs.extend_from_slice(w.contacts());
    }
    let [hit] = pairs[..] else {
        panic!("one collision, got {pairs:?}");
    };
    // The lower row is the entity; the normal points towards it (-x).
    assert_eq!((hit.entity, hit.touched), (left, Touched::Entity(right)));
    assert!((hit.normal - Vec3::NEG_X).length() < 1e-6, "normal {}", hit.normal);
    // Elastic, equal masses: the velocities swap, J = m (1 + e) v_rel / 2 = 6.
    assert!((hit.impulse - 6.0).abs() < 1e-4, "impulse {}", hit.impulse);
    assert!((w.velocity(left).expect("alive").x + 3.0).abs() < 1e-5);
    assert!(hit.point.x.abs() < 0.06, "between the two: {}", hit.point);
}

#[test]
fn a_kinematic_box_moves_by_its_velocity_and_hands_it_to_what_it_hits() {
    let mut w = World::default();
    let paddle = w.add_collider(BoxCollider {
        velocity: Vec3::new(0.0, 2.0, 0.0),
        ..BoxCollider::solid(Vec3::new(-1.0, -0.2, -1.0), Vec3::new(1.0, 0.0, 1.0), bouncy())
    });
    w.report_contacts(paddle).expect("in the world");
    let ball = resting_ball(&mut w);
    let mut hit_at = None;
    for k in 0..30 {
        step(&mut w);
        if !w.contacts().is_empty() && hit_at.is_none() {
            hit_at = Some(k);
        }
    }
    let top = w.collider::<BoxCollider>(paddle).expect("a box").max.y;
    assert!(
        (top - 2.0 * 30.0 * DT as f32).abs() < 1e-5,
        "moved 2 m/s for 0.5 s: top at {top}"
    );
    // Resting ball, paddle rising at 2 m/s, e = 0.8: it leaves at u + e u = 3.6 m/s.
    let v = w.velocity(ball).expect("alive").y;
    assert!(
        hit_at.is_some() && (v - 3.6).abs() < 1e-4,
        "ball at {v} m/s after {hit_at:?}"
    );
    // Drawn between steps: a quarter step after the last, a box moving at
    // 2 m/s is 2 dt (1 - 1/4) behind where the step left it.
    let (min, _) = w
        .collider::<BoxCollider>(paddle)
        .expect("a box")
        .interpolated(0.25, DT as f32);
    assert!((min.y - (-0.2 + 1.0 - 2.0 * 0.75 * DT as f32)).abs() < 1e-5, "{min}");
}

#[test]
fn a_kinematic_plane_rises_and_hands_its_speed_to_what_it_hits() {
    let mut w = World::default();
    let piston = w.add_collider(Plane {
        speed: 2.0,
        ..Plane::floor(0.0, bouncy())
    });
    w.report_contacts(piston).expect("in the world");
    let ball = resting_ball(&mut w);
    let mut hits = Vec::new();
    for _ in 0..30 {
        step(&mut w);
        hits.extend(w.contacts().iter().map(|c| (c.touched, c.normal)));
    }
    let offset = w.collider::<Plane>(piston).expect("a plane").offset;
    assert!((offset - 1.0).abs() < 1e-5, "rose 2 m/s for 0.5 s: at {offset}");
    // The same law as the box: u + e u = 3.6 m/s for a ball at rest, once.
    let v = w.velocity(ball).expect("alive").y;
    assert!((v - 3.6).abs() < 1e-4, "ball at {v} m/s");
    assert_eq!(hits, [(Touched::Collider(piston), Vec3::Y)]);
    // Drawn a quarter step after the last, three quarters of a step below.
    let drawn = w
        .collider::<Plane>(piston)
        .expect("a plane")
        .interpolated_offset(0.25, DT as f32);
    assert!((drawn - (offset - 2.0 * 0.75 * DT as f32)).abs() < 1e-6, "{drawn}");
}

#[test]
fn collider_handles_change_remove_and_refuse_with_a_message() {
    let mut w = World::default();
    w.add_force(Gravity::EARTH);
    let floor = w.add_collider(Plane::floor(0.0, bouncy()));
    let brick = w.add_collider(BoxCollider::solid(Vec3::splat(-0.1), Vec3::splat(0.1), bouncy()));
    w.collider_mut::<Plane>(floor).expect("a plane").offset = -2.0;
    assert_eq!(w.collider::<Plane>(floor).expect("a plane").offset, -2.0);
    let wrong = w.collider::<Plane>(brick).expect_err("a box is not a plane");
    assert_eq!(wrong.to_string(), format!("{brick} is a box collider, not a Plane"));
    w.remove_collider(brick).expect("in the world");
    assert!(!w.has_collider(brick) && w.has_collider(floor));
    let gone = w.remove_collider(brick).expect_err("removed already");
    assert_eq!(gone, ColliderError::Unknown { id: brick });
    assert!(gone.to_string().contains("not in this world"), "{gone}");
    // A later collider gets a new handle; the floor keeps its own.
    let ceiling = Plane {
        normal: Vec3::NEG_Y,
        offset: -5.0,
        material: bouncy(),
        speed: 0.0,
        ..Plane::default()
    };
    let wall = w.add_collider(ceiling);
    assert!(wall != brick && wall != floor);
    let ids: Vec<_> = w.colliders().map(|(id, c)| (id, c.name())).collect();
    assert_eq!(ids, [(floor, "plane"), (wall, "plane")]);
    // The moved floor is the one particles meet.
    let ball = w.spawn(Particle::default()).expect("valid");
    let mut lowest = f32::INFINITY;
    for _ in 0..120 {
        step(&mut w);
        lowest = lowest.min(w.position(ball).expect("alive").y);
    }
    assert!(
        (-2.0..-1.9).contains(&lowest),
        "fell past 0 to the floor at -2: {lowest}"
    );
}

#[test]
fn collider_and_force_configs_have_the_defaults_their_fields_state() {
    use tickwork_engine::{BoxCollider, Gravity, Material, NBody};
    let plane = Plane::default();
    assert_eq!(
        (plane.normal, plane.offset, plane.material, plane.speed),
        (Vec3::Y, 0.0, Material::default(), 0.0)
    );
    let cube = BoxCollider::default();
    assert_eq!(
        (cube.min, cube.max, cube.inside, cube.material, cube.velocity),
        (
            Vec3::splat(-0.5),
            Vec3::splat(0.5),
            false,
            Material::default(),
            Vec3::ZERO
        )
    );
    assert_eq!(Gravity::default(), Gravity::EARTH);
    assert_eq!(NBody::default(), NBody::new(6.674e-11, 0.0));
    // A literal names only what it changes: a wall facing +x at x = -1
    // stops a particle moving left.
    let mut w = World::default();
    w.add_collider(Plane {
        normal: Vec3::X,
        offset: -1.0,
        ..Plane::default()
    });
    let ball = w
        .spawn(Particle {
            velocity: Vec3::new(-10.0, 0.0, 0.0),
            radius: 0.1,
            ..Particle::default()
        })
        .expect("spawn");
    for _ in 0..60 {
        step(&mut w);
    }
    let x = w.position(ball).expect("alive").x;
    assert!(x >= -1.0 + 0.1 - 1e-6, "the wall holds the ball at x = {x}");
}

#[test]
fn a_particle_resting_under_gravity_reports_its_contact_every_step_and_one_left_alone_none() {
    // Under gravity the floor stops a resting ball every step (the step
    // pulls it in, the floor puts it back): a contact each step, under
    // either rule. With nothing pulling it in, the floor leaves it alone:
    // no contact, as for a ball that does not touch.
    for contact in [
        tickwork_engine::ContactRule::InStep,
        tickwork_engine::ContactRule::EndOfStep,
    ] {
        for gravity in [true, false] {
            let mut w = World::new(WorldConfig::default()).expect("a world");
            if gravity {
                w.add_force(Gravity::EARTH);
            }
            let floor = w.add_collider(Plane {
                contact,
                ..Plane::floor(0.0, Material::default())
            });
            w.report_contacts(floor).expect("the floor");
            let ball = w
                .spawn(Particle {
                    position: Vec3::new(0.0, 0.1, 0.0),
                    radius: 0.1,
                    ..Particle::default()
                })
                .expect("valid");
            // Settled first: the first steps may bounce off rounding.
            for _ in 0..30 {
                step(&mut w);
            }
            let mut steps_with_a_contact = 0;
            for _ in 0..60 {
                step(&mut w);
                let contacts = w.contacts();
                assert!(contacts.len() <= 1, "{contact:?}: {contacts:?}");
                if let Some(c) = contacts.first() {
                    assert_eq!((c.entity, c.touched), (ball, Touched::Collider(floor)));
                    steps_with_a_contact += 1;
                }
            }
            let y = w.position(ball).expect("the ball").y;
            assert!((y - 0.1).abs() < 1e-3, "{contact:?}, gravity {gravity}: resting at {y}");
            let expected = if gravity { 60 } else { 0 };
            assert_eq!(
                steps_with_a_contact, expected,
                "{contact:?}, gravity {gravity}: steps with a contact of 60"
            );
        }
    }
}

//! Contacts found inside the step (`ContactRule::InStep`): an elastic ball
//! that keeps its height for 100 bounces, particles at any speed that never
//! pass through a wall, a thin box or a paddle moving at them, a ball that
//! comes to rest, the instant in the contact events, and the limit on
//! events; each against what the end-of-step rule does.
// Reference values computed natively (never in a page): the platform's own
// functions are fine here (clippy.toml bans them in the engine).
#![allow(clippy::disallowed_methods)]

use crate::support;

use glam::Vec3;
use proptest::prelude::*;
use tickwork_engine::clock::FixedStep;
use tickwork_engine::{
    BoxCollider, ContactOverflow, ContactRule, Entity, Gravity, Material, Particle, Plane, SimulationError, World,
    WorldConfig,
};

const G: f64 = 9.81;

fn world(integrator: &str) -> World {
    World::new(WorldConfig {
        integrator: integrator.into(),
        ..WorldConfig::default()
    })
    .expect("a known method")
}

fn step(w: &mut World, dt: f64) -> Result<(), SimulationError> {
    let tick = w.tick();
    w.step(FixedStep {
        tick,
        time: tick as f64 * dt,
        dt,
    })
    .map(|_| ())
}

/// [`world`] under gravity, `-G` along y.
fn under_gravity(integrator: &str) -> World {
    let mut w = world(integrator);
    w.add_force(Gravity {
        acceleration: Vec3::new(0.0, -G as f32, 0.0),
    });
    w
}

fn elastic() -> Material {
    Material {
        restitution: 1.0,
        friction: 0.0,
    }
}

/// A point ball dropped from rest at 10 m onto an elastic floor at 0, at
/// 60 Hz: the apex of each flight (its height plus `v^2 / 2g`, read at the
/// top of the flight, where the ball turns), over `bounces` bounces.
fn apexes(integrator: &str, rule: ContactRule, bounces: usize) -> Vec<f64> {
    apexes_less(integrator, rule, bounces, 0.0)
}

/// [`apexes`] with `v dt / 2 * shift` taken off each: with `shift` 1, the
/// height semi-implicit Euler keeps in free fall (`y + v^2 / 2g - v dt / 2`).
fn apexes_less(integrator: &str, rule: ContactRule, bounces: usize, shift: f64) -> Vec<f64> {
    let mut w = world(integrator);
    w.add_force(Gravity {
        acceleration: Vec3::new(0.0, -G as f32, 0.0),
    });
    w.add_collider(Plane {
        material: elastic(),
        contact: rule,
        ..Plane::default()
    });
    let ball = w
        .spawn(Particle {
            position: Vec3::new(0.0, 10.0, 0.0),
            ..Particle::default()
        })
        .expect("valid");
    let dt = 1.0 / 60.0;
    let mut out = Vec::new();
    let mut last_vy = 0.0f32;
    while out.len() < bounces {
        step(&mut w, dt).expect("steps");
        let (x, v) = (w.position(ball).expect("live"), w.velocity(ball).expect("live"));
        // The top: rising, then falling.
        if last_vy > 0.0 && v.y <= 0.0 {
            let vy = f64::from(v.y);
            out.push(f64::from(x.y) + vy * vy / (2.0 * G) - shift * vy * dt / 2.0);
        }
        last_vy = v.y;
        assert!(w.tick() < 100_000, "bounces on");
    }
    out
}

#[test]
fn an_elastic_ball_keeps_its_height_for_a_hundred_bounces_with_velocity_verlet() {
    // Velocity Verlet is exact for constant gravity between contacts; the
    // contact at its instant keeps it so. (The issue measured the end-of-
    // step rule: 10.08, 10.31, 10.55, 10.79 m over the first bounces.)
    let in_step = apexes("velocity_verlet", ContactRule::InStep, 100);
    let worst = in_step.iter().map(|a| (a - 10.0).abs()).fold(0.0, f64::max);
    assert!(
        (in_step[99] - 10.0).abs() < 1e-4 && worst < 1e-4,
        "apex after 100 bounces {} m, worst {worst:e} m off 10 m",
        in_step[99]
    );
    let end_of_step = apexes("velocity_verlet", ContactRule::EndOfStep, 4);
    assert!(
        end_of_step[3] > 10.5,
        "the end-of-step rule gains height: {end_of_step:?}"
    );
}

#[test]
fn an_elastic_ball_keeps_semi_implicit_eulers_own_energy_for_a_hundred_bounces() {
    // Semi-implicit Euler's velocity is half a step ahead of its position:
    // in free fall it keeps `y + v^2 / 2g - v dt / 2` exactly, not the
    // energy. Each bounce inside the step keeps that too (the restitution
    // of the method's own energy), so that height stays 10 m bounce after
    // bounce, to f32 rounding. (Reflecting the path's velocity instead,
    // it moved by up to `|v| dt` a bounce, 0.15 m here, alternating.)
    let dt = 1.0 / 60.0;
    let kept = apexes_less("semi_implicit_euler", ContactRule::InStep, 100, 1.0);
    let worst = kept.iter().map(|a| (a - 10.0).abs()).fold(0.0, f64::max);
    assert!(worst < 1e-4, "worst kept height {worst:e} m off 10 m: {:?}", &kept[..5]);
    // The energy's own height at the top of each flight, where `|v|`
    // is below `g dt`: within `g dt^2 / 2` of it.
    let apexes = apexes("semi_implicit_euler", ContactRule::InStep, 100);
    let bound = G * dt * dt / 2.0 + 1e-4;
    let worst = apexes.iter().map(|a| (a - 10.0).abs()).fold(0.0, f64::max);
    assert!(
        worst < bound,
        "worst apex {worst} m off 10 m, bound {bound}: {:?}",
        &apexes[..5]
    );
}

/// Which side of a wall at x = 0 (facing -x) a particle of radius `r`
/// fired at it from x = -5 ends on after `steps`, at `hz`; `wall` makes
/// the collider.
fn fire(speed: f32, hz: f64, r: f32, rule: ContactRule, wall: impl Fn(ContactRule) -> Wall) -> (Vec3, Vec3) {
    let mut w = world("semi_implicit_euler");
    match wall(rule) {
        Wall::Plane(p) => {
            w.add_collider(p);
        }
        Wall::Box(b) => {
            w.add_collider(b);
        }
    }
    let e = w
        .spawn(Particle {
            position: Vec3::new(-5.0, 0.0, 0.0),
            velocity: Vec3::new(speed, 0.0, 0.0),
            radius: r,
            ..Particle::default()
        })
        .expect("valid");
    let dt = 1.0 / hz;
    // Long enough to reach the wall and come back past the start.
    let steps = ((20.0 / f64::from(speed)) / dt).ceil() as usize + 3;
    for _ in 0..steps {
        step(&mut w, dt).expect("steps");
        let x = w.position(e).expect("live");
        assert!(
            x.x + r <= 1e-4,
            "at {speed} m/s, {hz} Hz: through the wall at x = {}",
            x.x
        );
    }
    (w.position(e).expect("live"), w.velocity(e).expect("live"))
}

enum Wall {
    Plane(Plane),
    Box(BoxCollider),
}

fn plane_wall(rule: ContactRule) -> Wall {
    Wall::Plane(Plane {
        normal: -Vec3::X,
        offset: 0.0,
        material: elastic(),
        contact: rule,
        ..Plane::default()
    })
}

fn thin_box(thickness: f32) -> impl Fn(ContactRule) -> Wall {
    move |rule| {
        Wall::Box(BoxCollider {
            min: Vec3::new(0.0, -1.0, -1.0),
            max: Vec3::new(thickness, 1.0, 1.0),
            material: elastic(),
            contact: rule,
            ..BoxCollider::default()
        })
    }
}

#[test]
fn no_particle_passes_a_wall_or_a_thin_box_at_any_speed() {
    for speed in [10.0, 100.0, 1_000.0, 10_000.0] {
        for hz in [30.0, 60.0, 240.0] {
            let (x, v) = fire(speed, hz, 0.005, ContactRule::InStep, plane_wall);
            assert!(
                v.x < 0.0 && x.x < -5.0,
                "{speed} m/s at {hz} Hz bounced back: x {x}, v {v}"
            );
            let (x, v) = fire(speed, hz, 0.005, ContactRule::InStep, thin_box(0.01));
            assert!(
                v.x < 0.0 && x.x < -5.0,
                "{speed} m/s at {hz} Hz bounced off the box: x {x}, v {v}"
            );
            assert!((v.x + speed).abs() <= 1e-3 * speed, "elastic: {v}");
        }
    }
}

#[test]
fn the_end_of_step_rule_lets_the_issues_bullet_through_a_ten_centimetre_box() {
    // The issue's case: 100 m/s at a box 10 cm thick, 60 Hz, r = 0.01:
    // ended a step just past the middle, pushed out through the far face.
    let mut w = world("semi_implicit_euler");
    w.add_collider(BoxCollider {
        min: Vec3::new(-0.05, -1.0, -1.0),
        max: Vec3::new(0.05, 1.0, 1.0),
        contact: ContactRule::EndOfStep,
        ..BoxCollider::default()
    });
    let e = w
        .spawn(Particle {
            position: Vec3::new(-5.0, 0.0, 0.0),
            velocity: Vec3::new(100.0, 0.0, 0.0),
            radius: 0.01,
            ..Particle::default()
        })
        .expect("valid");
    for _ in 0..3 {
        step(&mut w, 1.0 / 60.0).expect("steps");
    }
    assert!(w.position(e).expect("live").x > 0.05, "through");
}

#[test]
fn a_paddle_moving_at_a_fast_ball_hands_it_its_speed_and_is_never_passed() {
    for speed in [10.0f32, 100.0, 1_000.0, 10_000.0] {
        for hz in [30.0, 60.0, 240.0] {
            let mut w = world("semi_implicit_euler");
            let paddle_speed = -20.0f32;
            w.add_collider(BoxCollider {
                min: Vec3::new(1.0, -1.0, -1.0),
                max: Vec3::new(1.02, 1.0, 1.0),
                material: elastic(),
                velocity: Vec3::new(paddle_speed, 0.0, 0.0),
                contact: ContactRule::InStep,
                ..BoxCollider::default()
            });
            let e = w
                .spawn(Particle {
                    position: Vec3::new(-5.0, 0.0, 0.0),
                    velocity: Vec3::new(speed, 0.0, 0.0),
                    radius: 0.005,
                    ..Particle::default()
                })
                .expect("valid");
            let dt = 1.0 / hz;
            for _ in 0..((6.0 / f64::from(speed.min(20.0))) / dt).ceil() as usize {
                step(&mut w, dt).expect("steps");
                let paddle = w
                    .colliders()
                    .find_map(|(_, c)| c.as_any().downcast_ref::<BoxCollider>().copied());
                let min = paddle.expect("the paddle").min.x;
                let x = w.position(e).expect("live").x;
                assert!(
                    x + 0.005 <= min + 1e-3,
                    "{speed} m/s at {hz} Hz: x {x} past the paddle at {min}"
                );
            }
            // Elastic off a wall moving at u: v' = 2u - v.
            let v = w.velocity(e).expect("live").x;
            let wanted = 2.0 * paddle_speed - speed;
            assert!(
                (v - wanted).abs() <= 1e-3 * wanted.abs(),
                "{speed} m/s: {v} vs {wanted}"
            );
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, .. ProptestConfig::default() })]

    /// Random speeds, directions, thicknesses and rates: a particle fired
    /// at a solid box from outside it never ends a step inside it.
    #[test]
    fn a_particle_never_ends_a_step_inside_a_solid_box(
        speed in 1.0f32..20_000.0,
        direction in (-1.0f32..1.0, -0.3f32..0.3, -0.3f32..0.3),
        thickness in 0.001f32..0.5,
        hz in 20.0f64..500.0,
        restitution in 0.0f32..1.0,
    ) {
        let mut w = world("semi_implicit_euler");
        let (lo, hi) = (Vec3::new(0.0, -1.0, -1.0), Vec3::new(thickness, 1.0, 1.0));
        w.add_collider(BoxCollider {
            min: lo,
            max: hi,
            material: Material { restitution, friction: 0.0 },
            contact: ContactRule::InStep,
            ..BoxCollider::default()
        });
        let d = Vec3::new(1.0, direction.1, direction.2).normalize();
        let start = Vec3::new(-3.0 + direction.0, 0.0, 0.0);
        let r = 0.002;
        let e = w.spawn(Particle { position: start, velocity: d * speed, radius: r, ..Particle::default() }).expect("valid");
        let dt = 1.0 / hz;
        for _ in 0..((8.0 / f64::from(speed)) / dt).ceil() as usize + 2 {
            step(&mut w, dt).expect("steps");
            let x = w.position(e).expect("live");
            let inside = (0..3).all(|k| x[k] > lo[k] - r + 1e-4 && x[k] < hi[k] + r - 1e-4);
            prop_assert!(!inside, "inside the box at {x} ({speed} m/s, {hz} Hz, {thickness} m)");
            prop_assert!(!(x.x > hi.x && x.y.abs() < 1.0 && x.z.abs() < 1.0), "through the box to {x}");
        }
    }
}

/// A ball of radius 0.1 dropped from 1 m onto a floor of restitution 0.5,
/// semi-implicit Euler at 60 Hz; returns the world and the ball.
fn dropped_ball() -> (World, Entity, tickwork_engine::ColliderId) {
    let mut w = under_gravity("semi_implicit_euler");
    let floor = w.add_collider(Plane {
        material: Material {
            restitution: 0.5,
            friction: 0.2,
        },
        contact: ContactRule::InStep,
        ..Plane::default()
    });
    w.report_contacts(floor).expect("the floor");
    let ball = w
        .spawn(Particle {
            position: Vec3::new(0.0, 1.0, 0.0),
            velocity: Vec3::new(0.3, 0.0, 0.0),
            radius: 0.1,
            ..Particle::default()
        })
        .expect("valid");
    (w, ball, floor)
}

/// Points dropped with semi-implicit Euler onto a frictionless in-step
/// floor of restitution `e`, under gravity and drag, from up to 10 m with
/// vertical speeds up to 2 m/s: how many still bounce (off the floor, or
/// moving along its normal) after `seconds`.
fn still_bouncing(e: f32, seconds: f64) -> usize {
    let mut w = under_gravity("semi_implicit_euler");
    w.add_force(tickwork_engine::LinearDrag { rate: 0.1 });
    w.add_collider(Plane {
        contact: ContactRule::InStep,
        ..Plane::floor(
            0.0,
            Material {
                restitution: e,
                friction: 0.0,
            },
        )
    });
    let rows: Vec<_> = (0..400)
        .map(|k| {
            let f = k as f32;
            w.spawn(Particle {
                position: Vec3::new(f * 0.01, 0.05 + (f * 0.6180339).fract() * 10.0, 0.0),
                velocity: Vec3::new(0.0, (f * 0.4142135).fract() * 4.0 - 2.0, 0.0),
                radius: 0.0,
                ..Particle::default()
            })
            .expect("valid")
        })
        .collect();
    let dt = 1.0 / 60.0;
    for _ in 0..(seconds / dt) as usize {
        step(&mut w, dt).expect("steps");
    }
    rows.iter()
        .filter(|&&p| {
            let (x, v) = (w.position(p).expect("live"), w.velocity(p).expect("live"));
            x.y != 0.0 || v.y != 0.0
        })
        .count()
}

#[test]
fn short_hops_die_out_with_semi_implicit_euler_as_a_real_balls_do() {
    // A real ball of restitution e dropped onto the floor at speed u is at
    // rest after 2 u / (g (1 - e)) seconds (the hops' flights form a
    // geometric series); from 10 m at 2 m/s, u < 14.2 m/s: 14.5 s for
    // e = 0.8, 29 s for 0.9. Reflecting the path's velocity at the instant,
    // semi-implicit Euler's short hops gained what restitution took (the
    // method's velocity is half a step ahead), and 3 of these 400 points
    // at 0.8, 41 at 0.9, hopped on forever (as many after 120 s) at about
    // g dt / (1 - e).
    for (e, seconds) in [(0.8, 16.0), (0.9, 31.0)] {
        assert_eq!(still_bouncing(e, seconds), 0, "restitution {e} after {seconds} s");
    }
}

#[test]
fn a_ball_with_restitution_one_half_comes_to_rest_and_stays_on_the_surface() {
    let (mut w, ball, _) = dropped_ball();
    let dt = 1.0 / 60.0;
    let mut events = 0;
    let mut rested_at = None;
    for k in 0..10_000 {
        step(&mut w, dt).expect("steps");
        events += w.contacts().len();
        let (x, v) = (w.position(ball).expect("live"), w.velocity(ball).expect("live"));
        if rested_at.is_none() && x.y == 0.1 && v.y == 0.0 {
            rested_at = Some(k);
        }
        if let Some(at) = rested_at {
            assert!(
                (x.y - 0.1).abs() <= 1e-6 && v.y == 0.0,
                "step {k} (at rest since {at}): y {}, vy {}",
                x.y,
                v.y
            );
        }
        assert!(w.contacts().len() <= 1, "one event a step at most");
    }
    // Bounces from 4.2, 2.1, 1.05, 0.53 m/s, then at rest: within a second.
    let rested_at = rested_at.expect("comes to rest");
    assert!(rested_at < 90, "at rest after {rested_at} steps");
    // Friction stopped the sliding too (each resting step brakes it), to
    // the rounding of the path's f32 ends.
    let v = w.velocity(ball).expect("live");
    assert!(v.length() < 1e-5, "{v}");
    assert!(events <= 10_000, "{events} events");
}

#[test]
fn contact_events_carry_the_instant_of_contact() {
    // Dropped from 1 m (radius 0.1) the ball touches at t = sqrt(1.8 / g)
    // = 0.4284 s, in step 25 (0-based) at 60 Hz, fraction 0.70.
    let (mut w, _, floor) = dropped_ball();
    let dt = 1.0 / 60.0;
    let touch = (1.8 / G).sqrt();
    let mut found = None;
    for _ in 0..40 {
        let tick = w.tick();
        step(&mut w, dt).expect("steps");
        if let Some(c) = w.contacts().first() {
            found = Some((tick, *c));
            break;
        }
    }
    let (tick, contact) = found.expect("a contact");
    assert_eq!(contact.touched, tickwork_engine::Touched::Collider(floor));
    let when = (tick as f64 + f64::from(contact.fraction)) * dt;
    // Semi-implicit Euler's path is a step behind the exact fall: within a step.
    assert!((when - touch).abs() < dt, "contact at {when} s, theory {touch} s");
    assert!(contact.fraction > 0.0 && contact.fraction < 1.0, "{}", contact.fraction);
    assert!(
        (contact.normal - Vec3::Y).length() < 1e-6 && contact.impulse > 0.0,
        "{contact:?}"
    );
}

#[test]
fn velocity_verlet_events_are_at_the_exact_instant() {
    let mut w = under_gravity("velocity_verlet");
    let floor = w.add_collider(Plane {
        contact: ContactRule::InStep,
        ..Plane::default()
    });
    w.report_contacts(floor).expect("the floor");
    w.spawn(Particle {
        position: Vec3::new(0.0, 1.0, 0.0),
        radius: 0.1,
        ..Particle::default()
    })
    .expect("valid");
    let dt = 1.0 / 60.0;
    for _ in 0..40 {
        let tick = w.tick();
        step(&mut w, dt).expect("steps");
        if let Some(c) = w.contacts().first() {
            let when = (tick as f64 + f64::from(c.fraction)) * dt;
            assert!((when - (1.8 / G).sqrt()).abs() < 1e-6, "{when}");
            return;
        }
    }
    panic!("no contact");
}

#[test]
fn a_particle_that_would_need_more_events_than_the_limit_is_an_error_naming_it() {
    // Between two walls a millimetre apart at 1 000 m/s: 16 m a step, over
    // ten thousand bounces; a world that asks for the error.
    let mut w = World::new(WorldConfig {
        contact_overflow: ContactOverflow::Error,
        ..WorldConfig::default()
    })
    .expect("a world");
    for (normal, offset) in [(Vec3::X, -0.0005), (-Vec3::X, -0.0005)] {
        w.add_collider(Plane {
            normal,
            offset,
            material: elastic(),
            contact: ContactRule::InStep,
            ..Plane::default()
        });
    }
    let e = w
        .spawn(Particle {
            position: Vec3::ZERO,
            velocity: Vec3::new(1_000.0, 0.0, 0.0),
            radius: 0.0,
            ..Particle::default()
        })
        .expect("valid");
    let error = step(&mut w, 1.0 / 60.0).expect_err("past the limit");
    let SimulationError::ContactEventLimit { entity, limit, .. } = error.clone() else {
        panic!("{error}");
    };
    assert_eq!((entity, limit), (e, tickwork_engine::colliders::MAX_CONTACT_EVENTS));
    let message = error.to_string();
    assert!(
        message.contains(&format!("entity {e} met more than 16 contacts in one step")) && message.contains("plane"),
        "{message}"
    );
}

#[test]
fn a_ball_a_paddle_pins_against_a_wall_is_left_to_the_end_of_step_rule_and_named() {
    // A paddle sweeping at 3 m/s towards a wall, stopped there as a game
    // stops it, a ball between: it bounces ever faster between the two as
    // they close (each bounce off the paddle adds 6 m/s), past the limit;
    // by default the step goes on, names it, and every step succeeds.
    let mut w = world("semi_implicit_euler");
    w.add_collider(Plane {
        normal: Vec3::NEG_X,
        offset: -1.0,
        material: elastic(),
        ..Plane::default()
    });
    let paddle = w.add_collider(BoxCollider {
        velocity: Vec3::new(3.0, 0.0, 0.0),
        material: elastic(),
        ..BoxCollider::solid(Vec3::new(-1.0, -0.5, -0.5), Vec3::new(0.0, 0.5, 0.5), elastic())
    });
    let ball = w
        .spawn(Particle {
            position: Vec3::new(0.5, 0.0, 0.0),
            radius: 0.05,
            ..Particle::default()
        })
        .expect("valid");
    let dt = 1.0 / 60.0;
    let mut named = Vec::new();
    for tick in 0..40u64 {
        let x = w.collider::<BoxCollider>(paddle).expect("the paddle").max.x;
        let to = (x + 3.0 * dt as f32).min(1.0);
        w.collider_mut::<BoxCollider>(paddle).expect("the paddle").velocity.x = (to - x) / dt as f32;
        let report = w
            .step(tickwork_engine::FixedStep {
                tick,
                time: tick as f64 * dt,
                dt,
            })
            .unwrap_or_else(|e| panic!("tick {tick}: {e}"));
        if let Some(entity) = report.contact_overflow {
            named.push((tick, entity));
        }
        let (x, v) = (w.position(ball).expect("live"), w.velocity(ball).expect("live"));
        assert!(x.is_finite() && v.is_finite(), "tick {tick}: {x} {v}");
    }
    assert!(!named.is_empty(), "no step passed the limit");
    assert!(named.iter().all(|&(_, e)| e == ball), "{named:?}");
}

/// `run` on a pool of `threads` threads.
fn on_threads<R: Send>(threads: usize, run: impl FnOnce() -> R + Send) -> R {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a pool")
        .install(run)
}

/// One 60 Hz step, asserting the path it took: in-step colliders are
/// pointwise, so the fused path takes them unless `plain` forced the other.
fn step_on_path(w: &mut World, plain: bool) {
    let tick = w.tick();
    let report = w
        .step(FixedStep {
            tick,
            time: tick as f64 / 60.0,
            dt: 1.0 / 60.0,
        })
        .expect("steps");
    assert_eq!(report.fused, !plain, "the path taken");
}

/// The state's hash, leaving out the collider that forced the plain path.
fn hash_on_path(w: &mut World, plain: bool) -> u64 {
    if plain {
        support::hash_without_plain_path(w)
    } else {
        w.state_hash()
    }
}

/// A crowd of fast particles in a box over a floor, both in-step, with
/// contacts reported: the world after 60 steps at 60 Hz.
fn crowd(threads: usize, plain: bool) -> (u64, Vec<tickwork_engine::Contact>) {
    on_threads(threads, || {
        let mut w = under_gravity("semi_implicit_euler");
        let floor = w.add_collider(Plane {
            contact: ContactRule::InStep,
            ..Plane::default()
        });
        w.add_collider(BoxCollider {
            min: Vec3::new(-2.0, -1.0, -2.0),
            max: Vec3::new(2.0, 10.0, 2.0),
            inside: true,
            contact: ContactRule::InStep,
            ..BoxCollider::default()
        });
        w.report_contacts(floor).expect("the floor");
        if plain {
            w.add_collider(support::ForcePlainPath);
        }
        for k in 0..6_000 {
            let f = k as f32;
            w.spawn(Particle {
                position: Vec3::new(
                    (f * 0.37).sin() * 1.5,
                    1.0 + (f * 0.11).fract() * 8.0,
                    (f * 0.53).cos() * 1.5,
                ),
                velocity: Vec3::new((f * 0.7).sin() * 30.0, (f * 0.3).cos() * 30.0, (f * 0.9).sin() * 30.0),
                radius: 0.02,
                ..Particle::default()
            })
            .expect("valid");
        }
        let mut contacts = Vec::new();
        for _ in 0..60 {
            step_on_path(&mut w, plain);
            contacts.extend_from_slice(w.contacts());
        }
        (hash_on_path(&mut w, plain), contacts)
    })
}

#[test]
fn in_step_contacts_are_the_same_bits_on_any_threads_and_either_path() {
    let fused = crowd(1, false);
    assert!(fused.1.len() > 1_000, "the floor is hit: {}", fused.1.len());
    assert!(fused.1.iter().any(|c| c.fraction < 1.0), "at instants inside the step");
    assert_eq!(fused, crowd(3, false), "fused, 1 and 3 threads");
    assert_eq!(fused, crowd(1, true), "fused and plain");
    assert_eq!(fused, crowd(3, true), "plain on 3 threads");
}

/// 4 001 particles (a short last block) dropped from up to 30 cm onto a
/// lone in-step floor with friction that does not report (the floor
/// settles and resolves whole blocks in one pass), on `threads` threads,
/// fused or plain: the state's hash after 2 s, and how many rest on the
/// floor (exactly on it, no normal velocity).
fn resting_crowd(threads: usize, plain: bool) -> (u64, usize) {
    settling_crowd(threads, plain, 0.3, 0.3)
}

/// [`resting_crowd`] with the floor's `friction`, dropped from up to
/// `height`: chunks clear of the floor whole, resting on it whole, and
/// partly each (the fused path takes the first two whole, the plain path
/// decides every particle alone).
fn settling_crowd(threads: usize, plain: bool, friction: f32, height: f32) -> (u64, usize) {
    on_threads(threads, || {
        let mut w = under_gravity("semi_implicit_euler");
        w.add_collider(Plane {
            contact: ContactRule::InStep,
            ..Plane::floor(
                0.0,
                Material {
                    restitution: 0.5,
                    friction,
                },
            )
        });
        if plain {
            w.add_collider(support::ForcePlainPath);
        }
        let n = 4_001;
        let rows: Vec<_> = (0..n)
            .map(|k| {
                let f = k as f32;
                w.spawn(Particle {
                    position: Vec3::new(
                        (f * 0.37).sin() * 3.0,
                        0.02 + (f * 0.11).fract() * height,
                        (f * 0.53).cos() * 3.0,
                    ),
                    velocity: Vec3::new((f * 0.7).sin(), (f * 0.3).cos() * 0.5, 0.0),
                    radius: 0.02,
                    ..Particle::default()
                })
                .expect("valid")
            })
            .collect();
        for _ in 0..120 {
            step_on_path(&mut w, plain);
        }
        let resting = rows
            .iter()
            .filter(|&&e| w.position(e).expect("live").y == 0.02 && w.velocity(e).expect("live").y == 0.0)
            .count();
        (hash_on_path(&mut w, plain), resting)
    })
}

#[test]
fn particles_resting_on_a_lone_floor_are_the_same_bits_on_any_threads_and_either_path() {
    let fused = resting_crowd(1, false);
    assert!(fused.1 > 3_900, "at rest on the floor after 2 s: {} of 4 001", fused.1);
    assert_eq!(fused, resting_crowd(2, false), "fused, 1 and 2 threads");
    assert_eq!(fused, resting_crowd(1, true), "fused and plain");
}

#[test]
fn particles_settling_on_a_frictionless_floor_are_the_same_bits_on_either_path() {
    for height in [0.3, 5.0] {
        let fused = settling_crowd(1, false, 0.0, height);
        assert!(
            fused.1 > 1_000,
            "from {height} m, at rest after 2 s: {} of 4 001",
            fused.1
        );
        assert_eq!(fused, settling_crowd(2, false, 0.0, height), "fused, 1 and 2 threads");
        assert_eq!(fused, settling_crowd(1, true, 0.0, height), "fused and plain");
    }
}

/// 4 001 particles at rest on a lone frictionless in-step floor, one in
/// 37 thrown down at it from up to 2 m at 5 m/s, so that in chunks whose
/// first particles rest a later one strikes the floor fast (the floor
/// resolves the resting blocks whole and must stop at the striking one),
/// on `threads` threads; with `reporting`, the floor reports its contacts,
/// which makes it decide every block alone (no whole chunks): every
/// particle's state after 1 s as bits, and the fast bounces seen. With
/// `layered`, every particle is thrown, each chunk of 512 from its own
/// layer (1 m above the last, half a metre deep), so that whole chunks are
/// clear of the floor for some steps and then strike it one by one. The
/// particles' radius is `radius` (resting ones start that far up). `up`
/// -1 turns the world upside down: a ceiling facing -y, gravity up.
fn rain_on_resting(threads: usize, reporting: bool, layered: bool, radius: f32, up: f32) -> (Vec<[u32; 6]>, usize) {
    on_threads(threads, || {
        let mut w = world("semi_implicit_euler");
        w.add_force(Gravity {
            acceleration: Vec3::new(0.0, -G as f32 * up, 0.0),
        });
        let floor = w.add_collider(Plane {
            normal: Vec3::new(0.0, up, 0.0),
            contact: ContactRule::InStep,
            ..Plane::floor(
                0.0,
                Material {
                    restitution: 0.8,
                    friction: 0.0,
                },
            )
        });
        if reporting {
            w.report_contacts(floor).expect("the floor");
        }
        let rows: Vec<_> = (0..4_001)
            .map(|k| {
                let f = k as f32;
                let thrown = layered || k % 37 == 5;
                let height = if layered {
                    0.5 + (k / 512) as f32 + (f * 0.11).fract() * 0.5
                } else if thrown {
                    radius + (f * 0.11).fract() * 2.0
                } else {
                    radius
                };
                w.spawn(Particle {
                    position: Vec3::new((f * 0.37).sin() * 3.0, height * up, (f * 0.53).cos() * 3.0),
                    velocity: Vec3::new(0.0, if thrown { -5.0 * up } else { 0.0 }, 0.0),
                    radius,
                    ..Particle::default()
                })
                .expect("valid")
            })
            .collect();
        let mut bounced = 0;
        for _ in 0..60 {
            step_on_path(&mut w, false);
            // Thrown particles leaving the floor upwards fast: bounced.
            bounced += rows
                .iter()
                .filter(|&&e| w.position(e).expect("live").y * up < 0.2 && w.velocity(e).expect("live").y * up > 2.0)
                .count();
        }
        let states = rows
            .iter()
            .map(|&e| {
                let (x, v) = (w.position(e).expect("live"), w.velocity(e).expect("live"));
                [x.x, x.y, x.z, v.x, v.y, v.z].map(f32::to_bits)
            })
            .collect();
        (states, bounced)
    })
}

#[test]
fn fast_particles_among_resting_ones_are_the_same_bits_whole_chunk_or_block_by_block() {
    // Point particles (radius 0) take loops of their own.
    for (layered, radius) in [(false, 0.02), (true, 0.02), (false, 0.0)] {
        let whole = rain_on_resting(1, false, layered, radius, 1.0);
        assert!(whole.1 > 50, "thrown particles bounced: {}", whole.1);
        assert!(
            whole == rain_on_resting(2, false, layered, radius, 1.0),
            "1 and 2 threads"
        );
        assert!(
            whole == rain_on_resting(1, true, layered, radius, 1.0),
            "whole chunks and block by block (layered: {layered}, radius {radius})"
        );
    }
    // Upside down (a ceiling, facing -y, gravity up): the same values with
    // the sign of every y and v_y flipped (not the same bits: a particle
    // put back on either surface is at `y - y = +0`).
    let floor = rain_on_resting(1, false, false, 0.0, 1.0);
    let ceiling = rain_on_resting(1, false, false, 0.0, -1.0);
    let flip = |s: &[u32; 6]| {
        let v = s.map(f32::from_bits);
        [v[0], -v[1], v[2], v[3], -v[4], v[5]]
    };
    let values = |s: &[u32; 6]| s.map(f32::from_bits);
    assert!(
        ceiling.0.iter().map(flip).eq(floor.0.iter().map(values)),
        "a ceiling is a floor upside down"
    );
    assert_eq!(ceiling.1, floor.1);
    assert!(
        ceiling == rain_on_resting(1, true, false, 0.0, -1.0),
        "the ceiling block by block"
    );
}

/// A bullet (radius 1 cm) fired at `speed` from x = -5 at a heavy ball of
/// radius 0.1 at rest at the origin, with sphere collisions swept or not,
/// at `hz`: the bullet's velocity at the end, and whether it was ever past
/// the ball's centre.
fn bullet_at_a_ball(speed: f32, hz: f64, swept: bool) -> (Vec3, bool, Vec<tickwork_engine::Contact>) {
    let mut w = world("semi_implicit_euler");
    let mut spheres = tickwork_engine::SphereCollisions::new(elastic());
    spheres.swept = swept;
    let id = w.add_collider(spheres);
    w.report_contacts(id).expect("the spheres");
    w.spawn(Particle {
        position: Vec3::ZERO,
        radius: 0.1,
        mass: 1e6,
        ..Particle::default()
    })
    .expect("valid");
    let bullet = w
        .spawn(Particle {
            position: Vec3::new(-5.0, 0.0, 0.0),
            velocity: Vec3::new(speed, 0.0, 0.0),
            radius: 0.01,
            ..Particle::default()
        })
        .expect("valid");
    let dt = 1.0 / hz;
    let mut past = false;
    let mut contacts = Vec::new();
    for _ in 0..((10.0 / f64::from(speed)) / dt).ceil() as usize + 2 {
        step(&mut w, dt).expect("steps");
        past |= w.position(bullet).expect("live").x > 0.0;
        contacts.extend_from_slice(w.contacts());
    }
    (w.velocity(bullet).expect("live"), past, contacts)
}

#[test]
fn a_bullet_passes_through_a_ball_between_two_instants_unless_spheres_are_swept() {
    // Without swept tests, 1 000 m/s at 60 Hz is 16.7 m a step: the bullet
    // is never seen touching the ball.
    let (v, past, contacts) = bullet_at_a_ball(1_000.0, 60.0, false);
    assert!(past && v.x == 1_000.0 && contacts.is_empty(), "{v} {past}");
    for speed in [10.0, 100.0, 1_000.0, 10_000.0] {
        for hz in [30.0, 60.0, 240.0] {
            let (v, past, contacts) = bullet_at_a_ball(speed, hz, true);
            assert!(!past, "{speed} m/s at {hz} Hz went through");
            assert!(
                (v.x + speed).abs() < 1e-3 * speed,
                "{speed} m/s at {hz} Hz bounced back: {v}"
            );
            let hit = contacts.first().expect("the hit is reported");
            assert!(
                hit.fraction >= 0.0 && hit.fraction <= 1.0 && hit.impulse.abs() > 0.0,
                "{hit:?}"
            );
        }
    }
    // Where the grid sees the contact anyway (a slow bullet), the same.
    let (v, past, _) = bullet_at_a_ball(0.5, 60.0, true);
    assert!(!past && v.x < 0.0, "{v}");
}

/// One step of one particle from `x0` at `v` (no forces: the method's
/// end velocity is `v`) against `collider`, on the fused path and on the
/// plain one: the two outcomes, which must be the same bits.
fn fused_and_plain(collider: Plane, x0: Vec3, v: Vec3, radius: f32) -> [(Result<(), String>, u64); 2] {
    [false, true].map(|plain| {
        let mut w = world("semi_implicit_euler");
        w.add_collider(collider);
        if plain {
            w.add_collider(support::ForcePlainPath);
        }
        w.spawn(Particle {
            position: x0,
            velocity: v,
            radius,
            ..Particle::default()
        })
        .expect("valid");
        let outcome = step(&mut w, 1.0 / 60.0).map_err(|e| e.to_string());
        let hash = if plain {
            support::hash_without_plain_path(&mut w)
        } else {
            w.state_hash()
        };
        (outcome, hash)
    })
}

#[test]
fn a_slanted_plane_far_from_the_origin_is_met_the_same_on_both_paths() {
    // Found by a second reading: the clearance test's rounding margin
    // followed the dot product's value, not its terms' sizes, so far from
    // the origin a particle that grazes a 45 degree plane was passed over
    // on the fused path and bounced on the plain one.
    let plane = Plane {
        normal: Vec3::new(1.0, 1.0, 0.0).normalize(),
        contact: ContactRule::InStep,
        ..Plane::default()
    };
    let x0 = Vec3::new(901.410_16, -900.970_34, 0.0);
    let v = Vec3::new(0.0, -0.010_986_327, 0.0);
    let [fused, plain] = fused_and_plain(plane, x0, v, 0.310_901_73);
    assert_eq!(fused, plain);
    assert!(fused.0.is_ok());
}

#[test]
fn a_particle_resting_on_a_floor_still_meets_a_thin_wall_it_slides_into() {
    // Found by a second reading: resting on one in-step surface ended the
    // particle's step, so a thin in-step box it slid into was never asked.
    let mut w = under_gravity("semi_implicit_euler");
    w.add_collider(Plane {
        contact: ContactRule::InStep,
        ..Plane::default()
    });
    w.add_collider(BoxCollider {
        min: Vec3::new(1.0, 0.0, -1.0),
        max: Vec3::new(1.01, 1.0, 1.0),
        material: elastic(),
        contact: ContactRule::InStep,
        ..BoxCollider::default()
    });
    let e = w
        .spawn(Particle {
            position: Vec3::new(0.4, 0.05, 0.0),
            velocity: Vec3::new(30.0, 0.0, 0.0),
            radius: 0.05,
            ..Particle::default()
        })
        .expect("valid");
    for _ in 0..20 {
        step(&mut w, 1.0 / 60.0).expect("steps");
        let x = w.position(e).expect("live");
        assert!(x.x <= 1.0 - 0.05 + 1e-4, "through the wall to {x}");
    }
    assert!(w.velocity(e).expect("live").x < 0.0, "bounced back");
}

/// 4 001 particles (radius 0.02) over and around an in-step box at rest,
/// on `threads` threads, fused or plain, under gravity, for 3 s: a solid
/// platform from y = -1 to 0 (`inside` false), or a room whose floor is at
/// y = -1 (`inside` true). Most drop from up to 30 cm onto its top (or
/// floor) with small sideways speeds, so they come to rest there, slide,
/// or fall off an edge; one in 23 is thrown at the box fast from any side,
/// below included. Every step checks that no particle is inside the solid
/// box or has left the room; returns the state's hash and how many rest
/// exactly on the top (or the floor).
fn box_crowd(threads: usize, plain: bool, inside: bool, friction: f32) -> (u64, usize) {
    on_threads(threads, || {
        let mut w = under_gravity("semi_implicit_euler");
        let material = Material {
            restitution: 0.5,
            friction,
        };
        let (lo, hi) = if inside {
            (Vec3::new(-2.0, -1.0, -2.0), Vec3::new(2.0, 3.0, 2.0))
        } else {
            (Vec3::new(-2.0, -1.0, -2.0), Vec3::new(2.0, 0.0, 2.0))
        };
        w.add_collider(BoxCollider {
            min: lo,
            max: hi,
            inside,
            material,
            contact: ContactRule::InStep,
            ..BoxCollider::default()
        });
        if plain {
            w.add_collider(support::ForcePlainPath);
        }
        let r = 0.02;
        let surface = if inside { lo.y + r } else { hi.y + r };
        let rows: Vec<_> = (0..4_001)
            .map(|k| {
                let f = k as f32;
                // On the room's floor, within it; on the platform, a little
                // past its edges too.
                let spread = if inside { 1.9 } else { 2.3 };
                let (x, z) = ((f * 0.37).sin() * spread, (f * 0.53).cos() * spread);
                let (position, velocity) = if k % 23 == 7 {
                    // Thrown at the box's middle from 1.5 m away, any side.
                    let dir = Vec3::new((f * 0.71).sin(), (f * 0.29).cos(), (f * 0.43).sin()).normalize();
                    let centre = (lo + hi) * 0.5;
                    let from = if inside { centre + dir * 1.5 } else { centre - dir * 3.5 };
                    let to = if inside { dir } else { (centre - from).normalize() };
                    (from, to * (20.0 + (f * 0.13).fract() * 200.0))
                } else {
                    (
                        Vec3::new(x, surface + (f * 0.11).fract() * 0.3, z),
                        Vec3::new((f * 0.7).sin() * 0.3, 0.0, (f * 0.9).cos() * 0.3),
                    )
                };
                w.spawn(Particle {
                    position,
                    velocity,
                    radius: r,
                    ..Particle::default()
                })
                .expect("valid")
            })
            .collect();
        for step in 0..180 {
            step_on_path(&mut w, plain);
            for &e in &rows {
                let p = w.position(e).expect("live");
                let within = (0..3).all(|k| p[k] > lo[k] - r + 1e-3 && p[k] < hi[k] + r - 1e-3);
                if inside {
                    let contained = (0..3).all(|k| p[k] >= lo[k] + r - 1e-4 && p[k] <= hi[k] - r + 1e-4);
                    assert!(contained, "step {step}: {p} left the room");
                } else {
                    assert!(!within, "step {step}: {p} inside the platform");
                }
            }
        }
        let resting = rows
            .iter()
            .filter(|&&e| w.position(e).expect("live").y == surface && w.velocity(e).expect("live").y == 0.0)
            .count();
        (hash_on_path(&mut w, plain), resting)
    })
}

#[test]
fn particles_resting_on_a_box_are_the_same_bits_on_any_threads_and_either_path_and_never_pass_it() {
    for inside in [false, true] {
        for friction in [0.0, 0.3] {
            let fused = box_crowd(1, false, inside, friction);
            // Some slide off the platform's edges, or are thrown.
            let least = if inside { 3_500 } else { 1_000 };
            assert!(
                fused.1 > least,
                "at rest on the box (inside: {inside}, friction {friction}): {} of 4 001",
                fused.1
            );
            assert_eq!(fused, box_crowd(2, false, inside, friction), "1 and 2 threads");
            assert_eq!(fused, box_crowd(1, true, inside, friction), "fused and plain");
        }
    }
}

#[test]
fn a_particle_resting_at_a_boxs_top_edge_stays_on_the_top() {
    // Its centre 1 mm inside the edge of the box grown by its radius:
    // sinking 2.7 mm a step under gravity, it ends each step deeper through
    // the top than through the side, where the end-of-step rule would push
    // it out sideways, off the edge. Inside the step it meets the top first
    // and rests on it.
    let mut w = under_gravity("semi_implicit_euler");
    w.add_collider(BoxCollider {
        min: Vec3::new(-1.0, -1.0, -1.0),
        max: Vec3::new(1.0, 0.0, 1.0),
        material: Material {
            restitution: 0.5,
            friction: 0.0,
        },
        contact: ContactRule::InStep,
        ..BoxCollider::default()
    });
    let r = 0.05;
    let start = Vec3::new(1.0 + r - 1e-3, r, 0.0);
    let e = w
        .spawn(Particle {
            position: start,
            radius: r,
            ..Particle::default()
        })
        .expect("valid");
    for k in 0..60 {
        step(&mut w, 1.0 / 60.0).expect("steps");
        let (x, v) = (w.position(e).expect("live"), w.velocity(e).expect("live"));
        // On the top where it was, still (to the f64 path's rounding).
        assert!(
            x.x == start.x && (x.y - r).abs() < 1e-6 && v.length() < 1e-5,
            "step {k}: at {x}, moving {v}"
        );
    }
}

#[test]
fn particles_at_rest_before_a_fast_kinematic_paddle_are_carried_not_passed() {
    // A paddle 2 cm thick sweeping +x at 100 m/s (1.7 m a step at 60 Hz)
    // into particles at rest, no gravity: every one is struck and leaves
    // at twice its speed or more (restitution 1), none is left behind it.
    let mut w = world("semi_implicit_euler");
    w.add_collider(BoxCollider {
        min: Vec3::new(-3.02, -1.0, -1.0),
        max: Vec3::new(-3.0, 1.0, 1.0),
        velocity: Vec3::new(100.0, 0.0, 0.0),
        material: elastic(),
        contact: ContactRule::InStep,
        ..BoxCollider::default()
    });
    let rows: Vec<_> = (0..64)
        .map(|k| {
            let f = k as f32;
            w.spawn(Particle {
                position: Vec3::new(
                    (f * 0.37).fract() * 2.0,
                    (f * 0.61).fract() - 0.5,
                    (f * 0.29).fract() - 0.5,
                ),
                radius: 0.01,
                ..Particle::default()
            })
            .expect("valid")
        })
        .collect();
    for _ in 0..6 {
        step(&mut w, 1.0 / 60.0).expect("steps");
    }
    for &e in &rows {
        let v = w.velocity(e).expect("live");
        assert!(v.x >= 199.0, "struck: {v} at {}", w.position(e).expect("live"));
    }
}

#[test]
fn a_floor_of_restitution_zero_never_sends_a_ball_up() {
    // Dropped from heights that meet the floor at every fraction of a
    // step, at up to 14 m/s: from its first contact on, the ball is on the
    // floor with no normal velocity (semi-implicit Euler's own energy is
    // scaled by e^2 = 0 there, whatever the fraction).
    for k in 0..40 {
        let mut w = under_gravity("semi_implicit_euler");
        w.add_collider(Plane {
            contact: ContactRule::InStep,
            ..Plane::floor(
                0.0,
                Material {
                    restitution: 0.0,
                    friction: 0.0,
                },
            )
        });
        let height = 0.3 + k as f32 * 0.25;
        let ball = w
            .spawn(Particle {
                position: Vec3::new(0.0, height, 0.0),
                radius: 0.0,
                ..Particle::default()
            })
            .expect("valid");
        let mut landed = None;
        for step_k in 0..200 {
            step(&mut w, 1.0 / 60.0).expect("steps");
            let (x, v) = (w.position(ball).expect("live"), w.velocity(ball).expect("live"));
            // Falling every step until the contact's step.
            if landed.is_none() && v.y >= 0.0 {
                landed = Some(step_k);
            }
            if landed.is_some() {
                // (To the f64 path's rounding in the contact's step.)
                assert!(
                    x.y.abs() < 1e-6 && v.y.abs() < 1e-5,
                    "from {height} m, step {step_k}: at {x}, moving {v}"
                );
            }
        }
        assert!(landed.is_some(), "from {height} m: landed");
    }
}

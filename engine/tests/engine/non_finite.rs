//! Non-finite values and runaway requests are errors that say what is known:
//! the entity and field, whether the state was bad before the step, the
//! force that diverged, the limit that was passed.

use glam::Vec3;
use tickwork_engine::clock::FixedStep;
use tickwork_engine::{Attractor, Emitter, NonFiniteCause, Particle, SimulationError, World, WorldConfig};

fn world(integrator: &str) -> World {
    World::new(WorldConfig {
        integrator: integrator.into(),
        ..WorldConfig::default()
    })
    .expect("registered")
}

fn step(w: &mut World) -> Result<(), SimulationError> {
    let tick = w.tick();
    w.step(FixedStep {
        tick,
        time: tick as f64 / 60.0,
        dt: 1.0 / 60.0,
    })
    .map(|_| ())
}

#[test]
fn a_nan_force_is_named_by_every_kind_of_method() {
    // A particle exactly on an unsoftened attractor: 0 / 0. Implicit Euler
    // once said "did not converge after 0 Newton iterations ... try a smaller
    // time step", Dormand-Prince "gave up after 132 sub-steps".
    for method in [
        "semi_implicit_euler",
        "implicit_euler",
        "trapezoidal",
        "dormand_prince",
        "rk4",
    ] {
        let mut w = world(method);
        w.add_force(Attractor {
            position: Vec3::ZERO,
            gm: 1.0,
            softening: 0.0,
        });
        let _calm = w
            .spawn(Particle {
                position: Vec3::X,
                ..Particle::default()
            })
            .expect("valid");
        let centre = w.spawn(Particle::default()).expect("valid");
        let error = step(&mut w).expect_err("a NaN acceleration");
        match &error {
            SimulationError::NonFinite { entity, field, .. } => {
                assert_eq!(*entity, centre, "{method}: {error}");
                assert!(
                    ["acceleration", "velocity", "position"].contains(field),
                    "{method}: {error}"
                );
            }
            other => panic!("{method}: expected a non-finite error, got {other}"),
        }
        assert!(
            error.to_string().contains(&format!("{centre} has a non-finite")),
            "{method}: {error}"
        );
    }
    // The solvers' failure is traced to the force.
    let mut w = world("implicit_euler");
    w.add_force(Attractor {
        position: Vec3::ZERO,
        gm: 1.0,
        softening: 0.0,
    });
    let centre = w.spawn(Particle::default()).expect("valid");
    let error = step(&mut w).expect_err("a NaN acceleration");
    assert!(
        matches!(
            error,
            SimulationError::NonFinite {
                field: "acceleration",
                cause: NonFiniteCause::Force,
                ..
            }
        ),
        "{error}"
    );
    assert!(
        error
            .to_string()
            .ends_with("the forces gave it at a finite position and velocity"),
        "{error}"
    );
    let _ = centre;
}

#[test]
fn a_nan_written_through_particles_mut_is_blamed_on_the_write_not_the_step() {
    let mut w = world("semi_implicit_euler");
    let e = w.spawn(Particle::default()).expect("valid");
    step(&mut w).expect("a finite step");
    let velocity = &mut w.particles_mut().velocity;
    let v = velocity.get(0).expect("one row");
    assert!(velocity.set(0, glam::Vec3A::new(v.x, f32::NAN, v.z)));
    let error = step(&mut w).expect_err("a NaN velocity");
    assert!(
        matches!(error, SimulationError::NonFinite { entity, field: "velocity", cause: NonFiniteCause::Start, .. } if entity == e),
        "{error}"
    );
    assert!(error.to_string().contains("it was so before the step began"), "{error}");
}

#[test]
fn a_step_with_a_nan_time_is_an_error() {
    let mut w = world("semi_implicit_euler");
    w.spawn(Particle::default()).expect("valid");
    let error = w
        .step(FixedStep {
            tick: 0,
            time: f64::NAN,
            dt: 1.0 / 60.0,
        })
        .expect_err("refused");
    assert_eq!(
        error.to_string(),
        "step 0: invalid fixed step: time NaN s, dt 0.016666666666666666 s (both must be finite)"
    );
}

#[test]
fn emitters_refuse_a_zero_direction_and_an_infinite_speed() {
    let mut w = world("semi_implicit_euler");
    let error = w
        .add_emitter(Emitter {
            direction: Vec3::ZERO,
            ..Emitter::default()
        })
        .expect_err("a zero direction");
    assert!(
        error.to_string().starts_with("invalid particle emitter.direction: 0"),
        "{error}"
    );
    let error = w
        .add_emitter(Emitter {
            speed: 3e38,
            ..Emitter::default()
        })
        .expect_err("an infinite jittered speed");
    assert!(error.to_string().contains("emitter.speed"), "{error}");
}

#[test]
fn an_emitter_past_the_spawn_limit_is_an_error_naming_the_limit() {
    let mut w = world("semi_implicit_euler");
    let falling = w
        .spawn(Particle {
            velocity: Vec3::new(0.0, -1.0, 0.0),
            ..Particle::default()
        })
        .expect("a particle");
    w.add_emitter(Emitter {
        rate: 1e12,
        ..Emitter::default()
    })
    .expect("a valid rate");
    let error = step(&mut w).expect_err("too many spawns");
    assert_eq!(
        error.to_string(),
        "step 0: emitter 0 is due 1.6666667e10 particles in one step, past the limit of 1000000 \
         (WorldConfig::max_spawns_per_step); lower its rate or raise the limit"
    );
    assert_eq!(w.particles().len(), 1, "nothing was spawned");
    // Refused before the step changed anything.
    assert_eq!((w.tick(), w.position(falling).expect("live")), (0, Vec3::ZERO));
}

#[test]
fn the_world_wide_particle_limit_holds_for_spawns_queues_and_emitters() {
    let mut w = World::new(WorldConfig {
        max_particles: 3,
        ..WorldConfig::default()
    })
    .expect("registered");
    w.spawn(Particle::default()).expect("room for one");
    w.queue_spawn(Particle::default()).expect("room for a queued one");
    w.spawn(Particle::default()).expect("room for the third");
    let limit = "the world already holds its limit of 3 particles (WorldConfig::max_particles); \
                 despawn some or raise the limit";
    let error = w
        .spawn(Particle::default())
        .expect_err("full, counting the queued spawn");
    assert_eq!(error.to_string(), limit);
    assert_eq!(w.queue_spawn(Particle::default()).expect_err("full").to_string(), limit);
    assert_eq!(w.len(), 2, "the refused spawns left nothing behind");
    step(&mut w).expect("the queued spawn lands");
    assert_eq!(w.len(), 3);

    // An emitter due more than the room left fails the step, naming the limit.
    w.add_emitter(Emitter {
        rate: 60.0,
        ..Emitter::default()
    })
    .expect("a valid emitter");
    let error = step(&mut w).expect_err("no room for the emitted particle");
    assert_eq!(
        error.to_string(),
        "step 1: emitter 0 would take the world past its limit of 3 particles (WorldConfig::max_particles); \
         give its particles a shorter lifetime, lower its rate or raise the limit"
    );
    assert_eq!(w.len(), 3, "nothing was spawned");
}

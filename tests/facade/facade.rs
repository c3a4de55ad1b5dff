//! Workspace-level integration tests through the `tickwork` facade.

use glam::Vec3A;
use tickwork::integrators::{Integrator, METHODS, build};

/// A projectile under constant gravity: every method of order 2 or more is
/// exact for constant acceleration (the solution is a quadratic in t), in f32
/// game precision.
#[test]
fn second_and_higher_order_methods_fly_a_projectile_exactly_through_the_facade() {
    let gravity = Vec3A::new(0.0, -9.81, 0.0);
    let (x0, v0) = (Vec3A::new(0.0, 1.0, 0.0), Vec3A::new(3.0, 12.0, -1.0));
    let dt = 1.0 / 60.0;
    let steps = 120;
    let t = steps as f32 * dt;
    let expected = x0 + v0 * t + gravity * (0.5 * t * t);
    // Position Verlet is excluded: its velocity estimate lags by half a step.
    for info in METHODS.iter().filter(|m| m.order >= 2 && m.order_velocity >= 2) {
        let mut method: Box<dyn Integrator<Vec3A>> = build(info.name).expect("registered");
        let (mut x, mut v) = (vec![x0], vec![v0]);
        let mut system = |_t: f32, _x: &[Vec3A], _v: &[Vec3A], a: &mut [Vec3A]| a.fill(gravity);
        for n in 0..steps {
            method
                .step(n as f32 * dt, dt, &mut x, &mut v, &mut system)
                .expect("step");
        }
        let error = (x[0] - expected).length();
        assert!(error < 2e-4, "{}: landed {error} from the closed form", info.name);
        assert!((v[0] - (v0 + gravity * t)).length() < 2e-4, "{}: velocity", info.name);
    }
}

/// First-order methods err on a projectile by exactly the known amount:
/// explicit Euler falls short by `g t dt / 2`, semi-implicit Euler overshoots by it.
#[test]
fn euler_methods_miss_the_projectile_by_half_a_step_of_gravity() {
    let (g, dt, steps) = (-9.81f64, 0.01, 100);
    let t = steps as f64 * dt;
    let exact = 0.5 * g * t * t;
    let mut system = |_t: f64, _x: &[f64], _v: &[f64], a: &mut [f64]| a[0] = g;
    for (name, sign) in [("explicit_euler", -1.0), ("semi_implicit_euler", 1.0)] {
        let mut method = build::<f64>(name).expect("registered");
        let (mut x, mut v) = (vec![0.0], vec![0.0]);
        for n in 0..steps {
            method
                .step(n as f64 * dt, dt, &mut x, &mut v, &mut system)
                .expect("step");
        }
        let offset = x[0] - exact;
        assert!(
            (offset - sign * 0.5 * g * t * dt).abs() < 1e-12,
            "{name}: offset {offset}"
        );
    }
}

/// A game written against the prelude alone: `Game::update` takes a
/// `Frame`, and a sensor's handle in a game's fields starts as
/// `SensorId::default()`, as a collider's does.
#[test]
fn the_prelude_has_what_a_games_update_and_fields_take() {
    use tickwork::prelude::*;
    #[derive(Default)]
    struct Fields {
        wall: ColliderId,
        trigger: SensorId,
    }
    fn steps_of(frame: &Frame) -> u32 {
        frame.steps
    }
    let fields = Fields::default();
    assert_eq!(
        (fields.wall, fields.trigger),
        (ColliderId::PLACEHOLDER, SensorId::PLACEHOLDER)
    );
    let mut clock = tickwork::engine::FixedClock::default();
    let frame = clock.step(3);
    assert_eq!(steps_of(&frame), 3);
}

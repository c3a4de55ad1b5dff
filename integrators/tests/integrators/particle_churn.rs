//! History follows the particle: spawning and despawning other particles
//! (with `Vec::swap_remove` semantics) never changes a particle's trajectory.

use tickwork_integrators::{Integrator, METHODS, build};

/// Independent damped oscillators: each particle's acceleration depends on it alone.
fn damped(_t: f64, x: &[f64], v: &[f64], a: &mut [f64]) {
    for i in 0..x.len() {
        a[i] = -x[i] - 0.5 * v[i];
    }
}

/// Independent undamped oscillators (velocity-independent forces).
fn undamped(_t: f64, x: &[f64], _v: &[f64], a: &mut [f64]) {
    for i in 0..x.len() {
        a[i] = -x[i];
    }
}

const STEPS: usize = 120;
const DT: f64 = 0.05;

/// The watched particle alone.
fn solo(name: &str, system: fn(f64, &[f64], &[f64], &mut [f64])) -> Vec<(f64, f64)> {
    let mut method = build::<f64>(name).expect("registered");
    let (mut x, mut v) = (vec![1.0], vec![0.0]);
    let mut system = system;
    (0..STEPS)
        .map(|n| {
            method
                .step(n as f64 * DT, DT, &mut x, &mut v, &mut system)
                .expect("step");
            (x[0], v[0])
        })
        .collect()
}

/// The watched particle among others that come and go around it.
fn crowded(name: &str, system: fn(f64, &[f64], &[f64], &mut [f64])) -> Vec<(f64, f64)> {
    let mut method: Box<dyn Integrator<f64>> = build(name).expect("registered");
    // Particle 0 is a companion, particle 1 the watched one.
    let (mut x, mut v) = (vec![-0.3, 1.0], vec![0.2, 0.0]);
    let mut watched = 1;
    let mut system = system;
    let mut trajectory = Vec::new();
    for n in 0..STEPS {
        match n {
            // Remove the companion: the watched particle (last) moves into slot 0.
            17 => {
                x.swap_remove(0);
                v.swap_remove(0);
                method.swap_remove(0, x.len() + 1);
                watched = 0;
            }
            // Spawn two particles after it.
            31 | 44 => {
                x.push(0.1 * n as f64);
                v.push(-1.0);
            }
            // Remove the first spawned one: the last moves into its slot.
            58 => {
                x.swap_remove(1);
                v.swap_remove(1);
                method.swap_remove(1, x.len() + 1);
            }
            // Spawn one more, then remove whichever particle is last.
            73 => {
                x.push(2.0);
                v.push(0.0);
            }
            90 => {
                let last = x.len() - 1;
                x.swap_remove(last);
                v.swap_remove(last);
                method.swap_remove(last, x.len() + 1);
            }
            _ => {}
        }
        method
            .step(n as f64 * DT, DT, &mut x, &mut v, &mut system)
            .expect("step");
        trajectory.push((x[watched], v[watched]));
    }
    trajectory
}

fn assert_same(name: &str, system: fn(f64, &[f64], &[f64], &mut [f64])) {
    let (alone, among) = (solo(name, system), crowded(name, system));
    for (n, (a, b)) in alone.iter().zip(&among).enumerate() {
        assert!(
            a.0.to_bits() == b.0.to_bits() && a.1.to_bits() == b.1.to_bits(),
            "{name}: step {n}: alone {a:?}, among others {b:?}"
        );
    }
}

#[test]
fn history_methods_give_the_same_trajectory_whatever_spawns_and_despawns_around_a_particle() {
    let history: Vec<_> = METHODS.iter().filter(|m| !m.self_starting).collect();
    let names: Vec<_> = history.iter().map(|m| m.name).collect();
    assert_eq!(
        names,
        [
            "position_verlet",
            "beeman",
            "adams_bashforth2",
            "adams_bashforth3",
            "adams_bashforth4"
        ]
    );
    for info in history {
        assert_same(info.name, damped);
    }
}

#[test]
fn every_explicit_method_is_unaffected_by_churn_on_velocity_independent_forces() {
    // Includes leapfrog and velocity Verlet, whose cached end-of-step
    // acceleration is recomputed when particles come and go.
    for info in METHODS.iter().filter(|m| !m.implicit) {
        assert_same(info.name, undamped);
    }
}

#[test]
fn a_particle_changed_outside_the_step_is_restarted() {
    // A bounce (velocity flipped by a collider) must not be undone by history.
    for info in METHODS.iter().filter(|m| !m.self_starting) {
        let mut method = build::<f64>(info.name).unwrap();
        let (mut x, mut v) = (vec![1.0], vec![-2.0]);
        let gravity = |_t: f64, _x: &[f64], _v: &[f64], a: &mut [f64]| a[0] = -10.0;
        let mut gravity = gravity;
        let dt = 0.01;
        for n in 0..10 {
            method.step(n as f64 * dt, dt, &mut x, &mut v, &mut gravity).unwrap();
        }
        v[0] = -v[0];
        let (x_bounce, v_bounce) = (x[0], v[0]);
        let stats = method.step(0.1, dt, &mut x, &mut v, &mut gravity).unwrap();
        assert_eq!(stats.bootstrapped, 1, "{}", info.name);
        // Constant acceleration: RK4 is exact.
        assert!(
            (x[0] - (x_bounce + v_bounce * dt - 5.0 * dt * dt)).abs() < 1e-12,
            "{}",
            info.name
        );
        assert!((v[0] - (v_bounce - 10.0 * dt)).abs() < 1e-12, "{}", info.name);
    }
}

/// The watched particle last of two; after step 20 a third is appended and
/// the first removed before the next step, so the new one moves into the
/// first slot: the watched particle, last when the method last stepped,
/// keeps its history where it is (it used to be moved into the removed
/// slot, and the watched one restarted).
fn last_among_new(name: &str, system: fn(f64, &[f64], &[f64], &mut [f64])) -> Vec<(f64, f64)> {
    let mut method: Box<dyn Integrator<f64>> = build(name).expect("registered");
    let (mut x, mut v) = (vec![-0.3, 1.0], vec![0.2, 0.0]);
    let mut system = system;
    (0..STEPS)
        .map(|n| {
            if n == 21 {
                x.push(0.7);
                v.push(-1.0);
                x.swap_remove(0);
                v.swap_remove(0);
                method.swap_remove(0, x.len() + 1);
            }
            method
                .step(n as f64 * DT, DT, &mut x, &mut v, &mut system)
                .expect("step");
            (x[1], v[1])
        })
        .collect()
}

#[test]
fn a_particle_keeps_its_history_when_one_appended_since_the_step_moves_into_a_removed_slot() {
    // The methods with history under velocity-dependent forces; every
    // explicit one where forces do not depend on velocity (leapfrog's and
    // velocity Verlet's cached accelerations are evaluated afresh when
    // particles come and go, as above).
    let history = METHODS
        .iter()
        .filter(|m| !m.self_starting)
        .map(|m| (m.name, damped as fn(_, &_, &_, &mut _)));
    let explicit = METHODS
        .iter()
        .filter(|m| !m.implicit)
        .map(|m| (m.name, undamped as fn(_, &_, &_, &mut _)));
    for (name, system) in history.chain(explicit) {
        let info = tickwork_integrators::find(name).expect("registered");
        let (alone, among) = (solo(info.name, system), last_among_new(info.name, system));
        for (n, (a, b)) in alone.iter().zip(&among).enumerate() {
            assert!(
                a.0.to_bits() == b.0.to_bits() && a.1.to_bits() == b.1.to_bits(),
                "{}: step {n}: alone {a:?}, last among new ones {b:?}",
                info.name
            );
        }
    }
}

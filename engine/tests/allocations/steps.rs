//! Steady-state steps allocate nothing, counted on the stepping thread
//! (`counting::this_thread`).

use crate::counting::this_thread as allocations;
use glam::Vec3;
use tickwork_engine::{
    Attractor, BoxCollider, Character, CharacterConfig, FixedStep, Gravity, LinearDrag, Material, Particle, Plane,
    SphereCollisions, Spring, SpringEnd, Springs, World, WorldConfig,
};

fn scene(method: &str, coupled: bool) -> World {
    let mut w = World::new(WorldConfig {
        integrator: method.into(),
        ..WorldConfig::default()
    })
    .expect("known");
    w.add_force(Gravity::EARTH);
    w.add_force(LinearDrag { rate: 0.1 });
    w.add_force(Attractor {
        position: Vec3::new(0.0, 5.0, 0.0),
        gm: 1.0,
        softening: 0.1,
    });
    w.add_collider(Plane::floor(0.0, Material::default()));
    let entities: Vec<_> = (0..3000)
        .map(|i| {
            let p = Particle {
                position: Vec3::new((i % 50) as f32 * 0.1, 0.5 + (i / 50) as f32 * 0.1, 0.0),
                velocity: Vec3::new(0.0, (i % 7) as f32, 0.0),
                radius: 0.04,
                ..Particle::default()
            };
            w.spawn(p).expect("spawn")
        })
        .collect();
    if coupled {
        let springs = entities
            .windows(2)
            .map(|p| Spring {
                a: SpringEnd::Entity(p[0]),
                b: SpringEnd::Entity(p[1]),
                stiffness: 10.0,
                rest_length: 0.1,
                damping: 0.1,
            })
            .collect();
        w.add_force(Springs::new(springs));
        w.add_collider(SphereCollisions::new(Material::default()));
        // Flush boxes (their seams) and characters running over them,
        // one riding a moving box.
        for k in 0..4 {
            let min = Vec3::new(6.0 + k as f32, -1.0, -1.0);
            w.add_collider(BoxCollider {
                velocity: Vec3::new(0.0, if k == 3 { 0.001 } else { 0.0 }, 0.0),
                ..BoxCollider::solid(min, min + Vec3::new(1.0, 1.0, 2.0), Material::default())
            });
        }
        for x in [6.5, 9.5] {
            let mut c = Character::new(glam::Vec2::new(x, 0.5), CharacterConfig::default());
            c.run(2.0);
            c.jump(5.0);
            w.add_character(c).expect("a character");
        }
    }
    w
}

#[test]
fn steady_state_steps_allocate_nothing() {
    for (method, coupled) in [
        ("semi_implicit_euler", false),
        ("rk4", false),
        ("velocity_verlet", false),
        ("semi_implicit_euler", true),
        ("adams_bashforth3", true),
    ] {
        let mut w = scene(method, coupled);
        let dt = 1.0 / 60.0;
        for tick in 0..5 {
            w.step(FixedStep {
                tick,
                time: tick as f64 * dt,
                dt,
            })
            .expect("step");
        }
        let before = allocations();
        for tick in 5..25 {
            w.step(FixedStep {
                tick,
                time: tick as f64 * dt,
                dt,
            })
            .expect("step");
        }
        assert_eq!(allocations() - before, 0, "{method} (coupled: {coupled}) allocated");
    }
}

fn allocations_per_snapshot(particles_scale: bool) -> usize {
    let mut w = scene("adams_bashforth2", true);
    if particles_scale {
        for i in 0..30_000 {
            w.spawn(Particle {
                position: Vec3::new(i as f32, 100.0, 0.0),
                ..Particle::default()
            })
            .expect("spawn");
        }
    }
    let mut snapshot = w.snapshot();
    for tick in 0..5 {
        w.step(FixedStep {
            tick,
            time: tick as f64 / 60.0,
            dt: 1.0 / 60.0,
        })
        .expect("step");
    }
    w.snapshot_into(&mut snapshot);
    let before = allocations();
    for tick in 5..10 {
        w.step(FixedStep {
            tick,
            time: tick as f64 / 60.0,
            dt: 1.0 / 60.0,
        })
        .expect("step");
        w.snapshot_into(&mut snapshot);
    }
    (allocations() - before) / 5
}

#[test]
fn snapshots_into_existing_buffers_reuse_the_particle_columns() {
    // The world's columns, forces and colliders reuse their buffers; the
    // integrator's scratch is copied by its derived Clone (a fixed number of
    // buffers, whatever the particle count).
    let small = allocations_per_snapshot(false);
    let large = allocations_per_snapshot(true);
    assert_eq!(small, large, "allocations must not grow with the particle count");
    assert!(small <= 24, "{small} allocations per snapshot");
}

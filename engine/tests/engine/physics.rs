//! The fixed step against theory: projectiles, bounces, springs, orbits.
// Reference values and set-ups computed natively (never in a page): the
// platform's own functions are fine here (clippy.toml bans them in the engine).
#![allow(clippy::disallowed_methods)]

use glam::Vec3;
use tickwork_engine::clock::FixedStep;
use tickwork_engine::{
    Attractor, BoxCollider, FixedClock, Gravity, Material, NBody, Particle, Plane, RigidBody, SphereCollisions, World,
    WorldConfig,
};

fn world(integrator: &str) -> World {
    World::new(WorldConfig {
        integrator: integrator.into(),
        ..WorldConfig::default()
    })
    .expect("known method")
}

fn step_at(tick: u64, dt: f64) -> FixedStep {
    FixedStep {
        tick,
        time: tick as f64 * dt,
        dt,
    }
}

#[test]
fn projectile_matches_the_closed_form_for_second_order_methods() {
    // Constant acceleration: any method exact on quadratics (midpoint, Heun,
    // RK4, Verlet...) reproduces x0 + v0 t + g t^2 / 2 to rounding.
    for method in ["velocity_verlet", "rk4", "midpoint", "heun", "leapfrog"] {
        let mut w = world(method);
        w.add_force(Gravity::EARTH);
        let v0 = Vec3::new(3.0, 12.0, -1.0);
        let e = w
            .spawn(Particle {
                velocity: v0,
                ..Particle::default()
            })
            .expect("spawn");
        let mut clock = FixedClock::default();
        for _ in 0..120 {
            let frame = clock.advance(1.0 / 60.0).expect("frame");
            for step in frame.fixed_steps() {
                w.step(step).expect("step");
            }
        }
        let t = w.time() as f32;
        let exact = v0 * t + Gravity::EARTH.acceleration * (0.5 * t * t);
        let x = w.position(e).expect("alive");
        assert!((x - exact).length() < 2e-4, "{method}: {x} vs {exact} at t = {t}");
    }
}

#[test]
fn bouncing_ball_keeps_the_energy_fraction_its_restitution_gives() {
    // A ball dropped from 2 m onto a floor with restitution e rises to e^2
    // times its height after each bounce (kinetic energy of the normal motion
    // is kept in the fraction e^2).
    let e = 0.8;
    let dt = 1.0 / 960.0;
    let mut w = world("velocity_verlet");
    w.add_force(Gravity::EARTH);
    w.add_collider(Plane::floor(
        0.0,
        Material {
            restitution: e,
            friction: 0.0,
        },
    ));
    let radius = 0.1;
    let ball = w.spawn(Particle {
        position: Vec3::new(0.0, 2.0 + radius, 0.0),
        radius,
        ..Particle::default()
    });
    let ball = ball.expect("spawn");
    let mut apexes = Vec::new();
    let mut previous_vy = 0.0;
    for tick in 0..(6.0 / dt) as u64 {
        w.step(step_at(tick, dt)).expect("step");
        let vy = w.velocity(ball).expect("alive").y;
        if previous_vy > 0.0 && vy <= 0.0 {
            apexes.push(w.position(ball).expect("alive").y - radius);
        }
        previous_vy = vy;
    }
    assert!(apexes.len() >= 3, "{apexes:?}");
    let mut height = 2.0;
    for apex in &apexes[..3] {
        let ratio = apex / height;
        assert!(
            (ratio - e * e).abs() < 0.01,
            "apex {apex} after {height}: ratio {ratio}, expected {}",
            e * e
        );
        height = *apex;
    }
}

#[test]
fn friction_slows_sliding_particles_by_coulomb_law() {
    // A particle landing at 45 degrees on a floor with mu: its tangential
    // speed drops by mu times the normal speed change (1 + e) |vn|.
    let mut w = world("semi_implicit_euler");
    w.add_collider(Plane::floor(
        0.0,
        Material {
            restitution: 0.5,
            friction: 0.2,
        },
    ));
    let p = w.spawn(Particle {
        position: Vec3::new(0.0, 0.001, 0.0),
        velocity: Vec3::new(4.0, -4.0, 0.0),
        radius: 0.0,
        ..Particle::default()
    });
    let p = p.expect("spawn");
    w.step(step_at(0, 0.01)).expect("step");
    let v = w.velocity(p).expect("alive");
    assert!((v.y - 2.0).abs() < 1e-5, "{v}");
    assert!((v.x - (4.0 - 0.2 * 1.5 * 4.0)).abs() < 1e-5, "{v}");
}

#[test]
fn box_container_keeps_particles_inside_and_obstacle_keeps_them_out() {
    let mut w = world("semi_implicit_euler");
    w.add_force(Gravity::EARTH);
    w.add_collider(BoxCollider {
        min: Vec3::splat(-1.0),
        max: Vec3::splat(1.0),
        inside: true,
        material: Material {
            restitution: 0.9,
            friction: 0.0,
        },
        velocity: Vec3::ZERO,
        ..BoxCollider::default()
    });
    let mut obstacle = world("semi_implicit_euler");
    obstacle.add_force(Gravity::EARTH);
    obstacle.add_collider(BoxCollider {
        min: Vec3::new(-1.0, -1.0, -1.0),
        max: Vec3::new(1.0, 0.0, 1.0),
        inside: false,
        material: Material::default(),
        velocity: Vec3::ZERO,
        ..BoxCollider::default()
    });
    let mut inside = Vec::new();
    let mut outside = Vec::new();
    for k in 0..50 {
        let v = Vec3::new((k as f32 * 0.7).sin(), (k as f32 * 1.3).cos(), (k as f32 * 0.3).sin()) * 8.0;
        inside.push(
            w.spawn(Particle {
                velocity: v,
                radius: 0.05,
                ..Particle::default()
            })
            .expect("spawn"),
        );
        let above = Particle {
            position: Vec3::new(k as f32 * 0.03 - 0.75, 0.5, 0.0),
            velocity: v * 0.2,
            radius: 0.05,
            ..Particle::default()
        };
        outside.push(obstacle.spawn(above).expect("spawn"));
    }
    for tick in 0..600 {
        w.step(step_at(tick, 1.0 / 120.0)).expect("step");
        obstacle.step(step_at(tick, 1.0 / 120.0)).expect("step");
        for e in &inside {
            let x = w.position(*e).expect("alive");
            assert!(x.abs().max_element() <= 0.95 + 1e-4, "escaped: {x}");
        }
        for e in &outside {
            let x = obstacle.position(*e).expect("alive");
            let inside_box = x.x.abs() < 1.0 && x.z.abs() < 1.0 && x.y < 0.05 - 1e-4 && x.y > -1.0;
            assert!(!inside_box, "entered the obstacle: {x}");
        }
    }
}

#[test]
fn sphere_collisions_conserve_momentum_and_separate_particles() {
    let mut w = world("semi_implicit_euler");
    w.add_collider(SphereCollisions::new(Material {
        restitution: 1.0,
        friction: 0.0,
    }));
    let a = w.spawn(Particle {
        position: Vec3::new(-1.0, 0.0, 0.0),
        velocity: Vec3::X,
        mass: 1.0,
        radius: 0.25,
        ..Particle::default()
    });
    let b = w.spawn(Particle {
        position: Vec3::new(1.0, 0.0, 0.0),
        velocity: -Vec3::X,
        mass: 3.0,
        radius: 0.25,
        ..Particle::default()
    });
    let (a, b) = (a.expect("spawn"), b.expect("spawn"));
    for tick in 0..200 {
        w.step(step_at(tick, 0.01)).expect("step");
    }
    let (va, vb) = (w.velocity(a).expect("alive"), w.velocity(b).expect("alive"));
    // Elastic head-on collision: 1 kg at +1 m/s, 3 kg at -1 m/s -> -2 and 0.
    assert!((va.x + 2.0).abs() < 1e-5 && vb.x.abs() < 1e-5, "{va} {vb}");
    assert!((va.x + 3.0 * vb.x + 2.0).abs() < 1e-5, "momentum");
}

#[test]
fn sphere_grid_resolves_a_crowd_without_overlaps() {
    let mut w = world("semi_implicit_euler");
    w.add_force(Gravity::EARTH);
    w.add_collider(Plane::floor(
        0.0,
        Material {
            restitution: 0.1,
            friction: 0.3,
        },
    ));
    w.add_collider(BoxCollider {
        min: Vec3::new(-1.0, -1.0, -1.0),
        max: Vec3::new(1.0, 10.0, 1.0),
        inside: true,
        material: Material::default(),
        velocity: Vec3::ZERO,
        ..BoxCollider::default()
    });
    w.add_collider(SphereCollisions::new(Material {
        restitution: 0.1,
        friction: 0.0,
    }));
    for k in 0..400 {
        let x = Vec3::new(
            (k % 10) as f32 * 0.2 - 0.9,
            0.1 + (k / 100) as f32 * 0.2,
            ((k / 10) % 10) as f32 * 0.2 - 0.9,
        );
        w.spawn(Particle {
            position: x + Vec3::splat(0.01 * (k % 7) as f32),
            radius: 0.05,
            ..Particle::default()
        })
        .expect("spawn");
    }
    for tick in 0..300 {
        w.step(step_at(tick, 1.0 / 120.0)).expect("step");
    }
    let x: Vec<_> = w.particles().position.iter().collect();
    let mut worst: f32 = 0.0;
    for i in 0..x.len() {
        for j in i + 1..x.len() {
            worst = worst.max(0.1 - (x[i] - x[j]).length());
        }
    }
    // Settled under gravity: overlaps stay a small fraction of the radius.
    assert!(worst < 0.02, "deepest overlap {worst}");
}

#[test]
fn kepler_orbit_energy_stays_bounded_with_a_symplectic_method() {
    for (method, bound) in [("velocity_verlet", 1e-3), ("explicit_euler", f64::INFINITY)] {
        let mut w = world(method);
        w.add_force(Attractor {
            position: Vec3::ZERO,
            gm: 1.0,
            softening: 0.0,
        });
        w.spawn(Particle {
            position: Vec3::X,
            velocity: Vec3::new(0.0, 1.2, 0.0),
            ..Particle::default()
        })
        .expect("spawn");
        let e0 = w.energy().expect("within the pair limit").total();
        let mut worst: f64 = 0.0;
        for tick in 0..20_000 {
            w.step(step_at(tick, 0.005)).expect("step");
            worst = worst.max(((w.energy().expect("within the pair limit").total() - e0) / e0).abs());
        }
        if bound.is_finite() {
            assert!(worst < bound, "{method}: {worst}");
        } else {
            assert!(worst > 0.2, "explicit Euler drifts: {worst}");
        }
    }
}

#[test]
fn two_body_gravity_conserves_momentum_and_energy() {
    let mut w = world("velocity_verlet");
    w.add_force(NBody::new(1.0, 0.0));
    let a = w.spawn(Particle {
        position: Vec3::new(-0.5, 0.0, 0.0),
        velocity: Vec3::new(0.0, -0.5, 0.0),
        ..Particle::default()
    });
    let b = w.spawn(Particle {
        position: Vec3::new(0.5, 0.0, 0.0),
        velocity: Vec3::new(0.0, 0.5, 0.0),
        ..Particle::default()
    });
    let (a, b) = (a.expect("spawn"), b.expect("spawn"));
    let e0 = w.energy().expect("within the pair limit").total();
    assert!((e0 - (0.25 - 1.0)).abs() < 1e-6, "K = 2 * 0.125, U = -1: {e0}");
    for tick in 0..5000 {
        w.step(step_at(tick, 0.002)).expect("step");
    }
    let p = w.velocity(a).expect("alive") + w.velocity(b).expect("alive");
    assert!(p.length() < 1e-5, "momentum {p}");
    assert!(((w.energy().expect("within the pair limit").total() - e0) / e0).abs() < 1e-3);
}

#[test]
fn nbody_is_bit_identical_serial_and_parallel() {
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool");
        pool.install(|| {
            let mut w = world("rk4");
            let mut nbody = NBody::new(0.01, 0.05);
            nbody.parallel_threshold = 16;
            w.add_force(nbody);
            for k in 0..100 {
                let angle = k as f32 * 0.7;
                let p = Particle {
                    position: Vec3::new(angle.cos(), angle.sin(), 0.01 * k as f32) * (1.0 + k as f32 * 0.01),
                    ..Particle::default()
                };
                w.spawn(p).expect("spawn");
            }
            for tick in 0..50 {
                w.step(step_at(tick, 0.01)).expect("step");
            }
            w.state_hash()
        })
    };
    assert_eq!(run(1), run(2));
}

#[test]
fn free_rigid_body_keeps_its_energy_and_turns() {
    let mut w = World::default();
    let body = RigidBody {
        angular_velocity: Vec3::new(0.1, 2.0, 0.05),
        inertia: Vec3::new(1.0, 2.0, 3.0),
        ..RigidBody::default()
    };
    let e = w.spawn_rigid(body).expect("spawn");
    let e0 = w.energy().expect("within the pair limit").total();
    for tick in 0..1000 {
        w.step(step_at(tick, 0.01)).expect("step");
    }
    let drift = ((w.energy().expect("within the pair limit").total() - e0) / e0).abs();
    assert!(
        drift < 1e-3,
        "{drift}: {} vs {e0}",
        w.energy().expect("within the pair limit").total()
    );
    let q = w.orientation(e).expect("alive");
    assert!((q.length() - 1.0).abs() < 1e-5);
    assert!(q.angle_between(glam::Quat::IDENTITY) > 0.5, "it turned");
    let row = w.row(e).expect("alive");
    assert_eq!(w.rigid_bodies().owner[0] as usize, row);
    // The exponential map is first order in energy but keeps angular momentum exactly.
    w.set_angular_integrator("exponential_map").expect("known");
    let momentum = |w: &World| {
        let r = w.rigid_bodies();
        tickwork_engine::integrators::angular::angular_momentum(r.orientation[0], r.angular_velocity[0], r.inertia[0])
    };
    let l0 = momentum(&w);
    for tick in 1000..2000 {
        w.step(step_at(tick, 0.01)).expect("step");
    }
    assert!(
        (momentum(&w) - l0).length() < 1e-3 * l0.length(),
        "{} vs {l0}",
        momentum(&w)
    );
}

#[test]
fn particle_slides_down_an_inclined_plane_at_g_sin_theta() {
    // A 30 degree frictionless incline: the particle stays on the plane and
    // accelerates along it at g sin 30 = 4.905 m/s^2.
    let theta = 30f32.to_radians();
    let normal = Vec3::new(-theta.sin(), theta.cos(), 0.0);
    let mut w = world("semi_implicit_euler");
    w.add_force(Gravity::EARTH);
    w.add_collider(Plane {
        normal,
        offset: 0.0,
        material: Material {
            restitution: 0.0,
            friction: 0.0,
        },
        speed: 0.0,
        ..Plane::default()
    });
    let p = w
        .spawn(Particle {
            radius: 0.0,
            ..Particle::default()
        })
        .expect("spawn");
    let dt = 1.0 / 240.0;
    for tick in 0..480 {
        w.step(step_at(tick, dt)).expect("step");
        assert!(normal.dot(w.position(p).expect("alive")) > -1e-5, "fell through");
    }
    let v = w.velocity(p).expect("alive");
    let along = Vec3::new(-theta.cos(), -theta.sin(), 0.0);
    assert!(
        (v.dot(along) - 9.81 * theta.sin() * 2.0).abs() < 0.05,
        "{v}: {}",
        v.dot(along)
    );
    assert!(v.dot(normal).abs() < 1e-3);
}

#[test]
fn sphere_collisions_work_on_the_hashed_grid_for_far_apart_particles() {
    // Two head-on pairs 10 km apart: the bounding box holds far more than
    // eight cells per particle, so the grid is hashed instead of dense.
    let mut w = world("semi_implicit_euler");
    w.add_collider(SphereCollisions::new(Material {
        restitution: 1.0,
        friction: 0.0,
    }));
    let mut pairs = Vec::new();
    for offset in [Vec3::ZERO, Vec3::new(10_000.0, 0.0, 0.0)] {
        let a = Particle {
            position: offset - Vec3::X,
            velocity: Vec3::X,
            radius: 0.25,
            ..Particle::default()
        };
        let b = Particle {
            position: offset + Vec3::X,
            velocity: -Vec3::X,
            mass: 3.0,
            radius: 0.25,
            ..Particle::default()
        };
        pairs.push((w.spawn(a).expect("spawn"), w.spawn(b).expect("spawn")));
    }
    for tick in 0..200 {
        w.step(step_at(tick, 0.01)).expect("step");
    }
    for (a, b) in pairs {
        let (va, vb) = (w.velocity(a).expect("alive"), w.velocity(b).expect("alive"));
        assert!((va.x + 2.0).abs() < 1e-5 && vb.x.abs() < 1e-5, "{va} {vb}");
    }
}

#[test]
fn subnormal_velocities_are_flushed_to_zero_every_64_steps_and_nothing_else_changes() {
    // Drag alone: v <- v (1 - b h) each step, whatever the method's form.
    let mut w = tickwork_engine::World::new(tickwork_engine::WorldConfig::default()).expect("default");
    w.add_force(tickwork_engine::LinearDrag { rate: 0.1 });
    let speeds = [1e-40_f32, -3e-39, -0.0, 1.3e-38, 1.0];
    let entities: Vec<_> = speeds
        .iter()
        .map(|&vx| {
            w.spawn(tickwork_engine::Particle {
                velocity: Vec3::new(vx, 0.0, 0.0),
                ..tickwork_engine::Particle::default()
            })
            .expect("spawn")
        })
        .collect();
    let dt = 1.0 / 60.0;
    let mut expected = speeds;
    let every = tickwork_engine::SUBNORMAL_FLUSH_EVERY;
    for tick in 0..=every {
        w.step(FixedStep {
            tick,
            time: tick as f64 * dt,
            dt,
        })
        .expect("step");
        for (k, v) in expected.iter_mut().enumerate() {
            // The same update as semi-implicit Euler: v += h (-b v).
            *v += (dt as f32) * (-0.1 * *v);
            if tick.is_multiple_of(every) && v.abs() < f32::MIN_POSITIVE && *v != 0.0 {
                *v = 0.0;
            }
            let got = w.velocity(entities[k]).expect("live").x;
            assert_eq!(
                got.to_bits(),
                v.to_bits(),
                "particle {k} (from {}) at tick {tick}",
                speeds[k]
            );
        }
    }
    let velocity = |k: usize| w.velocity(entities[k]).expect("live").x;
    // Subnormals became zero at tick 0 and stay so; 1.3e-38 went subnormal
    // on the way and was flushed at tick 64; the normal numbers follow the
    // drag exactly (checked bit for bit above).
    assert_eq!((velocity(0), velocity(1), velocity(3)), (0.0, 0.0, 0.0));
    assert!((velocity(4) - (1.0 - 0.1 / 60.0_f32).powi(65)).abs() < 1e-5);
}

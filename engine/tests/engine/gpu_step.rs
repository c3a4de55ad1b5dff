//! The fixed step on the GPU against the CPU's f32 step: the same world
//! (gravity, wind, quadratic and linear drag, an attractor, a floor with
//! friction and two walls, some immovable particles, a subnormal velocity;
//! and an n-body cloud) stepped on each gives the same bits for every
//! method the GPU step has on this machine's adapter (lavapipe on CI: its
//! compiler fuses no multiply-add and rounds `sqrt` and division
//! correctly), and the same checksum once stored back into the world; the
//! GPU's state does not depend on how the steps are batched; and what the
//! GPU step does not do is refused with its name.
//!
//! These need a graphics adapter with compute shaders; `scripts/test`
//! installs Mesa's software Vulkan driver. Without one they fail with the
//! error that names the packages; they never skip.
#![cfg(feature = "render")]

use glam::{Vec3, Vec3A};
use tickwork_engine::colliders::{BoxCollider, Material, Plane};
use tickwork_engine::forces::{Attractor, Gravity, LinearDrag, NBody, QuadraticDrag, Wind};
use tickwork_engine::gpu_step::{GpuStepError, GpuWorld};
use tickwork_engine::{FixedStep, GpuForce, Particle, WgslF32, World, WorldConfig};

const DT: f64 = 1.0 / 60.0;
const PARTICLES: usize = 4133;
/// The ticks the CPU runs alone before the GPU's copy is made: the GPU's
/// flush schedule must follow the world's tick, not its own count.
const BEFORE: u64 = 5;

use crate::support::{draw, gpu};

/// 4 096 particles from a seeded generator over a 10 m box, moving up to
/// 8 m/s, one in 16 immovable (no force or collider moves it; it keeps its
/// velocity); gravity, quadratic and linear drag, an attractor above; a
/// floor (e = 0.5, friction 0.2) at y = 0, frictionless walls facing -x at
/// x = 5 and +z at z = -5, a solid block and a container box.
fn world(method: &str) -> World {
    let mut world = World::new(WorldConfig {
        integrator: method.into(),
        ..WorldConfig::default()
    })
    .expect("a world");
    world.add_force(Gravity::EARTH);
    world.add_force(Wind {
        velocity: Vec3::new(1.0, 0.0, 2.0),
        rate: 0.1,
    });
    world.add_force(QuadraticDrag { coefficient: 0.02 });
    world.add_force(LinearDrag { rate: 0.3 });
    world.add_force(Attractor {
        position: Vec3::new(1.0, 12.0, -2.0),
        gm: 40.0,
        softening: 0.5,
    });
    world.add_collider(Plane::floor(
        0.0,
        Material {
            restitution: 0.5,
            friction: 0.2,
        },
    ));
    world.add_collider(Plane {
        normal: Vec3::NEG_X,
        offset: -5.0,
        ..Plane::floor(
            0.0,
            Material {
                restitution: 1.0,
                friction: 0.0,
            },
        )
    });
    // A wall facing +z at z = -5.
    world.add_collider(Plane {
        normal: Vec3::Z,
        offset: -5.0,
        ..Plane::floor(
            0.0,
            Material {
                restitution: 0.9,
                friction: 0.0,
            },
        )
    });
    // A solid block floating in the middle, and a container around it all.
    world.add_collider(BoxCollider::solid(
        Vec3::new(-2.0, 1.0, -2.0),
        Vec3::new(0.5, 3.0, 0.5),
        Material {
            restitution: 0.5,
            friction: 0.3,
        },
    ));
    world.add_collider(BoxCollider::container(
        Vec3::new(-6.0, -1.0, -6.0),
        Vec3::new(6.0, 14.0, 6.0),
        Material {
            restitution: 0.7,
            friction: 0.1,
        },
    ));
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 40) as f32 / (1u64 << 24) as f32
    };
    // Not a multiple of the workgroup's 256: the last group is partly idle.
    for k in 0..PARTICLES {
        let position = Vec3::new(10.0 * next() - 5.0, 10.0 * next(), 10.0 * next() - 5.0);
        let velocity = 8.0 * Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5);
        world
            .spawn(Particle {
                position,
                velocity,
                radius: 0.05 + 0.1 * next(),
                immovable: k % 16 == 0,
                ..Particle::default()
            })
            .expect("a particle");
    }
    all_end_of_step(&mut world);
    world
}

/// Every plane and box of `world` finds its contacts by `rule`.
fn every_rule(world: &mut World, rule: tickwork_engine::colliders::ContactRule) {
    let ids: Vec<_> = world.colliders().map(|(id, _)| id).collect();
    for id in ids {
        if let Ok(plane) = world.collider_mut::<Plane>(id) {
            plane.contact = rule;
        } else if let Ok(b) = world.collider_mut::<BoxCollider>(id) {
            b.contact = rule;
        }
    }
}

/// Every plane and box of `world` finds its contacts at the end of the
/// step: the rule the GPU step follows bit for bit.
fn all_end_of_step(world: &mut World) {
    every_rule(world, tickwork_engine::colliders::ContactRule::EndOfStep);
}

fn cpu_steps(world: &mut World, ticks: std::ops::Range<u64>) {
    for tick in ticks {
        world
            .step(FixedStep {
                tick,
                time: tick as f64 * DT,
                dt: DT,
            })
            .expect("a step");
    }
}

/// How many components of `a` and `b` differ in their bits, and the
/// largest difference relative to the component's size.
fn differences(a: &[Vec3], b: &[Vec3]) -> (usize, f32) {
    let mut count = 0;
    let mut largest = 0.0f32;
    for (p, q) in a.iter().zip(b) {
        for k in 0..3 {
            if p[k].to_bits() != q[k].to_bits() {
                count += 1;
                largest = largest.max((p[k] - q[k]).abs() / p[k].abs().max(q[k].abs()).max(1e-30));
            }
        }
    }
    (count, largest)
}

/// Whether `method` keeps a history between steps (the checksum covers
/// it; it stays on the GPU).
fn with_history(method: &str) -> bool {
    ![
        "explicit_euler",
        "semi_implicit_euler",
        "midpoint",
        "heun",
        "rk4",
        "forest_ruth",
    ]
    .contains(&method)
}

fn matches_the_cpu(method: &str) {
    let gpu = gpu();
    let mut cpu = world(method);
    cpu_steps(&mut cpu, 0..BEFORE);
    // A subnormal velocity on an immovable particle (nothing else changes
    // it): the CPU's step flushes it to 0 after tick 64 (every 64th); so
    // must the GPU's.
    let still = cpu.entities().rows()[16];
    cpu.set_velocity(still, Vec3::new(1e-40, 0.0, 0.0)).expect("set");
    // A GPU world starts its method's history afresh (its particles'
    // last accelerations or positions stay on the CPU): so does the CPU's
    // twin here, as a new integrator does.
    cpu.set_integrator(method).expect("a method");
    let mut stored = cpu.clone();
    let mut on_gpu = GpuWorld::new(gpu, &cpu).expect("the GPU takes the world");
    assert_eq!((on_gpu.len(), on_gpu.method()), (PARTICLES, method));
    cpu_steps(&mut cpu, BEFORE..BEFORE + 120);
    // In uneven batches: the same 120 steps.
    for steps in [1, 63, 56] {
        on_gpu.step(gpu, DT as f32, steps).expect("steps");
    }
    // Stored into the world it came from, the GPU's run has the CPU run's
    // checksum: positions, velocities, previous positions, tick, time,
    // lived time.
    let last = FixedStep {
        tick: BEFORE + 119,
        time: (BEFORE + 119) as f64 * DT,
        dt: DT,
    };
    on_gpu.store_into(gpu, &mut stored, last).expect("stored");
    assert_eq!(stored.tick(), cpu.tick());
    // The checksum covers the method's history too, which stays on the
    // GPU (not stored): the methods without compare checksums.
    let has_history = with_history(method);
    if !has_history {
        assert_eq!(
            format!("{:016x}", stored.state_hash()),
            format!("{:016x}", cpu.state_hash()),
            "{method}: the checksum of the GPU's run against the CPU's"
        );
    }
    // Stored again, nothing changes; a world at another tick is refused.
    let hash = stored.state_hash();
    on_gpu.store_into(gpu, &mut stored, last).expect("stored again");
    assert_eq!(stored.state_hash(), hash);
    assert!(
        on_gpu.store_into(gpu, &mut world(method), last).is_err(),
        "a world at another tick is refused"
    );
    let (x, v) = on_gpu.read_back(gpu).expect("read back");
    let p = cpu.particles();
    let (cx, cv): (Vec<Vec3>, Vec<Vec3>) = (
        p.position.iter().map(Vec3::from).collect(),
        p.velocity.iter().map(Vec3::from).collect(),
    );
    // Something happened: particles met the floor and the walls.
    // (Immovable particles keep their velocity and pass through.)
    let movable = || (0..cx.len()).filter(|k| k % 16 != 0);
    let outside: Vec<_> = movable()
        .filter(|&k| !(cx[k].y >= 0.0 && cx[k].x <= 5.0 && cx[k].z >= -5.0))
        .take(5)
        .collect();
    assert!(outside.is_empty(), "movable particles all inside: {outside:?}");
    assert!(
        movable().any(|k| cv[k].y > 0.0 && cx[k].y < 1.0),
        "some bounced off the floor"
    );
    assert_eq!(cv[16].x.to_bits(), 0, "the subnormal velocity was flushed");
    let (dx, dv) = (differences(&x, &cx), differences(&v, &cv));
    assert_eq!(
        (dx.0, dv.0),
        (0, 0),
        "{method}: the GPU's state against the CPU's after 120 steps: positions {dx:?}, velocities {dv:?} \
         (components that differ, largest relative difference)"
    );
}

#[test]
fn semi_implicit_euler_on_the_gpu_is_the_cpus_bit_for_bit() {
    matches_the_cpu("semi_implicit_euler");
}

#[test]
fn explicit_euler_on_the_gpu_is_the_cpus_bit_for_bit() {
    matches_the_cpu("explicit_euler");
}

#[test]
fn midpoint_on_the_gpu_is_the_cpus_bit_for_bit() {
    matches_the_cpu("midpoint");
}

#[test]
fn heun_on_the_gpu_is_the_cpus_bit_for_bit() {
    matches_the_cpu("heun");
}

#[test]
fn rk4_on_the_gpu_is_the_cpus_bit_for_bit() {
    matches_the_cpu("rk4");
}

#[test]
fn forest_ruth_on_the_gpu_is_the_cpus_bit_for_bit() {
    matches_the_cpu("forest_ruth");
}

// The methods with history: the last acceleration (velocity Verlet,
// leapfrog: recomputed for every particle when any was changed after its
// step, as on the CPU), the last position (position Verlet: a particle
// without starts by RK4). The floor, the walls and the flush at tick 64
// break histories all through the run.

#[test]
fn velocity_verlet_on_the_gpu_is_the_cpus_bit_for_bit() {
    matches_the_cpu("velocity_verlet");
}

#[test]
fn leapfrog_on_the_gpu_is_the_cpus_bit_for_bit() {
    matches_the_cpu("leapfrog");
}

#[test]
fn position_verlet_on_the_gpu_is_the_cpus_bit_for_bit() {
    matches_the_cpu("position_verlet");
}

// Beeman keeps a(t) and a(t - h); Adams-Bashforth 2-4 the past velocities
// and accelerations, a particle with too few taking RK4 steps until it
// has them.

#[test]
fn beeman_on_the_gpu_is_the_cpus_bit_for_bit() {
    matches_the_cpu("beeman");
}

#[test]
fn adams_bashforth_2_to_4_on_the_gpu_are_the_cpus_bit_for_bit() {
    for method in ["adams_bashforth2", "adams_bashforth3", "adams_bashforth4"] {
        matches_the_cpu(method);
    }
}

/// 1 000 particles of the seeded cloud pulling on one another (and a
/// floor at y = 2), `method` stepping them: the GPU's tiled all-pairs sums, one
/// round a evaluation, against the CPU's whole-array stages, bit for bit
/// after 60 steps. The floor restarts the history of the particles it
/// stops, so the methods with history start some particles by RK4 while
/// the others go on.
fn nbody_matches_the_cpu(method: &str) {
    let gpu = gpu();
    let mut cpu = World::new(WorldConfig {
        integrator: method.into(),
        ..WorldConfig::default()
    })
    .expect("a world");
    cpu.add_force(NBody::new(2.0, 0.2));
    // A floor at y = 2: the particles below it are stopped there in the
    // first step, others meet it later.
    cpu.add_collider(Plane::floor(
        2.0,
        Material {
            restitution: 0.5,
            friction: 0.0,
        },
    ));
    all_end_of_step(&mut cpu);
    let source = world(method);
    let p = source.particles();
    // 1 000 rows: four workgroups' tiles, the last partly full, and one in
    // 16 immovable (no mass: they pull on nothing).
    for k in 0..1000 {
        cpu.spawn(Particle {
            position: p.position.get(k).map(Vec3::from).expect("a row"),
            velocity: p.velocity.get(k).map(Vec3::from).expect("a row") * 0.1,
            mass: 1.0 + (k % 7) as f32,
            immovable: k % 16 == 0,
            radius: 0.05,
            ..Particle::default()
        })
        .expect("a particle");
    }
    let mut on_gpu = GpuWorld::new(gpu, &cpu).expect("the GPU takes the world");
    cpu_steps(&mut cpu, 0..1);
    let first: Vec<f32> = cpu.particles().position.iter().map(|x| x.y).collect();
    assert!(
        (1..1000).any(|k| k % 16 != 0 && (first[k] - 2.05).abs() < 1e-3),
        "{method}: the floor stopped particles in the first step"
    );
    cpu_steps(&mut cpu, 1..60);
    for steps in [1, 40, 19] {
        on_gpu.step(gpu, DT as f32, steps).expect("steps");
    }
    let (x, v) = on_gpu.read_back(gpu).expect("read back");
    let cpu_x: Vec<Vec3> = cpu.particles().position.iter().map(Vec3::from).collect();
    let cpu_v: Vec<Vec3> = cpu.particles().velocity.iter().map(Vec3::from).collect();
    let start: Vec<Vec3> = (0..1000).filter_map(|k| p.position.get(k).map(Vec3::from)).collect();
    assert!(
        (1..1000).any(|k| k % 16 != 0 && (cpu_x[k] - start[k]).length() > 0.5),
        "the cloud pulled itself together"
    );
    let (dx, dv) = (differences(&x, &cpu_x), differences(&v, &cpu_v));
    assert_eq!(
        (dx.0, dv.0),
        (0, 0),
        "{method} with n-body: positions {dx:?}, velocities {dv:?}"
    );
}

#[test]
fn nbody_under_the_euler_methods_on_the_gpu_is_the_cpus_bit_for_bit() {
    nbody_matches_the_cpu("semi_implicit_euler");
    nbody_matches_the_cpu("explicit_euler");
}

#[test]
fn nbody_under_the_multi_stage_methods_on_the_gpu_is_the_cpus_bit_for_bit() {
    for method in ["midpoint", "heun", "rk4", "forest_ruth"] {
        nbody_matches_the_cpu(method);
    }
}

#[test]
fn nbody_under_the_methods_with_history_on_the_gpu_is_the_cpus_bit_for_bit() {
    for method in [
        "velocity_verlet",
        "leapfrog",
        "position_verlet",
        "beeman",
        "adams_bashforth2",
        "adams_bashforth3",
        "adams_bashforth4",
    ] {
        nbody_matches_the_cpu(method);
    }
}

/// A force of the game's own, a swirl about the y axis (`a += k (-v_z, 0,
/// v_x)`), with its GPU form written beside its CPU form: nothing of the
/// engine names it.
#[derive(Clone, Debug)]
struct Swirl {
    k: f32,
}

impl tickwork_engine::Force for Swirl {
    fn name(&self) -> &'static str {
        "swirl"
    }

    fn accumulate(&self, _t: f32, _first: usize, _x: &[Vec3A], v: &[Vec3A], _w: &[f32], out: &mut [Vec3A]) {
        for (a, v) in out.iter_mut().zip(v) {
            *a += Vec3A::new(-v.z, 0.0, v.x) * self.k;
        }
    }

    fn gpu_form(&self) -> GpuForce {
        GpuForce::Term
    }

    fn write_wgsl(&self, out: &mut dyn core::fmt::Write) -> core::fmt::Result {
        writeln!(out, "    a = a + vec3<f32>(-v.z, 0.0, v.x) * {};", WgslF32(self.k))
    }
}

#[test]
fn a_games_own_force_steps_on_the_gpu_from_its_own_wgsl_as_on_the_cpu() {
    let gpu = gpu();
    let mut cpu = world("rk4");
    cpu.add_force(Swirl { k: 0.7 });
    let mut on_gpu = GpuWorld::new(gpu, &cpu).expect("the GPU takes a force with a GPU form");
    cpu_steps(&mut cpu, 0..60);
    on_gpu.step(gpu, DT as f32, 60).expect("steps");
    let (x, v) = on_gpu.read_back(gpu).expect("read back");
    let p = cpu.particles();
    let cx: Vec<Vec3> = p.position.iter().map(Vec3::from).collect();
    let cv: Vec<Vec3> = p.velocity.iter().map(Vec3::from).collect();
    assert!(cv.iter().any(|v| v.z.abs() > 1.0), "the swirl turned the particles");
    assert_eq!((differences(&x, &cx).0, differences(&v, &cv).0), (0, 0));
    // Without a GPU form the GPU step names the force.
    #[derive(Clone, Debug)]
    struct Cpu;
    impl tickwork_engine::Force for Cpu {
        fn name(&self) -> &'static str {
            "cpu_only"
        }
        fn accumulate(&self, _: f32, _: usize, _: &[Vec3A], _: &[Vec3A], _: &[f32], _: &mut [Vec3A]) {}
    }
    let mut refused = world("rk4");
    refused.add_force(Cpu);
    let error = GpuWorld::new(gpu, &refused).expect_err("no GPU form");
    assert!(matches!(error, GpuStepError::Force { force: "cpu_only" }), "{error:?}");
}

#[test]
fn gpu_worlds_on_threads_sharing_one_device_read_back_every_time() {
    // Each wait on a shared device may run another thread's read-back
    // callback: every read-back still gets its answer.
    let gpu = gpu();
    let readers: Vec<_> = (0..4)
        .map(|_| {
            std::thread::spawn(move || {
                let cpu = world("semi_implicit_euler");
                let mut on_gpu = GpuWorld::new(gpu, &cpu).expect("a GPU world");
                for _ in 0..150 {
                    on_gpu.step(gpu, DT as f32, 1).expect("a step");
                    let (x, _) = on_gpu.read_back(gpu).expect("every read-back answered");
                    assert_eq!(x.len(), PARTICLES);
                }
            })
        })
        .collect();
    for reader in readers {
        reader.join().expect("a reader");
    }
}

#[test]
fn the_gpus_state_does_not_depend_on_how_its_steps_are_batched() {
    let gpu = gpu();
    let cpu = world("semi_implicit_euler");
    let (mut once, mut singly) = (
        GpuWorld::new(gpu, &cpu).expect("a GPU world"),
        GpuWorld::new(gpu, &cpu).expect("a GPU world"),
    );
    once.step(gpu, DT as f32, 90).expect("steps");
    for _ in 0..90 {
        singly.step(gpu, DT as f32, 1).expect("steps");
    }
    assert_eq!(once.ticks(), 90);
    let (a, b) = (once.read_back(gpu).expect("read"), singly.read_back(gpu).expect("read"));
    assert_eq!(differences(&a.0, &b.0).0 + differences(&a.1, &b.1).0, 0);
}

#[test]
fn what_the_gpu_step_does_not_do_is_refused_by_name() {
    let gpu = gpu();
    let refused = |world: &World| GpuWorld::new(gpu, world).expect_err("refused").to_string();
    assert_eq!(
        refused(&world("predictor_corrector_euler")),
        "the GPU step has no method \"predictor_corrector_euler\": not on the GPU yet (these are: explicit \
         and semi-implicit Euler, midpoint, Heun, RK4, Forest-Ruth, velocity Verlet, leapfrog, position Verlet, \
         Beeman and Adams-Bashforth 2-4)"
    );
    assert_eq!(
        refused(&world("implicit_euler")),
        "the GPU step has no method \"implicit_euler\": implicit and adaptive methods stay on the CPU"
    );
    let mut springs = world("semi_implicit_euler");
    springs.add_force(tickwork_engine::forces::Springs::default());
    assert_eq!(
        refused(&springs),
        "the GPU step does not evaluate the force \"springs\": it takes gravity, wind, linear and quadratic \
         drag, attractors and n-body"
    );
    let mut spheres = world("semi_implicit_euler");
    spheres.add_collider(tickwork_engine::SphereCollisions::new(Material::default()));
    assert_eq!(
        refused(&spheres),
        "the GPU step does not resolve this spheres: sphere-sphere collisions stay on the CPU (the GPU step \
         resolves planes and boxes)"
    );
    // A moving plane whose normal is no axis.
    let mut tilted = world("semi_implicit_euler");
    tilted.add_collider(Plane {
        speed: 0.5,
        normal: Vec3::new(0.6, 0.8, 0.0),
        ..Plane::floor(-1.0, Material::default())
    });
    assert_eq!(
        refused(&tilted),
        "the GPU step does not resolve this plane: its normal is not an axis"
    );
    // A world whose colliders report contacts steps by advance, which
    // reads them back each step; a batch would lose them.
    let mut reporting = world("semi_implicit_euler");
    let floor = reporting.colliders().next().map(|(id, _)| id).expect("a floor");
    reporting.report_contacts(floor).expect("reports");
    let mut on_gpu = GpuWorld::new(gpu, &reporting).expect("a GPU world");
    assert!(!on_gpu.steps_in_batches());
    assert_eq!(
        on_gpu.step(gpu, DT as f32, 1).map_err(|e| e.to_string()),
        Err(
            "the GPU step does not do steps in a batch of a world whose colliders report contacts: step it \
             with GpuWorld::advance, which reads them back step by step"
                .to_owned()
        )
    );
    let error = GpuWorld::new(gpu, &world("exponential_euler")).expect_err("refused");
    assert!(matches!(error, GpuStepError::Method { .. }), "{error}");
    // The rest of what the CPU's step does that the GPU's does not.
    let with = |change: &dyn Fn(&mut World)| {
        let mut w = world("semi_implicit_euler");
        change(&mut w);
        refused(&w)
    };
    assert_eq!(
        with(&|w| {
            w.add_collider(Plane {
                normal: Vec3::new(0.6, 0.8, 0.0),
                ..Plane::floor(-3.0, Material::default())
            });
        }),
        "the GPU step does not resolve this plane: its normal is not an axis"
    );
    assert_eq!(
        with(&|w| {
            w.add_sensor(tickwork_engine::Sensor::sphere(Vec3::ZERO, 1.0))
                .expect("a sensor");
        }),
        "the GPU step does not do sensors"
    );
    // Pairs past the world's limit, refused as the CPU's step refuses them.
    let mut crowded = World::new(WorldConfig {
        max_pairs: 1000,
        ..WorldConfig::default()
    })
    .expect("a world");
    crowded.add_force(NBody::new(1.0, 0.1));
    for k in 0..100 {
        crowded
            .spawn(Particle {
                position: Vec3::new(k as f32, 0.0, 0.0),
                ..Particle::default()
            })
            .expect("a particle");
    }
    assert_eq!(
        refused(&crowded),
        "the force \"nbody\" would take 4950 pairs a step, past WorldConfig::max_pairs (1000): raise it to allow \
         more"
    );
    // A step that is not finite and positive.
    let mut fine = GpuWorld::new(gpu, &world("semi_implicit_euler")).expect("a GPU world");
    for dt in [0.0, -1.0, f32::NAN, f32::INFINITY] {
        assert_eq!(
            fine.step(gpu, dt, 1).map_err(|e| e.to_string()),
            Err(format!("a GPU step of {dt} s: the step must be finite and positive"))
        );
    }
    assert_eq!(fine.ticks(), 0, "nothing was stepped");
    // Storing no steps changes nothing; steps of another length than the
    // last step's are refused; a state that became infinite is an error
    // naming its row, as the CPU's step makes it.
    let mut source = world("semi_implicit_euler");
    cpu_steps(&mut source, 0..3);
    let before = source.state_hash();
    let step = |tick: u64| FixedStep {
        tick,
        time: tick as f64 * DT,
        dt: DT,
    };
    let mut copy = GpuWorld::new(gpu, &source).expect("a GPU world");
    copy.store_into(gpu, &mut source, step(2)).expect("nothing to store");
    assert_eq!(source.state_hash(), before, "a GPU world of no steps stores nothing");
    copy.step(gpu, 0.01, 1).expect("steps");
    assert_eq!(
        copy.store_into(gpu, &mut source, step(3)).map_err(|e| e.to_string()),
        Err(
            "the GPU step does not do storing steps of different lengths, or of another length than the last \
             step's"
                .to_owned()
        )
    );
    let mut wild = World::default();
    wild.spawn(Particle::default()).expect("a particle");
    wild.spawn(Particle {
        position: Vec3::new(3.39e38, 0.0, 0.0),
        velocity: Vec3::new(3e38, 0.0, 0.0),
        ..Particle::default()
    })
    .expect("a particle");
    let mut escaping = GpuWorld::new(gpu, &wild).expect("a GPU world");
    escaping.step(gpu, DT as f32, 2).expect("steps");
    let error = escaping.store_into(gpu, &mut wild, step(1)).expect_err("infinite");
    assert!(
        error
            .to_string()
            .starts_with("the GPU's state of row 1 is not finite: position [inf"),
        "{error}"
    );
}

#[test]
fn a_gpu_world_is_drawn_from_its_own_buffers_as_its_cpu_twin_is_drawn() {
    use tickwork_engine::render::{Camera, FrameView, RendererConfig};
    let gpu = gpu();
    let mut cpu = world("semi_implicit_euler");
    let mut on_gpu = GpuWorld::new(gpu, &cpu).expect("the GPU takes the world");
    cpu_steps(&mut cpu, 0..45);
    on_gpu.step(gpu, DT as f32, 45).expect("steps");
    // Quads for both (no splat), between the last two steps.
    let config = RendererConfig {
        splat_threshold: Some(usize::MAX),
        ..RendererConfig::default()
    };
    let camera = Camera::TwoD {
        center: glam::Vec2::new(0.0, 5.0),
        height: 12.0,
    };
    let draw = |view: &FrameView<'_>| draw(view, config.clone(), (320, 180));
    let from_cpu = draw(&FrameView::new(&cpu, 0.5, camera));
    let empty = World::default();
    let particles = [on_gpu.particles()];
    let from_gpu = draw(&FrameView {
        gpu_particles: &particles,
        ..FrameView::new(&empty, 0.5, camera)
    });
    let lit = from_cpu.pixels().filter(|p| p.0[..3].iter().any(|&c| c > 40)).count();
    assert!(lit > 2000, "the particles are drawn: {lit} pixels");
    let differing = from_cpu.pixels().zip(from_gpu.pixels()).filter(|(a, b)| a != b).count();
    assert_eq!(
        differing, 0,
        "the GPU world's frame against its CPU twin's, pixel for pixel"
    );
}

#[test]
fn a_gpu_world_is_drawn_along_hermite_curves_by_quads_and_by_the_splat_as_its_cpu_twin() {
    use tickwork_engine::interpolation::Interpolation;
    use tickwork_engine::render::{Camera, FrameView, RendererConfig};
    let gpu = gpu();
    let mut cpu = world("velocity_verlet");
    let mut on_gpu = GpuWorld::new(gpu, &cpu).expect("the GPU takes the world");
    cpu_steps(&mut cpu, 0..30);
    on_gpu.step(gpu, DT as f32, 30).expect("steps");
    let camera = Camera::TwoD {
        center: glam::Vec2::new(0.0, 5.0),
        height: 12.0,
    };
    let empty = World::default();
    let particles = [on_gpu.particles()];
    for (path, splat_threshold) in [("quads", usize::MAX), ("the splat", 0)] {
        let config = RendererConfig {
            splat_threshold: Some(splat_threshold),
            interpolation: Interpolation::Hermite { dt: DT as f32 },
            ..RendererConfig::default()
        };
        let draw = |view: &FrameView<'_>| draw(view, config.clone(), (320, 180));
        let from_cpu = draw(&FrameView::new(&cpu, 0.3, camera));
        let from_gpu = draw(&FrameView {
            gpu_particles: &particles,
            ..FrameView::new(&empty, 0.3, camera)
        });
        // The curve differs from the straight line: Hermite was drawn.
        let linear = {
            let config = RendererConfig {
                interpolation: Interpolation::Interpolate,
                ..config.clone()
            };
            crate::support::draw(&FrameView::new(&cpu, 0.3, camera), config, (320, 180))
        };
        let curved = from_cpu.pixels().zip(linear.pixels()).filter(|(a, b)| a != b).count();
        assert!(curved > 50, "{path}: Hermite and linear differ in {curved} pixels");
        let differing = from_cpu.pixels().zip(from_gpu.pixels()).filter(|(a, b)| a != b).count();
        assert_eq!(
            differing, 0,
            "{path}: the GPU world's Hermite frame against its CPU twin's"
        );
    }
}

/// A fountain's world: two jets of particles living 0.3 s and 0.55 s (so
/// expiry removes rows all through the columns), 300 particles of a
/// lattice, a third of them living 1 s, under gravity, wind and
/// quadratic drag, on a floor.
fn fountain(method: &str) -> World {
    let mut world = World::new(WorldConfig {
        integrator: method.into(),
        seed: 11,
        ..WorldConfig::default()
    })
    .expect("a world");
    world.add_force(Gravity::EARTH);
    world.add_force(Wind {
        velocity: Vec3::ZERO,
        rate: 0.0,
    });
    world.add_force(QuadraticDrag { coefficient: 0.02 });
    world.add_collider(Plane::floor(
        0.0,
        Material {
            restitution: 0.45,
            friction: 0.15,
        },
    ));
    for (x, rate, lifetime) in [(-1.0, 600.0, 0.3), (1.0, 450.0, 0.55)] {
        world
            .add_emitter(tickwork_engine::Emitter {
                position: Vec3::new(x, 0.1, 0.0),
                rate,
                lifetime,
                speed: 6.0,
                ..Default::default()
            })
            .expect("an emitter");
    }
    for k in 0..300 {
        world
            .spawn(Particle {
                position: Vec3::new((k % 20) as f32 * 0.2, 1.0 + (k / 20) as f32 * 0.2, 0.0),
                lifetime: (k % 3 == 0).then_some(1.0),
                ..Particle::default()
            })
            .expect("a particle");
    }
    all_end_of_step(&mut world);
    world
}

/// What a game does to its fountain between steps, on either copy: a
/// wind from tick 20, a spawn and a despawn now (tick 30) and queued
/// (tick 45), a stronger jet from tick 50 (the GPU's buffers grow), the
/// floor removed at tick 70.
fn play(world: &mut World, tick: u64) {
    match tick {
        20 => {
            if let Some(wind) = world.force_mut::<Wind>() {
                *wind = Wind {
                    velocity: Vec3::new(4.0, 0.0, 0.0),
                    rate: 0.5,
                };
            }
        }
        30 | 45 => {
            let entity = world.entities().rows()[7];
            let particle = Particle {
                position: Vec3::new(0.0, 3.0, 0.0),
                velocity: Vec3::new(1.0, 2.0, 0.0),
                ..Particle::default()
            };
            if tick == 30 {
                world.despawn(entity).expect("a despawn");
                world.spawn(particle).expect("a spawn");
            } else {
                world.queue_despawn(entity).expect("a despawn");
                world.queue_spawn(particle).expect("a spawn");
            }
        }
        50 => world.emitters_mut()[1].rate = 6000.0,
        70 => {
            let floor = world.colliders().next().map(|(id, _)| id).expect("a floor");
            world.remove_collider(floor).expect("removed");
        }
        _ => {}
    }
}

fn a_fountain_matches_the_cpu(method: &str) {
    let gpu = gpu();
    let mut cpu = fountain(method);
    let mut on_gpu_world = cpu.clone();
    let mut on_gpu = GpuWorld::new(gpu, &on_gpu_world).expect("a GPU world");
    assert_eq!(
        on_gpu.step(gpu, DT as f32, 1).expect_err("refused").to_string(),
        "the GPU step does not do steps in a batch of a world whose rows change (emitters, lifetimes, queued \
         spawns or despawns): step it with GpuWorld::advance, which follows them"
    );
    let (mut expired, mut spawned) = (0, 0);
    for tick in 0..90 {
        let step = FixedStep {
            tick,
            time: tick as f64 * DT,
            dt: DT,
        };
        play(&mut cpu, tick);
        play(&mut on_gpu_world, tick);
        let report = cpu.step(step).expect("a step");
        let on_gpu_report = on_gpu.advance(gpu, &mut on_gpu_world, step).expect("a GPU step");
        assert_eq!(
            (report.expired, report.spawned),
            (on_gpu_report.expired, on_gpu_report.spawned)
        );
        (expired, spawned) = (expired + report.expired, spawned + report.spawned);
        assert_eq!(on_gpu.len(), cpu.len(), "tick {tick}");
    }
    // Rows removed all through the columns and added at the end, and
    // the buffers grown past what they were made with.
    assert!(expired > 1000 && spawned > 2000, "{expired} expired, {spawned} spawned");
    assert!(cpu.len() > 2 * 300, "{} particles", cpu.len());
    let last = FixedStep {
        tick: 89,
        time: 89.0 * DT,
        dt: DT,
    };
    on_gpu.store_into(gpu, &mut on_gpu_world, last).expect("stored");
    let (x, v) = on_gpu.read_back(gpu).expect("read");
    let cpu_x: Vec<Vec3> = cpu.particles().position.iter().map(Vec3::from).collect();
    let cpu_v: Vec<Vec3> = cpu.particles().velocity.iter().map(Vec3::from).collect();
    assert_eq!(differences(&x, &cpu_x), (0, 0.0), "{method}: positions");
    assert_eq!(differences(&v, &cpu_v), (0, 0.0), "{method}: velocities");
    // (The checksum covers a method's history too, which stays on the GPU.)
    let has_history = with_history(method);
    if !has_history {
        assert_eq!(on_gpu_world.state_hash(), cpu.state_hash(), "{method}: checksum");
    }
    // Stored, it steps on, the world still followed.
    let step = FixedStep {
        tick: 90,
        time: 90.0 * DT,
        dt: DT,
    };
    cpu.step(step).expect("a step");
    on_gpu.advance(gpu, &mut on_gpu_world, step).expect("a GPU step");
    on_gpu.store_into(gpu, &mut on_gpu_world, step).expect("stored");
    let (x, v) = on_gpu.read_back(gpu).expect("read");
    let cpu_x: Vec<Vec3> = cpu.particles().position.iter().map(Vec3::from).collect();
    let cpu_v: Vec<Vec3> = cpu.particles().velocity.iter().map(Vec3::from).collect();
    assert_eq!(
        differences(&x, &cpu_x).0 + differences(&v, &cpu_v).0,
        0,
        "{method}: one more step"
    );
    if !has_history {
        assert_eq!(
            on_gpu_world.state_hash(),
            cpu.state_hash(),
            "{method}: checksum after one more step"
        );
    }
}

#[test]
fn a_fountain_under_semi_implicit_euler_follows_the_cpus_rows_bit_for_bit() {
    a_fountain_matches_the_cpu("semi_implicit_euler");
}

#[test]
fn a_fountain_under_rk4_follows_the_cpus_rows_bit_for_bit() {
    a_fountain_matches_the_cpu("rk4");
}

#[test]
fn a_fountain_under_the_methods_with_history_follows_the_cpus_rows_bit_for_bit() {
    // Rows come and go every step: histories move with their rows, new
    // rows start without.
    for method in ["velocity_verlet", "position_verlet", "beeman", "adams_bashforth4"] {
        a_fountain_matches_the_cpu(method);
    }
}

/// A small fountain whose particles pull on one another (n-body) as rows
/// come and go (two jets, lifetimes, a spawn and a despawn), stepped by
/// `method` on the CPU and by `GpuWorld::advance`: bit for bit after 60
/// steps, the GPU's rounds of sums following the rows and growing with
/// them, and new rows starting by RK4 while the others go on.
fn an_nbody_fountain_matches_the_cpu(method: &str) {
    let gpu = gpu();
    let mut cpu = World::new(WorldConfig {
        integrator: method.into(),
        seed: 5,
        ..WorldConfig::default()
    })
    .expect("a world");
    cpu.add_force(Gravity::EARTH);
    cpu.add_force(NBody::new(0.5, 0.1));
    cpu.add_collider(Plane::floor(
        0.0,
        Material {
            restitution: 0.5,
            friction: 0.0,
        },
    ));
    all_end_of_step(&mut cpu);
    for (x, rate, lifetime) in [(-0.5, 240.0, 0.25), (0.5, 180.0, 0.5)] {
        cpu.add_emitter(tickwork_engine::Emitter {
            position: Vec3::new(x, 0.1, 0.0),
            rate,
            lifetime,
            speed: 4.0,
            ..Default::default()
        })
        .expect("an emitter");
    }
    for k in 0..100 {
        cpu.spawn(Particle {
            position: Vec3::new((k % 10) as f32 * 0.3, 1.0 + (k / 10) as f32 * 0.3, 0.0),
            lifetime: (k % 4 == 0).then_some(0.4),
            ..Particle::default()
        })
        .expect("a particle");
    }
    let mut twin = cpu.clone();
    let mut on_gpu = GpuWorld::new(gpu, &twin).expect("a GPU world");
    let (mut expired, mut spawned) = (0, 0);
    for tick in 0..60 {
        let step = FixedStep {
            tick,
            time: tick as f64 * DT,
            dt: DT,
        };
        if tick == 30 {
            for world in [&mut cpu, &mut twin] {
                // A row the last step had: the last row, appended since,
                // moves into it.
                let entity = world.entities().rows()[3];
                world.despawn(entity).expect("a despawn");
            }
        }
        let report = cpu.step(step).expect("a step");
        on_gpu.advance(gpu, &mut twin, step).expect("a GPU step");
        (expired, spawned) = (expired + report.expired, spawned + report.spawned);
        assert_eq!(on_gpu.len(), cpu.len(), "tick {tick}");
    }
    assert!(expired > 50 && spawned > 200, "{expired} expired, {spawned} spawned");
    let (x, v) = on_gpu.read_back(gpu).expect("read");
    let cpu_x: Vec<Vec3> = cpu.particles().position.iter().map(Vec3::from).collect();
    let cpu_v: Vec<Vec3> = cpu.particles().velocity.iter().map(Vec3::from).collect();
    assert_eq!(differences(&x, &cpu_x), (0, 0.0), "{method} with n-body: positions");
    assert_eq!(differences(&v, &cpu_v), (0, 0.0), "{method} with n-body: velocities");
}

#[test]
fn an_nbody_fountain_follows_the_cpus_rows_bit_for_bit() {
    for method in ["semi_implicit_euler", "rk4", "beeman", "adams_bashforth4"] {
        an_nbody_fountain_matches_the_cpu(method);
    }
}

#[test]
fn a_gpu_worlds_particles_changed_between_steps_are_refused() {
    let gpu = gpu();
    let mut world = fountain("semi_implicit_euler");
    let mut on_gpu = GpuWorld::new(gpu, &world).expect("a GPU world");
    let step = |tick: u64| FixedStep {
        tick,
        time: tick as f64 * DT,
        dt: DT,
    };
    on_gpu.advance(gpu, &mut world, step(0)).expect("a step");
    let entity = world.entities().rows()[0];
    world.set_velocity(entity, Vec3::X).expect("set");
    assert_eq!(on_gpu.advance(gpu, &mut world, step(1)), Err(GpuStepError::Edited));
    assert!(
        GpuStepError::Edited
            .to_string()
            .starts_with("the particles of a GPU world were changed outside its steps (particles_mut, set_velocity")
    );
    // Made again from the world as it is, it goes on.
    let mut on_gpu = GpuWorld::new(gpu, &world).expect("a GPU world");
    on_gpu.advance(gpu, &mut world, step(1)).expect("a step");
    assert!(
        on_gpu.advance(gpu, &mut world, step(5)).is_err(),
        "a step from another tick"
    );
}

/// The test world with a ceiling coming down at 1.5 m/s, and the material
/// of the kinematic colliders.
fn with_ceiling(method: &str) -> (World, Material) {
    let mut world = world(method);
    let material = Material {
        restitution: 0.7,
        friction: 0.1,
    };
    world.add_collider(Plane {
        normal: Vec3::NEG_Y,
        offset: -9.0,
        speed: 1.5,
        ..Plane::floor(0.0, material)
    });
    (world, material)
}

/// The test world with kinematic colliders: a ceiling coming down at
/// 1.5 m/s, a solid block sliding through the particles and a small
/// container rising around some of them, all resolved in their own frame
/// as the CPU does.
fn kinematic_world(method: &str) -> World {
    let (mut world, material) = with_ceiling(method);
    world.add_collider(BoxCollider {
        velocity: Vec3::new(2.0, 0.5, 0.0),
        ..BoxCollider::solid(Vec3::new(-4.0, 1.0, -3.0), Vec3::new(-1.0, 4.0, 3.0), material)
    });
    world.add_collider(BoxCollider {
        velocity: Vec3::new(0.0, 0.8, -0.4),
        ..BoxCollider::container(Vec3::new(0.0, 2.0, -2.0), Vec3::new(3.0, 5.0, 1.0), material)
    });
    all_end_of_step(&mut world);
    world
}

fn kinematic_colliders_match_the_cpu(method: &str) {
    let gpu = gpu();
    let mut cpu = kinematic_world(method);
    let mut on_gpu_world = cpu.clone();
    let mut on_gpu = GpuWorld::new(gpu, &on_gpu_world).expect("a GPU world");
    assert!(!on_gpu.steps_in_batches());
    assert!(
        on_gpu
            .step(gpu, DT as f32, 1)
            .expect_err("refused")
            .to_string()
            .contains("a moving collider: step it with GpuWorld::advance")
    );
    let mut still = world(method);
    for tick in 0..120 {
        let step = FixedStep {
            tick,
            time: tick as f64 * DT,
            dt: DT,
        };
        cpu.step(step).expect("a step");
        still.step(step).expect("a step");
        on_gpu.advance(gpu, &mut on_gpu_world, step).expect("a GPU step");
    }
    let last = FixedStep {
        tick: 119,
        time: 119.0 * DT,
        dt: DT,
    };
    on_gpu.store_into(gpu, &mut on_gpu_world, last).expect("stored");
    let p = cpu.particles();
    let (cx, cv): (Vec<Vec3>, Vec<Vec3>) = (
        p.position.iter().map(Vec3::from).collect(),
        p.velocity.iter().map(Vec3::from).collect(),
    );
    let (x, v) = on_gpu.read_back(gpu).expect("read");
    assert_eq!(differences(&x, &cx).0 + differences(&v, &cv).0, 0, "{method}");
    if !with_history(method) {
        assert_eq!(on_gpu_world.state_hash(), cpu.state_hash(), "{method}: checksum");
    }
    // The kinematic colliders met particles: without them, another state.
    let without: Vec<Vec3> = still.particles().position.iter().map(Vec3::from).collect();
    let (moved, _) = differences(&cx, &without);
    assert!(
        moved > 300,
        "{method}: only {moved} components differ without the kinematic colliders"
    );
}

#[test]
fn kinematic_planes_and_boxes_on_the_gpu_are_the_cpus_bit_for_bit() {
    for method in ["semi_implicit_euler", "rk4", "velocity_verlet"] {
        kinematic_colliders_match_the_cpu(method);
    }
}

#[test]
fn contacts_of_reporting_colliders_are_the_cpus_step_by_step() {
    // The fountain's floor reports its contacts, and so does a paddle
    // sweeping through the jets; rows come and go every step, and each
    // contact is named by the entity it had when the step found it.
    let gpu = gpu();
    let mut cpu = fountain("semi_implicit_euler");
    let floor = cpu.colliders().next().map(|(id, _)| id).expect("a floor");
    cpu.report_contacts(floor).expect("reports");
    let paddle = cpu.add_collider(BoxCollider {
        velocity: Vec3::new(1.5, 0.0, 0.0),
        contact: tickwork_engine::colliders::ContactRule::EndOfStep,
        ..BoxCollider::solid(
            Vec3::new(-2.5, 1.0, -1.0),
            Vec3::new(-1.5, 1.3, 1.0),
            Material {
                restitution: 0.9,
                friction: 0.2,
            },
        )
    });
    cpu.report_contacts(paddle).expect("reports");
    let mut on_gpu_world = cpu.clone();
    let mut on_gpu = GpuWorld::new(gpu, &on_gpu_world).expect("a GPU world");
    let (mut on_floor, mut on_paddle) = (0, 0);
    for tick in 0..90 {
        let step = FixedStep {
            tick,
            time: tick as f64 * DT,
            dt: DT,
        };
        cpu.step(step).expect("a step");
        on_gpu.advance(gpu, &mut on_gpu_world, step).expect("a GPU step");
        assert_eq!(on_gpu_world.contacts(), cpu.contacts(), "tick {tick}");
        for contact in cpu.contacts() {
            match contact.touched {
                tickwork_engine::colliders::Touched::Collider(id) if id == floor => on_floor += 1,
                tickwork_engine::colliders::Touched::Collider(id) if id == paddle => on_paddle += 1,
                _ => {}
            }
        }
    }
    assert!(
        on_floor > 100 && on_paddle > 20,
        "{on_floor} floor and {on_paddle} paddle contacts"
    );
}

#[test]
fn a_playback_moved_between_the_gpu_and_the_cpu_keeps_its_state() {
    // The fountain scene (emitter, lifetimes, a floor) played on the GPU,
    // then on the CPU from where the GPU left it, ends where a CPU-only
    // playback ends: nothing of the GPU's steps is lost in the move.
    use tickwork_engine::Scene;
    use tickwork_engine::app::{FrameSource, Playback};
    use tickwork_engine::world::Backend;
    let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../assets/scenes/fountain.ron");
    let scene = Scene::load(&path).expect("scene");
    let gpu = gpu();
    let mut cpu = Playback::from_scene(&scene, None).expect("playback");
    let mut moved = Playback::from_scene_on(&scene, None, Some(Backend::Gpu)).expect("playback");
    moved.attach_gpu(gpu);
    for _ in 0..30 {
        cpu.advance(1.0 / 60.0).expect("a frame");
        moved.advance(1.0 / 60.0).expect("a frame");
    }
    moved.world_mut().set_backend(Backend::Cpu);
    for _ in 0..30 {
        cpu.advance(1.0 / 60.0).expect("a frame");
        moved.advance(1.0 / 60.0).expect("a frame");
    }
    assert_eq!(moved.world().tick(), 60);
    assert!(moved.world().len() > 1000, "{} particles", moved.world().len());
    assert_eq!(moved.world().state_hash(), cpu.world().state_hash());
}

/// Every plane and box of `world` finds its contacts inside the step.
fn all_in_step(world: &mut World) {
    every_rule(world, tickwork_engine::colliders::ContactRule::InStep);
}

/// Components of `a` and `b` further apart than `tolerance` (absolute,
/// metres or m/s), and the largest difference.
fn beyond(a: &[Vec3], b: &[Vec3], tolerance: f32) -> (usize, f32) {
    let mut count = 0;
    let mut largest = 0.0f32;
    for (p, q) in a.iter().zip(b) {
        let d = (*p - *q).abs().max_element();
        largest = largest.max(d);
        count += usize::from(d > tolerance || d.is_nan());
    }
    (count, largest)
}

/// The test world with a ceiling coming down at 1.5 m/s and a paddle
/// sweeping through the particles above the solid block (no collider
/// overlaps another: none pinches a particle).
fn in_step_world(method: &str) -> World {
    let (mut world, material) = with_ceiling(method);
    world.add_collider(BoxCollider {
        velocity: Vec3::new(-2.0, 0.0, 0.0),
        ..BoxCollider::solid(Vec3::new(3.0, 4.5, -3.0), Vec3::new(4.0, 5.5, 3.0), material)
    });
    all_end_of_step(&mut world);
    world
}

fn in_step_matches_the_cpu(method: &str) {
    let gpu = gpu();
    let mut cpu = in_step_world(method);
    all_in_step(&mut cpu);
    let floor = cpu.colliders().next().map(|(id, _)| id).expect("a floor");
    cpu.report_contacts(floor).expect("reports");
    let mut on_gpu_world = cpu.clone();
    let mut on_gpu = GpuWorld::new(gpu, &on_gpu_world).expect("a GPU world");
    let mut end_of_step = in_step_world(method);
    let (mut contacts, mut inside) = (0, 0);
    for tick in 0..120 {
        let step = FixedStep {
            tick,
            time: tick as f64 * DT,
            dt: DT,
        };
        cpu.step(step).expect("a step");
        end_of_step.step(step).expect("a step");
        on_gpu.advance(gpu, &mut on_gpu_world, step).expect("a GPU step");
        let (a, b) = (cpu.contacts(), on_gpu_world.contacts());
        contacts += a.len();
        // The same contacts, at the same instants to f32 rounding.
        let mut matched = 0;
        for c in a {
            inside += usize::from(c.fraction < 1.0);
            matched += usize::from(b.iter().any(|g| {
                g.entity == c.entity
                    && g.touched == c.touched
                    && (g.fraction - c.fraction).abs() <= 1e-3
                    && (g.point - c.point).abs().max_element() <= 1e-3
            }));
        }
        assert!(
            a.len().abs_diff(b.len()) <= 1 && matched + 1 >= a.len(),
            "{method}, tick {tick}: {} contacts on the CPU, {} on the GPU, {matched} alike",
            a.len(),
            b.len()
        );
    }
    let p = cpu.particles();
    let (cx, cv): (Vec<Vec3>, Vec<Vec3>) = (
        p.position.iter().map(Vec3::from).collect(),
        p.velocity.iter().map(Vec3::from).collect(),
    );
    let (x, v) = on_gpu.read_back(gpu).expect("read");
    let (far_x, largest_x) = beyond(&x, &cx, 1e-3);
    let (far_v, largest_v) = beyond(&v, &cv, 1e-2);
    eprintln!(
        "{method}: {contacts} floor contacts ({inside} inside the step); positions: {far_x} beyond 1 mm (largest {largest_x}), velocities: {far_v} beyond 1 cm/s (largest {largest_v})"
    );
    assert!(
        far_x <= 2 && far_v <= 2,
        "{method}: {far_x} positions beyond 1 mm (largest {largest_x}), {far_v} velocities beyond 1 cm/s (largest {largest_v})"
    );
    assert!(
        contacts > 100 && inside > 50,
        "{method}: {contacts} contacts, {inside} inside the step"
    );
    // The rule made a difference: the end-of-step run is another state.
    let other: Vec<Vec3> = end_of_step.particles().position.iter().map(Vec3::from).collect();
    let (apart, _) = beyond(&other, &cx, 1e-2);
    assert!(
        apart > 100,
        "{method}: only {apart} particles moved by the in-step rule"
    );
}

#[test]
fn in_step_planes_and_boxes_on_the_gpu_match_the_cpu_to_f32_rounding() {
    for method in ["semi_implicit_euler", "rk4", "velocity_verlet"] {
        in_step_matches_the_cpu(method);
    }
}

/// Particles at 10, 100, 1 000 and 10 000 m/s fired along +x from x = -5
/// at `wall` (its near face at x = 0) on the GPU at `hz`: where each ends
/// and its velocity, after long enough to come back past its start.
fn fire_on_the_gpu(hz: f64, wall: impl FnOnce(&mut World)) -> Vec<(f32, Vec3, Vec3)> {
    use tickwork_engine::colliders::ContactRule;
    let gpu = gpu();
    let mut w = World::new(WorldConfig::default()).expect("a world");
    wall(&mut w);
    all_in_step(&mut w);
    assert!(w.colliders().all(|(_, c)| c.in_step()), "{:?}", ContactRule::InStep);
    let speeds = [10.0f32, 100.0, 1_000.0, 10_000.0];
    for (k, speed) in speeds.iter().enumerate() {
        w.spawn(Particle {
            position: Vec3::new(-5.0, -0.6 + 0.4 * k as f32, 0.0),
            velocity: Vec3::new(*speed, 0.0, 0.0),
            radius: 0.005,
            ..Particle::default()
        })
        .expect("a particle");
    }
    let mut on_gpu = GpuWorld::new(gpu, &w).expect("a GPU world");
    let dt = 1.0 / hz;
    // The slowest, 10 m/s, from 5 m away and back past its start.
    let steps = (1.2 / dt).ceil() as u64;
    for tick in 0..steps {
        let step = FixedStep {
            tick,
            time: tick as f64 * dt,
            dt,
        };
        on_gpu.advance(gpu, &mut w, step).expect("a GPU step");
    }
    let (x, v) = on_gpu.read_back(gpu).expect("read");
    speeds.iter().zip(x).zip(v).map(|((s, x), v)| (*s, x, v)).collect()
}

#[test]
fn no_particle_passes_a_wall_a_thin_box_or_a_paddle_on_the_gpu() {
    let elastic = Material {
        restitution: 1.0,
        friction: 0.0,
    };
    for hz in [30.0, 60.0, 240.0] {
        // A plane facing -x at x = 0, and a solid box 1 cm thick.
        let plane = |w: &mut World| {
            w.add_collider(Plane {
                normal: Vec3::NEG_X,
                offset: 0.0,
                ..Plane::floor(0.0, elastic)
            });
        };
        let thin = |w: &mut World| {
            w.add_collider(BoxCollider::solid(
                Vec3::new(0.0, -1.0, -1.0),
                Vec3::new(0.01, 1.0, 1.0),
                elastic,
            ));
        };
        for (name, ends) in [("wall", fire_on_the_gpu(hz, plane)), ("box", fire_on_the_gpu(hz, thin))] {
            for (speed, x, v) in ends {
                assert!(
                    x.x < -5.0 && (v.x + speed).abs() <= 1e-3 * speed,
                    "{speed} m/s at {hz} Hz off the {name}: x {x}, v {v}"
                );
            }
        }
        // A paddle 2 cm thick at x = 6, coming at them at 20 m/s: met
        // before x = 0 by all but the slowest, handed its speed (elastic
        // off a wall moving at u: v' = 2u - v).
        let paddle = |w: &mut World| {
            w.add_collider(BoxCollider {
                velocity: Vec3::new(-20.0, 0.0, 0.0),
                ..BoxCollider::solid(Vec3::new(6.0, -1.0, -1.0), Vec3::new(6.02, 1.0, 1.0), elastic)
            });
        };
        for (speed, x, v) in fire_on_the_gpu(hz, paddle) {
            let wanted = 2.0 * -20.0 - speed;
            assert!(
                x.x < -5.0 && (v.x - wanted).abs() <= 1e-3 * wanted.abs(),
                "{speed} m/s at {hz} Hz off the paddle: x {x}, v {v} (wanted {wanted})"
            );
        }
    }
}

#[test]
fn an_elastic_ball_keeps_its_height_for_a_hundred_bounces_on_the_gpu() {
    // Velocity Verlet under gravity onto an elastic floor at 60 Hz,
    // dropped from 10 m: the energy's height after 100 bounces (286 s)
    // within 1e-4 m, as the CPU's f64 path keeps it (4.4e-5 on lavapipe:
    // f32 rounding at each bounce is about 1e-6 of 10 m).
    use tickwork_engine::colliders::ContactRule;
    let gpu = gpu();
    let mut w = World::new(WorldConfig {
        integrator: "velocity_verlet".into(),
        ..WorldConfig::default()
    })
    .expect("a world");
    w.add_force(Gravity::EARTH);
    w.add_collider(Plane {
        contact: ContactRule::InStep,
        ..Plane::floor(
            0.0,
            Material {
                restitution: 1.0,
                friction: 0.0,
            },
        )
    });
    w.spawn(Particle {
        position: Vec3::new(0.0, 10.0, 0.0),
        ..Particle::default()
    })
    .expect("a ball");
    let mut on_gpu = GpuWorld::new(gpu, &w).expect("a GPU world");
    let g = 9.81f32;
    let steps = (100.0 * 2.0 * (2.0 * 10.0 / f64::from(g)).sqrt() / DT).ceil() as u32;
    on_gpu.step(gpu, DT as f32, steps).expect("GPU steps");
    let (x, v) = on_gpu.read_back(gpu).expect("read");
    let height = x[0].y + v[0].y * v[0].y / (2.0 * g);
    eprintln!("GPU, velocity Verlet, in-step floor: the energy's height after {steps} steps: {height} m");
    assert!(
        (height - 10.0).abs() <= 1e-4,
        "after {steps} steps: height {height} (y {}, v {})",
        x[0].y,
        v[0].y
    );
    // Its end-of-step twin gains height at every bounce.
    let floor = w.colliders().next().map(|(id, _)| id).expect("the floor");
    w.collider_mut::<Plane>(floor).expect("a plane").contact = ContactRule::EndOfStep;
    let mut twin = GpuWorld::new(gpu, &w).expect("a GPU world");
    twin.step(gpu, DT as f32, steps).expect("GPU steps");
    let (x, v) = twin.read_back(gpu).expect("read");
    let gained = x[0].y + v[0].y * v[0].y / (2.0 * g) - 10.0;
    assert!(gained > 0.5, "end of step: {gained} m gained");
}

#[test]
fn a_step_past_the_room_for_contacts_is_whole_names_the_room_and_the_next_has_more() {
    // 100 particles at 100 m/s inside a reporting container 2 mm wide:
    // each meets the in-step limit of contacts every step, more than the
    // room of two a particle and 1 024.
    let gpu = gpu();
    let mut w = World::new(WorldConfig::default()).expect("a world");
    let room = w.add_collider(BoxCollider::container(
        Vec3::new(-0.001, -1.0, -1.0),
        Vec3::new(0.001, 1.0, 1.0),
        Material {
            restitution: 1.0,
            friction: 0.0,
        },
    ));
    w.report_contacts(room).expect("reports");
    for k in 0..100 {
        w.spawn(Particle {
            position: Vec3::new(0.0, -0.9 + 0.018 * k as f32, 0.0),
            velocity: Vec3::new(100.0, 0.0, 0.0),
            radius: 0.0,
            ..Particle::default()
        })
        .expect("a particle");
    }
    let mut on_gpu = GpuWorld::new(gpu, &w).expect("a GPU world");
    let step = |tick: u64| FixedStep {
        tick,
        time: tick as f64 * DT,
        dt: DT,
    };
    let error = on_gpu.advance(gpu, &mut w, step(0)).expect_err("past the room");
    let GpuStepError::Contacts { found, room } = error else {
        panic!("{error}");
    };
    assert_eq!(room, 2 * 100 + 1024);
    assert!(found > room, "{found} in a room of {room}");
    assert_eq!(w.contacts().len(), room as usize);
    assert!(
        error.to_string().contains(&format!("found {found} contacts")),
        "{error}"
    );
    // The step was whole: the next one follows it, with room for them all;
    // every particle ends inside, to the rounding of the projection.
    assert_eq!(w.tick(), 1);
    on_gpu.advance(gpu, &mut w, step(1)).expect("the next step");
    let inside = w.contacts().iter().filter(|c| c.fraction < 1.0).count();
    assert!(inside > room as usize, "{inside} contacts inside the step");
    let (x, _) = on_gpu.read_back(gpu).expect("read");
    let far = x.iter().map(|p| p.x.abs()).fold(0.0f32, f32::max);
    assert!(far <= 0.001 + 1e-6, "all in the container: {far} {:?}", &x[..3]);
}

//! Steady-state steps allocate nothing on any thread, rayon's workers
//! included, at 1k particles (one lane) and at 100k and 1M (two lanes), and
//! with 20k colliding spheres (their slabs solved on two threads).
//! Its own test binary with one test, for two process-wide settings: the
//! counter is the process's (`counting::process`), so no other test may
//! allocate while it counts, and the test's thread joins rayon's global
//! pool, which only the first user of rayon in a process can do.

#[path = "../../tests/support/counting_alloc.rs"]
mod counting;

#[global_allocator]
static GLOBAL: counting::Counting = counting::Counting;

use counting::process;
use glam::Vec3;
use tickwork_engine::{FixedStep, Gravity, LinearDrag, Material, Particle, Plane, World, WorldConfig};

fn world(n: usize, method: &str) -> World {
    let mut w = World::new(WorldConfig {
        integrator: method.into(),
        // Two lanes from 100k (on two or more cores).
        parallel_threshold: 50_000,
        ..WorldConfig::default()
    })
    .expect("known");
    w.add_force(Gravity::EARTH);
    w.add_force(LinearDrag { rate: 0.1 });
    w.add_collider(Plane::floor(0.0, Material::default()));
    for i in 0..n {
        let p = Particle {
            position: Vec3::new((i % 1000) as f32 * 0.01, 0.5 + (i / 1000) as f32 * 0.001, 0.0),
            velocity: Vec3::new(0.0, (i % 7) as f32, 0.0),
            radius: 0.004,
            // Some mortal particles, so expiry's bookkeeping runs too.
            lifetime: (i % 10 == 0).then_some(1e6),
            ..Particle::default()
        };
        w.spawn(p).expect("spawn");
    }
    w
}

/// Allocations in 32 steps after 8 warming ones (buffers grow, history
/// methods start, the pool's queues fill), and the lanes the last step used.
fn steady_allocations(w: &mut World) -> (usize, u32) {
    let dt = 1.0 / 60.0;
    let step = |w: &mut World, tick: u64| {
        w.step(FixedStep {
            tick,
            time: tick as f64 * dt,
            dt,
        })
        .expect("step")
    };
    for tick in 0..8 {
        step(w, tick);
    }
    let before = process();
    let mut used = 0;
    for tick in 8..40 {
        used = step(w, tick).fused_lanes;
    }
    (process() - before, used)
}

#[test]
fn steady_steps_allocate_nothing_on_any_thread_at_1k_100k_and_1m() {
    // The stepping thread is one of the pool's two: its joins go to its own
    // deque (reused), not to the pool's injector, whose queue allocates a
    // block every 63 jobs sent from outside the pool.
    tickwork_engine::threads::join_thread_pool().expect("the global pool, once");
    let mut failures = Vec::new();
    let threads = rayon::current_num_threads();
    assert!(
        threads >= 2,
        "two lanes need two cores; this machine gives rayon {threads}"
    );
    for (n, lanes) in [(1_000, 1), (100_000, threads), (1_000_000, threads)] {
        // Methods with per-particle state (cached accelerations, history)
        // step whole slices, on no lane (0).
        for (method, splits) in [
            ("semi_implicit_euler", true),
            ("rk4", true),
            ("velocity_verlet", false),
            ("adams_bashforth3", false),
        ] {
            let lanes = if splits { lanes as u32 } else { 0 };
            let (allocated, used) = steady_allocations(&mut world(n, method));
            if allocated != 0 || used != lanes {
                failures.push(format!(
                    "{n} particles, {method}: {allocated} allocations in 32 steps on {used} lanes (expected {lanes})"
                ));
            }
        }
    }
    // 20 000 colliding spheres settling in a box (the crowd scene, smaller):
    // the grid's scratch, and the slabs, gathers and write-back on rayon's
    // threads.
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/scenes/crowd.ron");
    let text = std::fs::read_to_string(path).expect("the crowd scene");
    let text = text.replace("count: (100, 10, 100)", "count: (40, 10, 50)");
    let scene = tickwork_engine::Scene::parse(&text, "crowd.ron").expect("parses");
    let (allocated, _) = steady_allocations(&mut scene.build().expect("builds").0);
    if allocated != 0 {
        failures.push(format!("20 000 spheres: {allocated} allocations in 32 steps"));
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

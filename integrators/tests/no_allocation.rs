//! Steady-state steps allocate nothing: a counting global allocator
//! (`tests/support/counting_alloc.rs`), counted per thread so that tests
//! running in parallel do not disturb each other.

#[path = "../../tests/support/counting_alloc.rs"]
mod counting;

#[global_allocator]
static GLOBAL: counting::Counting = counting::Counting;

use counting::this_thread as allocations;
use glam::Vec3A;
use tickwork_integrators::{Integrator, METHODS, build};

/// Gravity plus linear drag, the games' workload; optionally declared
/// pointwise, so that explicit methods step it in chunks.
struct GravityAndDrag {
    pointwise: bool,
}

impl tickwork_integrators::System<Vec3A> for GravityAndDrag {
    fn acceleration(&mut self, _t: f32, _x: &[Vec3A], v: &[Vec3A], a: &mut [Vec3A]) {
        for (a, v) in a.iter_mut().zip(v) {
            *a = Vec3A::new(0.0, -9.81, 0.0) - *v * 0.1;
        }
    }
    fn is_pointwise(&self) -> bool {
        self.pointwise
    }
}

#[test]
fn steady_state_steps_allocate_nothing() {
    // The counter sees allocations (so this test can fail).
    let before = allocations();
    let probe = std::hint::black_box(Vec::<u8>::with_capacity(16));
    assert_eq!(allocations() - before, 1);
    drop(probe);
    let dt = 1.0 / 60.0;
    // 256 particles in one piece, 5000 in chunks of 512 and a partial one.
    for (count, pointwise) in [(256, false), (5000, true)] {
        for info in METHODS {
            let mut method: Box<dyn Integrator<Vec3A>> = build(info.name).expect("registered");
            let mut x: Vec<Vec3A> = (0..count).map(|i| Vec3A::new(i as f32, 10.0, 0.0)).collect();
            let mut v = vec![Vec3A::X; count];
            x.reserve(8);
            v.reserve(8);
            let mut system = GravityAndDrag { pointwise };
            let mut n = 0;
            let mut step = |method: &mut Box<dyn Integrator<Vec3A>>, x: &mut Vec<Vec3A>, v: &mut Vec<Vec3A>| {
                method.step(n as f32 * dt, dt, x, v, &mut system).expect("step");
                n += 1;
            };
            // Warm up: buffers sized, histories full.
            for _ in 0..5 {
                step(&mut method, &mut x, &mut v);
            }
            let before = allocations();
            for _ in 0..20 {
                step(&mut method, &mut x, &mut v);
            }
            assert_eq!(allocations() - before, 0, "{} allocated in steady state", info.name);
            // Churn at constant count: a despawn and a spawn restart one particle
            // (an RK4 bootstrap for history methods), still without allocating.
            x.swap_remove(3);
            v.swap_remove(3);
            method.swap_remove(3, x.len() + 1);
            x.push(Vec3A::ZERO);
            v.push(Vec3A::ZERO);
            let before = allocations();
            for _ in 0..5 {
                step(&mut method, &mut x, &mut v);
            }
            assert_eq!(allocations() - before, 0, "{} allocated after churn", info.name);
        }
    }
}

//! Pointwise systems are stepped in cache-sized chunks; the results must be
//! bit-identical to the whole-slice step, including systems that index their
//! own per-particle data through `acceleration_range`.

use glam::Vec3A;
use tickwork_integrators::{Integrator, METHODS, System, build};

/// Gravity, drag and a per-particle charge in a uniform field.
struct Charged {
    charges: Vec<f32>,
    pointwise: bool,
    calls: usize,
}

impl Charged {
    fn force(&self, index: usize, v: Vec3A) -> Vec3A {
        Vec3A::new(0.0, -9.81, 0.0) + Vec3A::new(0.3, 0.0, -0.2) * self.charges[index] - v * 0.05
    }
}

impl System<Vec3A> for Charged {
    fn acceleration(&mut self, _t: f32, _x: &[Vec3A], v: &[Vec3A], out: &mut [Vec3A]) {
        self.calls += 1;
        for (i, (a, v)) in out.iter_mut().zip(v).enumerate() {
            *a = self.force(i, *v);
        }
    }
    fn acceleration_range(&mut self, _t: f32, first: usize, _x: &[Vec3A], v: &[Vec3A], out: &mut [Vec3A]) {
        self.calls += 1;
        for (i, (a, v)) in out.iter_mut().zip(v).enumerate() {
            *a = self.force(first + i, *v);
        }
    }
    fn is_pointwise(&self) -> bool {
        self.pointwise
    }
}

fn run(name: &str, pointwise: bool, n: usize) -> (Vec<Vec3A>, Vec<Vec3A>, usize) {
    let mut method: Box<dyn Integrator<Vec3A>> = build(name).expect("registered");
    let mut system = Charged {
        charges: (0..n).map(|i| (i % 13) as f32 - 6.0).collect(),
        pointwise,
        calls: 0,
    };
    let mut x: Vec<Vec3A> = (0..n).map(|i| Vec3A::new(i as f32 * 0.01, 1.0, 0.0)).collect();
    let mut v: Vec<Vec3A> = (0..n).map(|i| Vec3A::new(0.0, (i % 5) as f32, 1.0)).collect();
    let dt = 1.0 / 60.0;
    for step in 0..30 {
        method
            .step(step as f32 * dt, dt, &mut x, &mut v, &mut system)
            .expect("step");
    }
    (x, v, system.calls)
}

#[test]
fn chunked_steps_are_bit_identical_to_whole_slice_steps() {
    let n = 5000; // nine full chunks and a partial one
    let mut chunked_methods = 0;
    for info in METHODS {
        let (x_whole, v_whole, calls_whole) = run(info.name, false, n);
        let (x_chunked, v_chunked, calls_chunked) = run(info.name, true, n);
        let same = x_whole
            .iter()
            .zip(&x_chunked)
            .chain(v_whole.iter().zip(&v_chunked))
            .all(|(a, b)| a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits));
        assert!(same, "{}: chunked and whole-slice results differ", info.name);
        if calls_chunked > calls_whole {
            chunked_methods += 1;
        }
    }
    // The explicit self-starting methods took the chunked path.
    assert_eq!(chunked_methods, 8);
}

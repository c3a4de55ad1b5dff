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
    // The explicit self-starting methods (see the list below) took the chunked path.
    assert_eq!(chunked_methods, SPLITTING.len());
}

/// The explicit self-starting methods, which keep no per-particle state
/// between steps and so split pointwise, in registry order.
const SPLITTING: [&str; 9] = [
    "explicit_euler",
    "semi_implicit_euler",
    "implicit_drag_euler",
    "predictor_corrector_euler",
    "exponential_euler",
    "midpoint",
    "heun",
    "rk4",
    "forest_ruth",
];

/// Steps the particles as separate sub-slices, each with its own copy of the
/// method, the way the engine spreads chunks over threads.
fn run_split(name: &str, n: usize, pieces: usize) -> (Vec<Vec3A>, Vec<Vec3A>) {
    let prototype: Box<dyn Integrator<Vec3A>> = build(name).expect("registered");
    let mut methods: Vec<Box<dyn Integrator<Vec3A>>> = (0..pieces).map(|_| prototype.clone_boxed()).collect();
    let charges: Vec<f32> = (0..n).map(|i| (i % 13) as f32 - 6.0).collect();
    let mut x: Vec<Vec3A> = (0..n).map(|i| Vec3A::new(i as f32 * 0.01, 1.0, 0.0)).collect();
    let mut v: Vec<Vec3A> = (0..n).map(|i| Vec3A::new(0.0, (i % 5) as f32, 1.0)).collect();
    let dt = 1.0 / 60.0;
    let size = n.div_ceil(pieces);
    for step in 0..30 {
        for (k, ((xs, vs), method)) in x.chunks_mut(size).zip(v.chunks_mut(size)).zip(&mut methods).enumerate() {
            let mut system = Charged {
                charges: charges[k * size..k * size + xs.len()].to_vec(),
                pointwise: true,
                calls: 0,
            };
            method.step(step as f32 * dt, dt, xs, vs, &mut system).expect("step");
        }
    }
    (x, v)
}

#[test]
fn methods_that_split_pointwise_give_identical_results_on_sub_slices() {
    let n = 3001;
    let mut splitting = Vec::new();
    for info in METHODS {
        let method: Box<dyn Integrator<Vec3A>> = build(info.name).expect("registered");
        if !method.splits_pointwise() {
            continue;
        }
        splitting.push(info.name);
        let (x_whole, v_whole, _) = run(info.name, true, n);
        let (x_split, v_split) = run_split(info.name, n, 7);
        assert!(
            x_whole
                .iter()
                .zip(&x_split)
                .chain(v_whole.iter().zip(&v_split))
                .all(|(a, b)| a == b),
            "{}: sub-slice steps differ from the whole-slice step",
            info.name
        );
    }
    assert_eq!(splitting, SPLITTING);
}

#[test]
fn copied_state_continues_bit_identically() {
    // A copy taken mid-run (history, cached accelerations) continues exactly as
    // the original: what world snapshots rely on.
    for info in METHODS {
        let mut a: Box<dyn Integrator<Vec3A>> = build(info.name).expect("registered");
        let mut b: Box<dyn Integrator<Vec3A>> = build(info.name).expect("registered");
        let mut system = Charged {
            charges: vec![1.0, -2.0, 3.0],
            pointwise: false,
            calls: 0,
        };
        let mut x = vec![Vec3A::ZERO, Vec3A::X, Vec3A::Y];
        let mut v = vec![Vec3A::Z, Vec3A::ZERO, Vec3A::X];
        let dt = 0.01;
        for step in 0..5 {
            a.step(step as f32 * dt, dt, &mut x, &mut v, &mut system).expect("step");
        }
        assert!(b.copy_state_from(a.as_ref()), "{}", info.name);
        let (mut x2, mut v2) = (x.clone(), v.clone());
        for step in 5..20 {
            a.step(step as f32 * dt, dt, &mut x, &mut v, &mut system).expect("step");
            b.step(step as f32 * dt, dt, &mut x2, &mut v2, &mut system)
                .expect("step");
        }
        assert_eq!((x, v), (x2, v2), "{}", info.name);
    }
    let mut euler: Box<dyn Integrator<Vec3A>> = build("explicit_euler").expect("registered");
    let rk4: Box<dyn Integrator<Vec3A>> = build("rk4").expect("registered");
    assert!(
        !euler.copy_state_from(rk4.as_ref()),
        "different method types must not copy"
    );
}

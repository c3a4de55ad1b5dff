//! Four particles per value, stored per axis ([`Vec3x4`]): every explicit
//! method steps them, lane for lane, to the bits it gives on `Vec3A`, the
//! groundwork of a per-axis particle layout.

use glam::Vec3A;
use tickwork_integrators::{METHODS, Vec3x4, build};

const G: Vec3A = Vec3A::new(0.3, -9.81, 0.1);
const DRAG: f32 = 0.4;
const STIFFNESS: f32 = 7.0;

fn start(n: usize) -> (Vec<Vec3A>, Vec<Vec3A>) {
    let x = (0..n)
        .map(|i| Vec3A::new(i as f32 * 0.1, 1.0 - (i % 5) as f32 * 0.3, (i % 3) as f32))
        .collect();
    let v = (0..n)
        .map(|i| Vec3A::new((i % 7) as f32 - 3.0, 0.5, -(i as f32) * 0.02))
        .collect();
    (x, v)
}

fn blocks(a: &[Vec3A]) -> Vec<Vec3x4> {
    a.chunks_exact(4)
        .map(|c| Vec3x4::from_lanes([c[0], c[1], c[2], c[3]]))
        .collect()
}

fn bits(a: &[Vec3A]) -> Vec<u32> {
    a.iter().flat_map(|a| a.to_array().map(f32::to_bits)).collect()
}

#[test]
fn explicit_methods_step_four_particles_per_value_to_the_same_bits() {
    // Gravity, drag and a spring to the origin: `a = g - b v - k x`, written
    // with the same operations in the same order for both types.
    let mut lanes = |_t: f32, x: &[Vec3A], v: &[Vec3A], a: &mut [Vec3A]| {
        for ((a, x), v) in a.iter_mut().zip(x).zip(v) {
            *a = G - *v * DRAG - *x * STIFFNESS;
        }
    };
    let mut per_axis = |_t: f32, x: &[Vec3x4], v: &[Vec3x4], a: &mut [Vec3x4]| {
        for ((a, x), v) in a.iter_mut().zip(x).zip(v) {
            *a = Vec3x4::splat(G) - *v * DRAG - *x * STIFFNESS;
        }
    };
    let explicit: Vec<&str> = METHODS
        .iter()
        .filter(|m| !m.implicit && !m.variable_cost)
        .map(|m| m.name)
        .collect();
    assert_eq!(explicit.len(), 16, "{explicit:?}");
    let h = 1.0 / 60.0;
    for name in explicit {
        let (mut x, mut v) = start(64);
        let (mut xb, mut vb) = (blocks(&x), blocks(&v));
        let mut method = build::<Vec3A>(name).expect("registered");
        let mut method_b = build::<Vec3x4>(name).expect("registered");
        for n in 0..200 {
            let t = n as f32 * h;
            method.step(t, h, &mut x, &mut v, &mut lanes).expect("step");
            method_b.step(t, h, &mut xb, &mut vb, &mut per_axis).expect("step");
        }
        let unpack = |b: &[Vec3x4]| b.iter().flat_map(|b| b.lanes()).collect::<Vec<_>>();
        assert_eq!(bits(&x), bits(&unpack(&xb)), "{name}: positions");
        assert_eq!(bits(&v), bits(&unpack(&vb)), "{name}: velocities");
        assert!(
            x.iter().all(|x| x.is_finite() && x.length() < 10.0),
            "{name}: a bounded motion"
        );
    }
}

#[test]
fn a_block_is_its_four_lanes() {
    let lanes = [Vec3A::X, Vec3A::new(1.0, 2.0, 3.0), -Vec3A::Z, Vec3A::splat(0.5)];
    let b = Vec3x4::from_lanes(lanes);
    assert_eq!(b.lanes(), lanes);
    let sum = (b + b * 2.0 - b).lanes();
    assert_eq!(sum, lanes.map(|l| l + l * 2.0 - l));
    // The dot product sums the lanes' dot products.
    use tickwork_integrators::Vector;
    assert_eq!(b.dot(b), lanes.iter().map(|l| l.dot(*l)).sum::<f32>());
    assert!(!Vec3x4::from_lanes([Vec3A::X, Vec3A::X, Vec3A::splat(f32::NAN), Vec3A::X]).is_finite());
}

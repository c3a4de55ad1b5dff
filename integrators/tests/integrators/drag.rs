//! Drag against its closed forms: the split backward Euler of the lecture
//! (`implicit_drag_euler`) and the full backward Euler by Newton-Krylov on
//! stiff drag, down to tiny velocities.

use crate::common;

use common::Oscillator;
use tickwork_integrators::{ImplicitDragEuler, ImplicitEuler, Integrator, SemiImplicitEuler, System, build};

/// Gravity plus linear drag `b`, in 3D: `a = g - b v`.
struct FallWithDrag {
    b: f32,
}

impl System<glam::Vec3A> for FallWithDrag {
    fn acceleration(&mut self, _t: f32, _x: &[glam::Vec3A], v: &[glam::Vec3A], out: &mut [glam::Vec3A]) {
        for (a, v) in out.iter_mut().zip(v) {
            *a = glam::Vec3A::new(0.0, -9.81, 0.0) - *v * self.b;
        }
    }
    fn linear_drag(&self) -> f32 {
        self.b
    }
    fn is_pointwise(&self) -> bool {
        true
    }
}

#[test]
fn implicit_drag_euler_is_semi_implicit_euler_without_drag() {
    // 1 500 particles (three chunks) on an undamped spring, bit for bit.
    let n = 1500;
    let x0: Vec<glam::Vec3A> = (0..n).map(|i| glam::Vec3A::new(i as f32 * 0.01, 1.0, -0.5)).collect();
    let v0: Vec<glam::Vec3A> = (0..n).map(|i| glam::Vec3A::new(0.0, (i % 7) as f32, 1.0)).collect();
    let mut spring = |_t: f32, x: &[glam::Vec3A], _v: &[glam::Vec3A], a: &mut [glam::Vec3A]| {
        for (a, x) in a.iter_mut().zip(x) {
            *a = -*x * 40.0;
        }
    };
    let (mut xa, mut va) = (x0.clone(), v0.clone());
    let (mut xb, mut vb) = (x0, v0);
    let mut split = ImplicitDragEuler::new();
    let mut plain = SemiImplicitEuler::new();
    for n in 0..500 {
        let t = n as f32 / 60.0;
        split.step(t, 1.0 / 60.0, &mut xa, &mut va, &mut spring).expect("step");
        plain.step(t, 1.0 / 60.0, &mut xb, &mut vb, &mut spring).expect("step");
    }
    assert_eq!(xa, xb);
    assert_eq!(va, vb);
}

#[test]
fn implicit_drag_euler_is_the_lectures_closed_form_on_pure_drag() {
    // v(t + dt) = v(t) / (1 + dt b), exactly to rounding, also at h b = 50.
    for (b, h) in [(0.5, 0.1), (1000.0, 0.05)] {
        let mut method = ImplicitDragEuler::<f64>::new();
        let mut drag = Oscillator { k: 0.0, b };
        let (mut x, mut v) = (vec![0.0], vec![2.0]);
        let (mut x_exact, mut v_exact) = (0.0f64, 2.0f64);
        for n in 0..40 {
            method.step(n as f64 * h, h, &mut x, &mut v, &mut drag).expect("step");
            v_exact /= 1.0 + h * b;
            x_exact += h * v_exact;
            assert!(
                (v[0] - v_exact).abs() <= 1e-14 * v_exact.abs(),
                "b {b}, step {n}: v {} vs {v_exact}",
                v[0]
            );
            assert!((x[0] - x_exact).abs() <= 1e-14 * x_exact.abs(), "b {b}, step {n}: x");
        }
    }
}

#[test]
fn implicit_drag_euler_stays_bounded_on_stiff_drag_where_explicit_methods_explode() {
    // h b = 30: explicit Euler's factor 1 - h b = -29 explodes; the split
    // backward Euler settles at the terminal velocity g / b.
    let b = 1800.0;
    let mut system = FallWithDrag { b };
    let terminal = -9.81 / b;
    let run = |name: &str, system: &mut FallWithDrag| {
        let mut method = build::<glam::Vec3A>(name).expect("registered");
        let (mut x, mut v) = (vec![glam::Vec3A::ZERO; 4], vec![glam::Vec3A::new(5.0, 20.0, -3.0); 4]);
        for n in 0..600 {
            if method
                .step(n as f32 / 60.0, 1.0 / 60.0, &mut x, &mut v, system)
                .is_err()
            {
                return f32::INFINITY;
            }
        }
        // The largest distance, NaN (a blow-up) winning over every number.
        v.iter()
            .map(|v| (*v - glam::Vec3A::new(0.0, terminal, 0.0)).length())
            .fold(0.0, |worst: f32, d| if d.is_nan() || d > worst { d } else { worst })
    };
    let split = run("implicit_drag_euler", &mut system);
    assert!(
        split < 1e-6,
        "implicit_drag_euler: {split:e} from the terminal velocity"
    );
    let explicit = run("explicit_euler", &mut system);
    assert!(
        explicit.is_nan() || explicit >= 1.0,
        "explicit Euler should have exploded: {explicit:e}"
    );
    // Every intermediate step is bounded by the start speed too (no overshoot).
    let mut method = ImplicitDragEuler::new();
    let (mut x, mut v) = (vec![glam::Vec3A::ZERO], vec![glam::Vec3A::new(5.0, 20.0, -3.0)]);
    let start = v[0].length();
    for n in 0..60 {
        method
            .step(n as f32 / 60.0, 1.0 / 60.0, &mut x, &mut v, &mut system)
            .expect("step");
        assert!(
            v[0].length() <= start,
            "step {n}: |v| {} grew past {start}",
            v[0].length()
        );
        assert!(
            v[0].y <= 20.0 && v[0].x >= 0.0,
            "step {n}: the velocity reversed: {}",
            v[0]
        );
    }
}

#[test]
fn backward_euler_follows_stiff_drag_down_to_tiny_velocities() {
    // b = 1000, h = 0.1: the closed form v0 / (1 + h b)^N falls by 101 per
    // step. A stopping rule with an absolute part (1e-10 (1 + |u|)) accepted
    // the first guess once |h b v| < 1e-10, freezing v near 1e-12.
    let (b, h) = (1000.0, 0.1);
    let mut method = ImplicitEuler::<f64>::new();
    let mut drag = Oscillator { k: 0.0, b };
    let (mut x, mut v) = (vec![0.0], vec![1.0]);
    let mut exact = 1.0f64;
    for n in 0..11 {
        method.step(n as f64 * h, h, &mut x, &mut v, &mut drag).expect("step");
        exact /= 1.0 + h * b;
        assert!(
            (v[0] - exact).abs() <= 1e-9 * exact,
            "step {}: v {:e} vs the closed form {exact:e}",
            n + 1,
            v[0]
        );
    }
    assert!(v[0] < 1e-21, "v {:e}", v[0]);
}

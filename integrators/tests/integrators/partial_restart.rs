//! History methods restart only the particles that lost their history (a
//! bounce, a teleport): on a pointwise system the RK4 start runs on those
//! particles alone, so a floor full of resting particles, a few of which
//! bounce each step, costs the method's own price, not RK4's. The restarted
//! particles must come out bit-identical to the all-particle restart.

use glam::Vec3A;
use tickwork_integrators::{METHODS, System, build};

/// Gravity, linear drag and a stiff radial pull: pointwise, with a
/// velocity-dependent part, so every RK4 stage matters. Counts the particles
/// it evaluates; `pointwise: false` makes the methods take the everyone path.
struct Pull {
    pointwise: bool,
    evaluated: usize,
}

impl Pull {
    fn at(x: Vec3A, v: Vec3A) -> Vec3A {
        Vec3A::new(0.0, -9.81, 0.0) - v * 0.3 - x * 4.0
    }
}

impl System<Vec3A> for Pull {
    fn acceleration(&mut self, _t: f32, x: &[Vec3A], v: &[Vec3A], out: &mut [Vec3A]) {
        self.evaluated += x.len();
        for ((out, x), v) in out.iter_mut().zip(x).zip(v) {
            *out = Self::at(*x, *v);
        }
    }

    fn is_pointwise(&self) -> bool {
        self.pointwise
    }

    fn acceleration_range(&mut self, t: f32, _first: usize, x: &[Vec3A], v: &[Vec3A], out: &mut [Vec3A]) {
        self.acceleration(t, x, v, out);
    }
}

fn start(n: usize) -> (Vec<Vec3A>, Vec<Vec3A>) {
    let x = (0..n)
        .map(|i| Vec3A::new(i as f32 * 0.01, 1.0 + (i % 7) as f32 * 0.1, -0.5))
        .collect();
    let v = (0..n).map(|i| Vec3A::new(0.2, (i % 5) as f32 * -0.3, 0.1)).collect();
    (x, v)
}

/// The particles a "collider" edits after step `step`: runs at both ends,
/// a run in the middle and a lone particle, different on every step.
fn edited(step: usize, n: usize) -> Vec<usize> {
    let s = step % 5;
    let mut rows = vec![0, 1, n - 1, n / 2 + s, n / 2 + s + 1, n / 2 + s + 2, 17 + 3 * s];
    rows.dedup();
    rows
}

#[test]
fn only_the_particles_that_lost_their_history_are_restarted_and_they_match_the_full_restart() {
    let history_methods: Vec<&str> = METHODS.iter().filter(|m| !m.self_starting).map(|m| m.name).collect();
    assert_eq!(history_methods.len(), 5, "{history_methods:?}");
    let n = 1000;
    let h = 1.0 / 60.0;
    for name in history_methods {
        let mut partial = build::<Vec3A>(name).expect("registered");
        let mut full = build::<Vec3A>(name).expect("registered");
        let (mut xp, mut vp) = start(n);
        let (mut xf, mut vf) = start(n);
        let mut pointwise = Pull {
            pointwise: true,
            evaluated: 0,
        };
        let mut coupled = Pull {
            pointwise: false,
            evaluated: 0,
        };
        // Long enough for every method's history to fill (AB4 needs 3 steps).
        for _ in 0..6 {
            partial.step(0.0, h, &mut xp, &mut vp, &mut pointwise).expect("step");
            full.step(0.0, h, &mut xf, &mut vf, &mut coupled).expect("step");
        }
        for step in 0..40 {
            let rows = edited(step, n);
            for &row in &rows {
                // A bounce: the velocity flips.
                vp[row].y = -vp[row].y;
                vf[row].y = -vf[row].y;
            }
            pointwise.evaluated = 0;
            let stats = partial.step(0.0, h, &mut xp, &mut vp, &mut pointwise).expect("step");
            full.step(0.0, h, &mut xf, &mut vf, &mut coupled).expect("step");
            // Restarted: the edited rows, and (AB3, AB4) those still
            // rebuilding their history from an edit one or two steps ago.
            let restarted = stats.bootstrapped as usize;
            assert!(
                restarted >= rows.len() && restarted <= 3 * rows.len(),
                "{name}: {restarted} restarted"
            );
            // One evaluation of everyone, plus three (Beeman, which reuses
            // the last step's acceleration: four) of each restarted
            // particle, where the full restart evaluates everyone 4 times.
            let per_start = if name == "beeman" { 4 } else { 3 };
            assert_eq!(
                pointwise.evaluated,
                n + per_start * restarted,
                "{name}, step {step}: evaluations"
            );
            assert!(pointwise.evaluated < 2 * n, "{name}: {}", pointwise.evaluated);
            // Bit for bit what the all-particle restart gives.
            let bits = |x: &[Vec3A]| {
                x.iter()
                    .flat_map(|x| x.to_array().map(f32::to_bits))
                    .collect::<Vec<_>>()
            };
            assert_eq!(bits(&xp), bits(&xf), "{name}, step {step}: positions");
            assert_eq!(bits(&vp), bits(&vf), "{name}, step {step}: velocities");
        }
    }
}

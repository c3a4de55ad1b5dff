//! History methods key their history on the sequence of steps and `h`, never
//! on the time passed in: a caller that passes `t = 0` on every step (natural
//! for time-independent forces) keeps the method it asked for.

use tickwork_integrators::{METHODS, build};

#[test]
fn history_methods_keep_their_method_when_the_time_passed_in_does_not_advance() {
    let history_methods: Vec<&str> = METHODS.iter().filter(|m| !m.self_starting).map(|m| m.name).collect();
    assert_eq!(
        history_methods,
        [
            "position_verlet",
            "beeman",
            "adams_bashforth2",
            "adams_bashforth3",
            "adams_bashforth4"
        ]
    );
    let mut spring = |_t: f64, x: &[f64], _v: &[f64], a: &mut [f64]| {
        for (a, x) in a.iter_mut().zip(x) {
            *a = -4.0 * *x;
        }
    };
    let h = 0.01;
    for name in history_methods {
        let mut frozen_time = build::<f64>(name).expect("registered");
        let mut advancing = build::<f64>(name).expect("registered");
        let (mut x0, mut v0) = (vec![1.0, -0.5], vec![0.0, 2.0]);
        let (mut x1, mut v1) = (x0.clone(), v0.clone());
        for n in 0..200 {
            let stats = frozen_time.step(0.0, h, &mut x0, &mut v0, &mut spring).expect("step");
            advancing
                .step(n as f64 * h, h, &mut x1, &mut v1, &mut spring)
                .expect("step");
            if n >= 3 {
                assert_eq!(stats.bootstrapped, 0, "{name}, step {n}: restarted with RK4");
                assert_eq!(stats.evaluations, 1, "{name}, step {n}: evaluations");
            }
        }
        // Time-independent forces: the same trajectory, bit for bit.
        assert_eq!((&x0, &v0), (&x1, &v1), "{name}");
        // A change of h still restarts every particle.
        let stats = frozen_time
            .step(0.0, h / 2.0, &mut x0, &mut v0, &mut spring)
            .expect("step");
        assert_eq!(stats.bootstrapped, 2, "{name}: a new h must restart the history");
    }
}

//! The clock is pure: every behaviour is tested here without a world or a window.

use proptest::prelude::*;

use super::*;

fn clock(config: ClockConfig) -> FixedClock {
    FixedClock::new(config).expect("valid config")
}

#[test]
fn sixty_hz_display_runs_one_step_per_frame_and_time_is_exact() {
    let mut c = FixedClock::default();
    let mut total = 0;
    for _ in 0..3600 {
        total += c.advance(1.0 / 60.0).expect("frame").steps;
    }
    // Rounding 1/60 s to nanoseconds loses a third of a ns per frame, so the
    // last frame may still be pending; never more than one.
    assert!((3599..=3600).contains(&total), "{total}");
    let (n, d) = c.exact_time();
    assert_eq!(n * 60, d * u128::from(total));
    let mut c = FixedClock::default();
    c.step(3600);
    assert_eq!(c.exact_time(), (60, 1));
    assert_eq!(c.time(), 60.0);
}

#[test]
fn simulated_time_is_n_steps_exactly_for_awkward_rates() {
    let mut c = clock(ClockConfig {
        rate: Rate::hz_f64(59.94).expect("rate"),
        ..ClockConfig::default()
    });
    c.step(1_000_003);
    // 1_000_003 * 50 / 2997 seconds, in lowest terms.
    let (n, d) = c.exact_time();
    assert_eq!(n * 2997, d * 1_000_003 * 50);
}

#[test]
fn frames_shorter_than_a_step_accumulate_and_alpha_tracks_the_remainder() {
    let mut c = clock(ClockConfig {
        rate: Rate::hz(10).expect("rate"),
        ..ClockConfig::default()
    });
    let f = c.advance(0.025).expect("frame");
    assert_eq!((f.steps, f.alpha), (0, 0.25));
    let f = c.advance(0.05).expect("frame");
    assert_eq!((f.steps, f.alpha), (0, 0.75));
    let f = c.advance(0.05).expect("frame");
    assert_eq!(f.steps, 1);
    assert!((f.alpha - 0.25).abs() < 1e-12);
}

#[test]
fn fixed_steps_report_ticks_and_times() {
    let mut c = clock(ClockConfig {
        rate: Rate::hz(4).expect("rate"),
        max_frame_time: 1.0,
        ..ClockConfig::default()
    });
    let f = c.advance(0.5).expect("frame");
    let steps: Vec<FixedStep> = f.fixed_steps().collect();
    assert_eq!(
        steps,
        vec![
            FixedStep {
                tick: 0,
                time: 0.0,
                dt: 0.25
            },
            FixedStep {
                tick: 1,
                time: 0.25,
                dt: 0.25
            }
        ]
    );
}

#[test]
fn bad_frame_durations_are_errors_and_change_nothing() {
    let mut c = FixedClock::default();
    c.advance(0.01).expect("frame");
    let before = c.backlog();
    for bad in [-0.001, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let err = c.advance(bad).expect_err("rejected");
        assert!(matches!(err, ClockError::InvalidFrameTime { value } if value.to_bits() == bad.to_bits()));
        assert!(err.to_string().starts_with("invalid frame duration: "), "{err}");
    }
    assert_eq!(c.backlog(), before);
    assert_eq!(
        c.advance(-1.5).map(|_| ()).unwrap_err().to_string(),
        "invalid frame duration: -1.5 s (must be finite and not negative)"
    );
}

#[test]
fn bad_settings_are_errors() {
    for (config, field) in [
        (
            ClockConfig {
                max_frame_time: 0.0,
                ..ClockConfig::default()
            },
            "max_frame_time",
        ),
        (
            ClockConfig {
                time_scale: f64::NAN,
                ..ClockConfig::default()
            },
            "time_scale",
        ),
        (
            ClockConfig {
                max_steps_per_frame: 0,
                ..ClockConfig::default()
            },
            "max_steps_per_frame",
        ),
    ] {
        let err = FixedClock::new(config).expect_err("rejected");
        assert!(err.to_string().contains(field), "{err}");
    }
    let mut c = FixedClock::default();
    assert_eq!(
        c.set_time_scale(-2.0).unwrap_err().to_string(),
        "invalid clock setting time_scale: -2 (expected from 1e-6 to 1e6 game seconds per real second)"
    );
}

#[test]
fn drop_policy_cuts_a_long_stall_and_reports_it() {
    let mut c = FixedClock::default(); // 60 Hz, 0.25 s max frame, 8 steps cap
    let f = c.advance(10.0).expect("frame");
    assert_eq!(f.steps, 8);
    // 10 s real: 9.75 s cut by max_frame_time, then 0.25 s = 15 steps of which 7 dropped.
    assert!((f.dropped - (9.75 + 7.0 / 60.0)).abs() < 1e-9, "{}", f.dropped);
    assert!((f.effective_speed - 8.0 / 60.0 / 10.0).abs() < 1e-12);
    // Next frames are normal again: no burst.
    let f = c.advance(1.0 / 60.0).expect("frame");
    assert_eq!(f.steps, 1);
    assert_eq!(f.dropped, 0.0);
}

#[test]
fn catch_up_policy_pays_the_debt_over_following_frames_within_the_cap() {
    let mut c = clock(ClockConfig {
        hitch_policy: HitchPolicy::CatchUp,
        ..ClockConfig::default()
    });
    let f = c.advance(10.0).expect("frame");
    assert_eq!(f.steps, 8);
    assert!((f.dropped - 9.75).abs() < 1e-9, "only the max-frame cut is dropped");
    // 15 steps were owed; 7 remain and run next frame with this frame's own step.
    let f = c.advance(1.0 / 60.0).expect("frame");
    assert_eq!(f.steps, 8);
    let f = c.advance(1.0 / 60.0).expect("frame");
    assert_eq!(f.steps, 1);
    assert!(c.tick() == 17 || c.tick() == 16, "{}", c.tick());
}

#[test]
fn slow_down_policy_slows_following_frames_and_recovers() {
    let mut c = clock(ClockConfig {
        hitch_policy: HitchPolicy::SlowDown,
        ..ClockConfig::default()
    });
    // A machine that can only show 4 frames per second: each frame needs 15 steps.
    let f = c.advance(0.25).expect("frame");
    assert_eq!(f.steps, 8);
    // The next slow frame is dilated to what the cap simulates: no time dropped.
    let f = c.advance(0.25).expect("frame");
    // 8 steps' worth of time (7 when the dilated time rounds just below).
    assert!((7..=8).contains(&f.steps), "{}", f.steps);
    assert!(f.dropped < 1e-9, "{}", f.dropped);
    assert!((f.effective_speed - 8.0 / 15.0).abs() < 0.07, "{}", f.effective_speed);
    // Back to 60 fps: speed recovers to 1 within a few dozen frames.
    for _ in 0..40 {
        c.advance(1.0 / 60.0).expect("frame");
    }
    let ticks = c.tick();
    let mut steps = 0;
    for _ in 0..60 {
        steps += c.advance(1.0 / 60.0).expect("frame").steps;
    }
    assert!((59..=60).contains(&steps), "{steps} after {ticks}");
}

#[test]
fn time_scale_changes_the_number_of_steps_not_their_size() {
    let mut c = clock(ClockConfig {
        time_scale: 0.25,
        ..ClockConfig::default()
    });
    let mut steps = 0;
    for _ in 0..240 {
        let f = c.advance(1.0 / 60.0).expect("frame");
        steps += f.steps;
        assert!(f.fixed_steps().all(|s| s.dt == 1.0 / 60.0));
    }
    assert!((59..=60).contains(&steps), "{steps}");
    c.set_time_scale(2.0).expect("scale");
    let f = c.advance(1.0 / 60.0).expect("frame");
    assert!((2..=3).contains(&f.steps));
    assert!((f.effective_speed - 2.0).abs() < 0.6);
}

#[test]
fn pause_stops_time_single_step_runs_exactly_one() {
    let mut c = FixedClock::default();
    c.advance(0.02).expect("frame");
    let alpha = c.alpha();
    c.pause();
    assert!(c.is_paused());
    assert_eq!(c.advance(1.0).expect("frame").steps, 0);
    assert_eq!(c.alpha(), alpha);
    assert!(c.single_step());
    let f = c.advance(0.001).expect("frame");
    assert_eq!((f.steps, f.alpha), (1, alpha));
    assert_eq!(c.advance(0.5).expect("frame").steps, 0);
    c.resume();
    assert!(!c.single_step(), "ignored while running");
    assert_eq!(c.advance(1.0 / 60.0).expect("frame").steps, 1);
}

#[test]
fn step_n_runs_steps_outside_real_time() {
    let mut c = FixedClock::default();
    let f = c.step(5);
    assert_eq!((f.steps, f.first_tick, c.tick()), (5, 0, 5));
    assert_eq!(c.backlog(), 0.0);
}

#[test]
fn changing_the_rate_keeps_time_continuous() {
    let mut c = FixedClock::default();
    c.step(30); // 0.5 s at 60 Hz
    c.set_rate(Rate::hz(100).expect("rate"));
    c.step(25); // + 0.25 s at 100 Hz
    assert_eq!(c.exact_time(), (3, 4));
    assert_eq!(c.dt(), 0.01);
    c.set_rate(Rate::seconds(1.0 / 3.0).expect("rate"));
    c.step(3);
    assert_eq!(c.exact_time(), (7, 4));
    // Accumulated time carries over the change.
    let mut c = clock(ClockConfig {
        rate: Rate::hz(10).expect("rate"),
        ..ClockConfig::default()
    });
    c.advance(0.05).expect("frame");
    c.set_rate(Rate::hz(20).expect("rate"));
    assert_eq!(c.advance(0.0).expect("frame").steps, 1);
}

proptest! {
    /// For any sequence of frames that never hitch, simulated time never runs
    /// ahead of the time fed in and never lags it by a step or more; alpha is
    /// the remainder as a fraction of a step.
    #[test]
    fn simulated_time_follows_accepted_time(frames in prop::collection::vec(0.0f64..0.05, 1..400), hz in 1u32..480) {
        let mut c = clock(ClockConfig {
            rate: Rate::hz(hz).expect("rate"),
            max_steps_per_frame: u32::MAX,
            ..ClockConfig::default()
        });
        let dt = 1.0 / f64::from(hz);
        let mut fed = 0.0;
        for d in frames {
            let f = c.advance(d).expect("frame");
            fed += d;
            prop_assert!((0.0..1.0).contains(&f.alpha));
            prop_assert_eq!(f.dropped, 0.0);
            let simulated = c.time();
            // Nanosecond rounding of each frame: allow 1 ns per frame.
            prop_assert!(simulated <= fed + 1e-9 * 400.0, "ahead: {} > {}", simulated, fed);
            prop_assert!(fed - simulated < dt + 1e-9 * 400.0, "lags: {} vs {}", simulated, fed);
            prop_assert!((fed - simulated - f.alpha * dt).abs() < 1e-6);
        }
    }

    /// With hitches and any policy, alpha stays in range, the step cap holds,
    /// and simulated time never runs ahead of accepted time.
    #[test]
    fn hitch_guard_holds_for_any_frames(
        frames in prop::collection::vec(prop_oneof![0.0f64..0.05, 0.0f64..20.0], 1..200),
        policy in prop_oneof![Just(HitchPolicy::Drop), Just(HitchPolicy::SlowDown), Just(HitchPolicy::CatchUp)],
        cap in 1u32..20,
    ) {
        let mut c = clock(ClockConfig { hitch_policy: policy, max_steps_per_frame: cap, ..ClockConfig::default() });
        for d in frames {
            let f = c.advance(d).expect("frame");
            prop_assert!(f.steps <= cap);
            prop_assert!((0.0..1.0).contains(&f.alpha));
            prop_assert!(f.dropped >= 0.0 && f.dropped <= d + 1e-9);
            prop_assert!(c.time() <= c.accepted_time() + 1e-9);
            if policy != HitchPolicy::CatchUp {
                prop_assert!(c.backlog() < c.dt());
            }
        }
    }
}

/// One operation on a clock, as a game, the control panel or a hostile user
/// makes them.
#[derive(Clone, Debug)]
enum Operation {
    Frame(f64),
    Rate(u32),
    PrimeRate(usize),
    Scale(f64),
    Pause,
    Resume,
    SingleSteps(u32),
    Policy(HitchPolicy),
}

const PRIMES: [u32; 16] = [2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53];

fn operation() -> impl Strategy<Value = Operation> {
    prop_oneof![
        6 => prop_oneof![0.0f64..0.05, 0.0f64..2.0, Just(1e9), Just(f64::MAX)].prop_map(Operation::Frame),
        2 => (1u32..2000).prop_map(Operation::Rate),
        2 => (0usize..PRIMES.len()).prop_map(Operation::PrimeRate),
        1 => prop_oneof![1e-6f64..1e6, Just(1e6), Just(1e-6)].prop_map(Operation::Scale),
        1 => Just(Operation::Pause),
        1 => Just(Operation::Resume),
        1 => prop_oneof![0u32..3, Just(1_000_000)].prop_map(Operation::SingleSteps),
        1 => prop_oneof![Just(HitchPolicy::Drop), Just(HitchPolicy::SlowDown), Just(HitchPolicy::CatchUp)]
            .prop_map(Operation::Policy),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Long random sequences of rate, scale, pause, single-step, policy and
    /// frame-time changes, with overflow checks on (this crate's tests build
    /// in the dev profile): nothing panics, the step cap holds on every
    /// frame (single steps included), time never goes back and stays
    /// continuous across rate changes (within the re-basing's nanosecond),
    /// and alpha stays in range. Before, a dozen prime-rate changes
    /// overflowed the exact time and a time scale of 1e30 the accumulator.
    #[test]
    fn exact_time_survives_any_sequence_of_operations(
        operations in prop::collection::vec(operation(), 1..600),
        cap in 1u32..16,
    ) {
        let mut c = clock(ClockConfig { max_steps_per_frame: cap, ..ClockConfig::default() });
        let mut last_time = 0.0f64;
        for op in operations {
            match op {
                Operation::Frame(d) => {
                    let f = c.advance(d).expect("a finite frame");
                    prop_assert!(f.steps <= cap, "{} steps, cap {}", f.steps, cap);
                    prop_assert!((0.0..1.0).contains(&f.alpha));
                    prop_assert!(f.dropped.is_finite() && f.dropped >= 0.0, "dropped {}", f.dropped);
                    let times: Vec<f64> = f.fixed_steps().map(|s| s.time).collect();
                    prop_assert!(times.windows(2).all(|w| w[0] < w[1]));
                }
                Operation::Rate(hz) => {
                    let before = c.time();
                    c.set_rate(Rate::hz(hz).expect("in range"));
                    prop_assert!((c.time() - before).abs() <= 1e-9 * before.max(1.0), "{} -> {}", before, c.time());
                }
                Operation::PrimeRate(k) => c.set_rate(Rate::hz(PRIMES[k]).expect("in range")),
                Operation::Scale(s) => c.set_time_scale(s).expect("in range"),
                Operation::Pause => c.pause(),
                Operation::Resume => c.resume(),
                Operation::SingleSteps(n) => {
                    for _ in 0..n.min(1_000) {
                        c.single_step();
                    }
                }
                Operation::Policy(p) => c.set_hitch_policy(p),
            }
            let time = c.time();
            prop_assert!(time.is_finite() && time >= last_time - 1e-9 * last_time.max(1.0), "{} after {}", time, last_time);
            last_time = time;
        }
    }
}

#[test]
fn sixty_prime_rate_changes_keep_exact_time_continuous() {
    // The least common multiple of these denominators is far past u128.
    let mut c = FixedClock::default();
    let mut expected = 0.0f64;
    for (k, hz) in PRIMES.iter().cycle().take(60).enumerate() {
        c.set_rate(Rate::hz(*hz * 37 + k as u32).expect("in range"));
        c.step(7);
        expected += 7.0 * c.dt();
        assert!(
            (c.time() - expected).abs() < 1e-9,
            "change {k}: {} vs {expected}",
            c.time()
        );
    }
}

#[test]
fn a_huge_time_scale_is_an_error_naming_the_limit() {
    let mut c = FixedClock::default();
    let error = c.set_time_scale(1e30).unwrap_err().to_string();
    assert_eq!(
        error,
        "invalid clock setting time_scale: 1e30 (expected from 1e-6 to 1e6 game seconds per real second)"
    );
    let error = FixedClock::new(ClockConfig {
        max_frame_time: 1e300,
        ..ClockConfig::default()
    })
    .unwrap_err()
    .to_string();
    assert!(
        error.contains("max_frame_time: 1e300 (expected from 1e-9 (a nanosecond) to 3600 seconds)"),
        "{error}"
    );
}

#[test]
fn a_million_queued_single_steps_run_at_most_the_cap_per_frame() {
    let mut c = FixedClock::default();
    c.pause();
    for _ in 0..1_000_000 {
        c.single_step();
    }
    let mut total = 0u64;
    for _ in 0..10 {
        let f = c.advance(1.0 / 60.0).expect("frame");
        assert!(f.steps <= 8, "{} steps in one frame", f.steps);
        total += u64::from(f.steps);
    }
    assert_eq!(total, 80);
    c.resume();
    assert_eq!(c.advance(0.0).expect("frame").steps, 0, "resume drops the queue");
}

#[test]
fn slow_down_recovers_after_an_extreme_time_scale() {
    let mut c = clock(ClockConfig {
        hitch_policy: HitchPolicy::SlowDown,
        ..ClockConfig::default()
    });
    c.set_time_scale(FixedClock::MAX_TIME_SCALE).expect("in range");
    for _ in 0..1_000 {
        let f = c.advance(0.25).expect("frame");
        assert!(f.dropped.is_finite());
        assert_eq!(f.steps, 8, "the clock never freezes");
    }
    c.set_time_scale(1.0).expect("in range");
    // 5% a frame from the floor of 1e-3: about 140 frames to full speed.
    let mut steps = 0;
    for _ in 0..400 {
        steps = c.advance(1.0 / 60.0).expect("frame").steps;
    }
    assert_eq!(steps, 1, "back to one step per 60 Hz frame");
}

#[test]
fn catch_up_debt_is_bounded() {
    let mut c = clock(ClockConfig {
        hitch_policy: HitchPolicy::CatchUp,
        max_frame_time: 3600.0,
        ..ClockConfig::default()
    });
    // An hour-long frame owes 216 000 steps; the debt keeps 60 frames' worth.
    let f = c.advance(3600.0).expect("frame");
    assert_eq!(f.steps, 8);
    assert!(f.dropped > 3590.0, "dropped {}", f.dropped);
    assert!(c.backlog() <= 61.0 * 8.0 / 60.0, "backlog {}", c.backlog());
}

#[test]
fn deferred_steps_are_due_again_next_frame_and_only_a_frames_cap_of_them_is_kept() {
    let mut clock = FixedClock::new(ClockConfig {
        rate: Rate::hz(60).expect("a rate"),
        max_steps_per_frame: 4,
        ..ClockConfig::default()
    })
    .expect("a clock");
    // Three steps due, one run, two given back: due again with no new time,
    // at the same ticks, and no time is counted as dropped.
    let frame = clock.advance(3.0 / 60.0).expect("advances");
    assert_eq!((frame.first_tick, frame.steps), (0, 3));
    assert_eq!(clock.defer(2), 0.0);
    assert_eq!(clock.tick(), 1);
    let frame = clock.advance(0.0).expect("advances");
    assert_eq!((frame.first_tick, frame.steps), (1, 2));
    // Only the last frame's steps can be given back.
    clock.defer(10);
    assert_eq!(clock.tick(), 1);
    // Four steps run and given back frame after frame pile up to one
    // frame's cap (4 steps); past it the time is dropped, as a hitch is.
    let _ = clock.advance(0.0).expect("advances");
    for _ in 0..3 {
        let frame = clock.advance(4.0 / 60.0).expect("advances");
        clock.defer(frame.steps);
    }
    // Counted in whole nanoseconds.
    assert!(
        (clock.dropped_total() - 8.0 / 60.0).abs() < 1e-8,
        "{}",
        clock.dropped_total()
    );
    assert_eq!(clock.advance(0.0).expect("advances").steps, 4);
}

/// The exact time `steps` steps of `rate` add, in seconds (as f64 of an
/// exact fraction).
fn segment_seconds(rate: Rate, steps: u64) -> f64 {
    let (numer, denom) = rate.fraction();
    let total = u128::from(numer) * u128::from(steps);
    let denom = u128::from(denom);
    (total / denom) as f64 + (total % denom) as f64 / denom as f64
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Rates from `hz_f64` have step denominators up to about 1e12, so the
    /// time line's units (1e9 of them a second) pass 2^64: for any sequence
    /// of such rates, the time still equals the sum of the steps taken,
    /// within the documented rounding of half a nanosecond per change.
    /// (Run in the test profile, with overflow checks on: a product that
    /// overflows panics here.)
    #[test]
    fn time_is_the_sum_of_its_steps_across_rates_with_large_denominators(
        segments in proptest::collection::vec((1.0f64..1.0e6, 0u64..5_000), 1..40),
    ) {
        let mut c = FixedClock::default();
        let mut expected = 0.0f64;
        for (k, &(hz, steps)) in segments.iter().enumerate() {
            let rate = Rate::hz_f64(hz).expect("in range");
            c.set_rate(rate);
            c.step(u32::try_from(steps).expect("below 5000"));
            expected += segment_seconds(rate, steps);
            let bound = 0.5e-9 * (k + 1) as f64 + 1e-15 * expected;
            prop_assert!(
                (c.time() - expected).abs() <= bound,
                "after change {k} to {hz} Hz ({:?}): time {} vs the sum of the steps {expected}",
                rate.fraction(),
                c.time()
            );
        }
    }
}

#[test]
fn the_reported_rate_change_keeps_time_the_sum_of_its_steps() {
    // From the hardening issue: after this rate the time was 0.16 s short.
    let mut c = FixedClock::default();
    let mut expected = 0.0;
    for (hz, steps) in [
        (59.94, 1_000_000),
        (167_545.335_9, 3_000_000),
        (997.3, 10),
        (12_345.678_9, 7),
    ] {
        let rate = Rate::hz_f64(hz).expect("in range");
        c.set_rate(rate);
        c.step(steps);
        expected += segment_seconds(rate, u64::from(steps));
        assert!(
            (c.time() - expected).abs() < 2e-9 + 1e-15 * expected,
            "at {hz} Hz: {} vs {expected}",
            c.time()
        );
    }
}

#[test]
fn max_frame_time_states_its_real_bounds_and_can_change_at_run_time() {
    // 5e-324 is above zero: the message gives the bound it is below.
    let error = FixedClock::new(ClockConfig {
        max_frame_time: 5e-324,
        ..ClockConfig::default()
    })
    .expect_err("below a nanosecond");
    assert_eq!(
        error.to_string(),
        "invalid clock setting max_frame_time: 5e-324 (expected from 1e-9 (a nanosecond) to 3600 seconds)"
    );
    let mut c = FixedClock::default();
    c.set_max_frame_time(0.05).expect("in range");
    assert_eq!(c.config().max_frame_time, 0.05);
    // A 1 s stall now counts as 50 ms: 3 steps at 60 Hz.
    assert_eq!(c.advance(1.0).expect("frame").steps, 3);
    let error = c.set_max_frame_time(f64::NAN).expect_err("not a number");
    assert!(error.to_string().contains("max_frame_time: NaN"), "{error}");
    assert_eq!(c.config().max_frame_time, 0.05, "unchanged by the refused value");
}

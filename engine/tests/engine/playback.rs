//! Playback: the clock, controls and HUD shared by the window and the
//! off-screen runner. Pure: no GPU, no window.
#![cfg(feature = "render")]

use std::path::PathBuf;

use tickwork_engine::Scene;
use tickwork_engine::app::{Control, Playback};
use tickwork_engine::integrators::METHODS;

fn projectile() -> Playback {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../assets/scenes/projectile.ron");
    let scene = Scene::load(&path).expect("scene");
    Playback::from_scene(&scene, None).expect("playback")
}

#[test]
fn frames_run_the_steps_their_durations_are_due() {
    let mut playback = projectile(); // 60 Hz
    let frame = playback.advance(1.0 / 30.0).expect("frame");
    assert_eq!(frame.steps, 2);
    let frame = playback.advance(1.0 / 120.0).expect("frame");
    assert_eq!(frame.steps, 0);
    assert!((frame.alpha - 0.5).abs() < 1e-6, "half a step past: {}", frame.alpha);
    assert_eq!(playback.world().tick(), 2);
    let error = playback.advance(f64::NAN).expect_err("NaN frame");
    assert_eq!(
        error.to_string(),
        "invalid frame duration: NaN s (must be finite and not negative)"
    );
    let error = playback.advance(-0.01).expect_err("negative frame");
    assert!(
        error.to_string().starts_with("invalid frame duration: -0.01 s"),
        "{error}"
    );
}

#[test]
fn pause_single_step_and_time_scale() {
    let mut playback = projectile();
    playback.control(Control::TogglePause).expect("pause");
    assert_eq!(playback.advance(0.1).expect("frame").steps, 0);
    playback.control(Control::SingleStep).expect("step");
    assert_eq!(playback.advance(0.1).expect("frame").steps, 1);
    assert_eq!(playback.advance(0.1).expect("frame").steps, 0);
    playback.control(Control::TogglePause).expect("resume");
    playback.control(Control::Faster).expect("faster");
    assert_eq!(playback.clock().config().time_scale, 2.0);
    assert_eq!(playback.advance(1.0 / 60.0).expect("frame").steps, 2);
    for _ in 0..10 {
        playback.control(Control::Faster).expect("faster");
    }
    assert_eq!(playback.clock().config().time_scale, 16.0, "capped at 16");
    for _ in 0..20 {
        playback.control(Control::Slower).expect("slower");
    }
    assert_eq!(playback.clock().config().time_scale, 0.0625, "floored at 1/16");
}

#[test]
fn integrators_switch_by_number_and_in_turn_and_reset_keeps_the_choice() {
    let mut playback = projectile(); // velocity Verlet
    playback.control(Control::Integrator(0)).expect("first method");
    assert_eq!(playback.world().integrator().info().name, METHODS[0].name);
    playback.control(Control::NextIntegrator).expect("next");
    assert_eq!(playback.world().integrator().info().name, METHODS[1].name);
    let last = METHODS.len() - 1;
    playback.control(Control::Integrator(last)).expect("last");
    playback.control(Control::NextIntegrator).expect("wraps");
    assert_eq!(playback.world().integrator().info().name, METHODS[0].name);
    let error = playback.control(Control::Integrator(99)).expect_err("no method 100");
    assert!(error.to_string().starts_with("unknown integrator '#100'"), "{error}");

    let rk4 = METHODS.iter().position(|m| m.name == "rk4").expect("registered");
    playback.control(Control::Integrator(rk4)).expect("rk4");
    // The initial state with the viewer's method (the hash covers the method).
    let initial = {
        let mut fresh = projectile();
        fresh.control(Control::Integrator(rk4)).expect("rk4");
        fresh.world().state_hash()
    };
    for _ in 0..30 {
        playback.advance(1.0 / 60.0).expect("frame");
    }
    assert_ne!(playback.world().state_hash(), initial);
    playback.control(Control::Reset).expect("reset");
    assert_eq!(playback.world().tick(), 0);
    assert_eq!(playback.world().integrator().info().name, METHODS[rk4].name);
    assert_eq!(
        playback.world().state_hash(),
        initial,
        "reset restores the initial state"
    );
}

#[test]
fn the_hud_reports_the_frame_the_method_and_the_energy() {
    let mut playback = projectile();
    playback.advance(1.0 / 30.0).expect("frame");
    let mut hud = String::new();
    playback.hud_text(&mut hud);
    let lines: Vec<&str> = hud.lines().collect();
    assert_eq!(lines[0], "projectile  |  velocity_verlet");
    assert_eq!(lines[1], "30 fps  |  2 steps this frame  |  dropped 0.000 s  |  x1");
    // Velocity Verlet conserves the projectile's energy to round-off.
    assert!(
        lines[2].starts_with("1 particles  |  t = 0.03 s  |  energy "),
        "{}",
        lines[2]
    );
    let drift: f64 = lines[2]
        .rsplit("drift ")
        .next()
        .and_then(|s| s.trim_end_matches(')').parse().ok())
        .expect("a drift figure");
    assert!(drift.abs() < 1e-5, "{drift}");
    playback.control(Control::TogglePause).expect("pause");
    playback.advance(0.5).expect("frame");
    playback.hud_text(&mut hud);
    assert!(hud.lines().next().expect("line").ends_with("|  paused"), "{hud}");
}

#[test]
fn trails_record_one_point_per_step() {
    let mut playback = projectile();
    for _ in 0..10 {
        playback.advance(1.0 / 20.0).expect("frame"); // 3 steps each
    }
    assert_eq!(playback.world().tick(), 30);
    let followed: Vec<_> = playback.trails_mut().entities().collect();
    assert_eq!(followed.len(), 1, "scenes of up to 8 particles get trails");
    let points: Vec<_> = playback.trails_mut().points(followed[0]).collect();
    assert_eq!(points.len(), 30);
    assert_eq!(points[29], playback.world().position(followed[0]).expect("alive"));
    // x = 7.5 t: one point per step of 1/60 s.
    assert!((points[0].x - 7.5 / 60.0).abs() < 1e-5, "{}", points[0].x);
}

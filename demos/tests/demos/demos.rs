//! Every demo binary as a user runs it without a display: a fixed number of
//! frames off-screen, the last one matched against its golden image, and
//! the outcome each prints checked against what the physics says. The
//! lander is played by a recorded input file to a known outcome.
//!
//! Needs a graphics adapter (Mesa's software Vulkan driver, which
//! `scripts/test` installs); nothing here skips without one.

use std::path::{Path, PathBuf};
use std::process::Command;

use tickwork::engine::app::{FrameSource, GameSession, Key, Recording, SessionOptions};
use tickwork::engine::render::GoldenImages;
use tickwork_demos::lander::{Flight, Lander};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn scratch(name: &str) -> PathBuf {
    let dir = root().join("target/test-demos").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch dir");
    dir
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// Runs `binary` headless for `frames` frames (0: its default) of 480x270
/// (or `--size` in `extra`) into a scratch directory; returns its standard
/// output and the last frame.
fn run_demo(binary: &str, name: &str, frames: u64, extra: &[&str]) -> (String, image::RgbaImage) {
    let dir = scratch(name);
    let out = dir.join("frames");
    let gif = dir.join(format!("{name}.gif"));
    let frames_text = frames.to_string();
    let mut args = vec!["--headless"];
    if !extra.contains(&"--size") {
        args.extend(["--size", "480x270"]);
    }
    args.extend([
        "--out",
        out.to_str().expect("utf-8"),
        "--gif",
        gif.to_str().expect("utf-8"),
    ]);
    if frames > 0 {
        args.extend(["--frames", &frames_text]);
    }
    args.extend(extra);
    let output = Command::new(binary).args(&args).output().expect("runs");
    let stdout = text(&output.stdout);
    assert!(
        output.status.success(),
        "{name} failed:\n{stdout}\n{}",
        text(&output.stderr)
    );
    assert!(
        stdout.contains(&format!("to {}/ and the GIF {}", out.display(), gif.display())),
        "{name} says where its frames went:\n{stdout}"
    );
    let pngs = std::fs::read_dir(&out).expect("frames written").count() as u64;
    if frames > 0 {
        assert_eq!(pngs, frames, "{name}: one PNG per frame");
    }
    let gif_frames = image::codecs::gif::GifDecoder::new(std::io::BufReader::new(
        std::fs::File::open(&gif).expect("the GIF exists"),
    ))
    .map(|d| image::AnimationDecoder::into_frames(d).count())
    .expect("a GIF");
    assert_eq!(gif_frames as u64, pngs, "{name}: one GIF frame per PNG");
    let last = image::open(out.join(format!("frame_{:05}.png", pngs - 1)))
        .expect("the last frame decodes")
        .to_rgba8();
    (stdout, last)
}

fn check_golden(name: &str, image: &image::RgbaImage) {
    let golden = GoldenImages::new(root().join("assets/golden"), root().join("target/golden"));
    if let Err(error) = golden.check(name, image) {
        panic!("{error}");
    }
}

/// The value after `key=` in `line`.
fn value(line: &str, key: &str) -> f64 {
    let start = line
        .find(&format!(" {key}="))
        .unwrap_or_else(|| panic!("{key} in {line}"))
        + key.len()
        + 2;
    line[start..]
        .split_whitespace()
        .next()
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("a number after {key}= in {line}"))
}

#[test]
fn orbits_races_every_integrator_and_euler_spirals_out_while_symplectic_methods_stay_bound() {
    // 360 frames at 60 fps of a 120 Hz simulation: two periods of 3 s.
    let (stdout, last) = run_demo(env!("CARGO_BIN_EXE_orbits"), "orbits", 360, &["--size", "800x450"]);
    let line = stdout
        .lines()
        .find(|l| l.starts_with("orbits: energy error"))
        .unwrap_or_else(|| panic!("the outcome line:\n{stdout}"));
    assert_eq!(
        line.matches('=').count(),
        tickwork::integrators::METHODS.len(),
        "{line}"
    );
    // Explicit Euler gains energy every step: it is far off after two orbits.
    assert!(value(line, "explicit_euler") > 0.3, "{line}");
    // Symplectic methods keep a nearby energy: bounded error, of their order.
    for method in ["semi_implicit_euler", "leapfrog", "velocity_verlet", "position_verlet"] {
        assert!(value(line, method).abs() < 0.1, "{method}: {line}");
    }
    assert!(value(line, "forest_ruth").abs() < 1e-5, "{line}");
    assert!(value(line, "rk4").abs() < 1e-3, "{line}");
    check_golden("demo_orbits", &last);
}

#[test]
fn fountain_spawns_at_its_emitters_rate_and_matches_its_golden_frame() {
    let (stdout, last) = run_demo(env!("CARGO_BIN_EXE_fountain"), "fountain", 120, &["--seed", "3"]);
    // 3 jets x 6 000 particles per second x 2 s (120 steps at 60 Hz), none
    // old enough to expire (3.4 s).
    assert!(stdout.contains("fountain: 36000 droplets alive"), "{stdout}");
    check_golden("demo_fountain", &last);
}

/// The line that gives a run's final checksum.
fn checksum_line(stdout: &str) -> &str {
    stdout
        .lines()
        .find(|l| l.contains("the final state at tick"))
        .unwrap_or_else(|| panic!("no checksum line:\n{stdout}"))
}

#[test]
fn fountain_on_the_gpu_ends_in_the_cpus_checksum_and_matches_the_same_golden_frame() {
    // Emitters, lifetimes of 3.4 s and a wind the game switches: the GPU
    // step follows the world's rows; on lavapipe its state is the CPU's.
    let (cpu, _) = run_demo(env!("CARGO_BIN_EXE_fountain"), "fountain_cpu", 120, &["--seed", "3"]);
    let (gpu, last) = run_demo(
        env!("CARGO_BIN_EXE_fountain"),
        "fountain_gpu",
        120,
        &["--seed", "3", "--gpu"],
    );
    assert_eq!(checksum_line(&gpu), checksum_line(&cpu));
    assert!(gpu.contains("fountain: 36000 droplets alive"), "{gpu}");
    // Drawn from the GPU's buffers, as the CPU's run is drawn.
    check_golden("demo_fountain", &last);
}

#[test]
fn the_fountain_takes_its_size_and_a_timing_run_writes_no_frames() {
    // 30 600 droplets when full: 3 jets of 3 000 a second; after one
    // second (60 steps) 9 000, none expired (3.4 s).
    let output = Command::new(env!("CARGO_BIN_EXE_fountain"))
        .args([
            "--headless",
            "--gpu",
            "--particles",
            "30600",
            "--frames",
            "60",
            "--size",
            "160x90",
        ])
        .arg("--no-frames")
        .output()
        .expect("runs");
    let stdout = text(&output.stdout);
    assert!(output.status.success(), "{stdout}\n{}", text(&output.stderr));
    assert!(stdout.contains("fountain: 9000 droplets alive"), "{stdout}");
    assert!(
        stdout.contains("tickwork: drew 60 frames in ") && stdout.contains("none written: --no-frames"),
        "{stdout}"
    );
    assert!(!stdout.contains("wrote"), "{stdout}");
    // Frames written and none: a contradiction, refused.
    let output = Command::new(env!("CARGO_BIN_EXE_fountain"))
        .args(["--headless", "--no-frames", "--out", "somewhere"])
        .output()
        .expect("runs");
    assert!(!output.status.success());
    assert!(
        text(&output.stderr).contains("'--no-frames' cannot be used with '--out <OUT>'"),
        "{}",
        text(&output.stderr)
    );
}

#[test]
fn cloth_blows_up_under_explicit_euler_and_stays_stable_under_implicit_methods() {
    let (stdout, last) = run_demo(env!("CARGO_BIN_EXE_cloth"), "cloth", 90, &[]);
    let line = stdout
        .lines()
        .find(|l| l.starts_with("cloth: "))
        .unwrap_or_else(|| panic!("{stdout}"));
    assert!(line.starts_with("cloth: explicit_euler blew up"), "{line}");
    assert!(line.contains("non-finite"), "{line}");
    assert!(line.ends_with("implicit_euler stable, newmark_beta stable"), "{line}");
    check_golden("demo_cloth", &last);
}

#[test]
fn tops_runs_both_angular_methods_side_by_side() {
    let (stdout, last) = run_demo(env!("CARGO_BIN_EXE_tops"), "tops", 120, &[]);
    let line = stdout
        .lines()
        .find(|l| l.starts_with("tops: energy error: "))
        .unwrap_or_else(|| panic!("{stdout}"));
    assert!(
        line.contains("quaternion_euler ") && line.contains("exponential_map "),
        "{line}"
    );
    check_golden("demo_tops", &last);
}

fn recording() -> PathBuf {
    root().join("assets/recordings/lander_land_then_crash.ron")
}

#[test]
fn the_lander_replays_a_recording_to_a_landing_then_a_crash() {
    // No --frames: as many as the recording needs.
    let replay = recording();
    let (stdout, last) = run_demo(
        env!("CARGO_BIN_EXE_lander"),
        "lander",
        0,
        &["--replay", replay.to_str().expect("utf-8")],
    );
    assert!(
        stdout.contains("lander: crashed (missed the pad), score 677"),
        "first flight landed for 677, the second missed the pad:\n{stdout}"
    );
    check_golden("demo_lander", &last);
}

/// Plays the recording through a session without a GPU, with frames of
/// `frame` seconds; returns the outcomes seen and the final state hash.
fn replay(frame: impl Fn(u64) -> f64) -> (Vec<(u64, Flight)>, u64) {
    let recording = Recording::load(&recording()).expect("the recording loads");
    let ticks = recording.ticks;
    let mut session = GameSession::new(
        Lander::default(),
        SessionOptions {
            replay: Some(recording),
            ..SessionOptions::default()
        },
    )
    .expect("a session");
    let mut seen = vec![(0, session.game().flight())];
    let mut k = 0;
    while session.ticks() < ticks {
        session.advance(frame(k)).expect("steps");
        k += 1;
        let flight = session.game().flight();
        if seen.last().is_none_or(|(_, f)| *f != flight) {
            seen.push((session.ticks(), flight));
        }
    }
    // The frame that crosses the recording's end may run a step or two more.
    (seen, session.stage().worlds[0].world.state_hash())
}

#[test]
fn a_replay_is_bit_identical_whatever_the_frame_timing() {
    let (steady, hash_steady) = replay(|_| 1.0 / 60.0);
    assert_eq!(
        steady.iter().map(|(_, f)| *f).collect::<Vec<_>>(),
        [
            Flight::Flying,
            Flight::Landed { score: 677 },
            Flight::Flying,
            Flight::Crashed {
                reason: "missed the pad"
            }
        ]
    );
    assert_eq!(steady[1].0, 448, "touch-down at the recorded tick");
    // Uneven frames run the same ticks with the same inputs: the same
    // outcomes at the same ticks.
    let (uneven, _) = replay(|k| [0.004, 0.031, 0.0167, 0.009][k as usize % 4]);
    assert_eq!(steady, uneven, "the same outcomes at the same ticks");
    let (_, hash_again) = replay(|_| 1.0 / 60.0);
    assert_eq!(hash_steady, hash_again);
}

#[test]
fn a_recording_made_live_replays_to_the_same_state() {
    let dir = scratch("record");
    let path = dir.join("flight.ron");
    let mut live = GameSession::new(
        Lander::default(),
        SessionOptions {
            record: Some(path.clone()),
            ..SessionOptions::default()
        },
    )
    .expect("a session");
    // Frames of uneven length; keys change between them.
    for k in 0..200u64 {
        match k {
            20 => live.key(Key::Left, true),
            35 => live.key(Key::Left, false),
            40 => live.key(Key::Up, true),
            120 => live.key(Key::Up, false),
            _ => {}
        }
        live.advance(if k % 3 == 0 { 0.03 } else { 0.011 }).expect("steps");
    }
    let written = live.save_recording().expect("saved").expect("a path");
    assert_eq!(written, path);
    let recording = Recording::load(&path).expect("loads");
    assert_eq!(recording.ticks, live.ticks());
    let mut replayed = GameSession::new(
        Lander::default(),
        SessionOptions {
            replay: Some(recording),
            ..SessionOptions::default()
        },
    )
    .expect("a session");
    while replayed.ticks() < live.ticks() {
        replayed.advance(1.0 / 60.0).expect("steps");
    }
    assert_eq!(replayed.ticks(), live.ticks());
    assert_eq!(
        replayed.stage().worlds[0].world.state_hash(),
        live.stage().worlds[0].world.state_hash(),
        "the replay reaches the live run's exact state"
    );
    // Recording again to the same file is refused without --force.
    let again = GameSession::new(
        Lander::default(),
        SessionOptions {
            record: Some(path.clone()),
            ..SessionOptions::default()
        },
    );
    assert!(matches!(again, Err(tickwork::engine::app::RunError::Exists(p)) if p == path));
}

fn lander(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_lander"))
        .args(args)
        .output()
        .expect("runs")
}

#[test]
fn bad_options_and_files_are_errors_that_say_what_and_where() {
    let dir = scratch("errors");
    let broken = dir.join("broken.ron");
    std::fs::write(&broken, "Recording(\n    game: \"lander\",\n    hz: sixty,\n)").expect("write");
    let cases: [(Vec<String>, &str); 5] = [
        (
            vec!["--headless".into(), "--replay".into(), broken.display().to_string()],
            "line 3, column",
        ),
        (vec!["--headless".into(), "--integrator".into(), "eulr".into()], "eulr"),
        (
            vec!["--size".into(), "0x100".into()],
            "not a positive whole number of pixels",
        ),
        (vec!["--hz=-5".into()], "not a positive, finite number"),
        (
            vec![
                "--headless".into(),
                "--replay".into(),
                recording().display().to_string(),
                "--hz".into(),
                "30".into(),
            ],
            "--hz differs from the recording's",
        ),
    ];
    for (args, expected) in cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let output = lander(&args);
        let stderr = text(&output.stderr);
        assert!(!output.status.success(), "{args:?} must fail");
        assert!(
            stderr.contains(expected),
            "{args:?}: expected {expected:?} in:\n{stderr}"
        );
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    }
    // A recording of another game.
    let other = dir.join("other.ron");
    std::fs::write(
        &other,
        std::fs::read_to_string(recording())
            .expect("read")
            .replace("game: \"lander\"", "game: \"orbits\""),
    )
    .expect("write");
    let output = lander(&["--headless", "--replay", other.to_str().expect("utf-8")]);
    assert!(
        text(&output.stderr).contains("the recording is of \"orbits\", not \"lander\""),
        "{}",
        text(&output.stderr)
    );
    assert!(Path::new(&other).exists());
}

#[test]
fn a_recording_that_cannot_be_saved_is_refused_before_the_run() {
    // It was refused only after the whole run, losing the input.
    let out = root().join("target/test-demos/record-refused");
    let _ = std::fs::remove_dir_all(&out);
    for (record, expected) in [
        (
            "/nonexistent-dir/r.ron",
            "/nonexistent-dir/r.ron: the directory /nonexistent-dir does not exist",
        ),
        ("/", "/: is a directory; name a file"),
    ] {
        let output = std::process::Command::new(env!("CARGO_BIN_EXE_orbits"))
            .args(["--headless", "--frames", "3", "--record", record, "--out"])
            .arg(&out)
            .output()
            .expect("runs");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(!output.status.success(), "{record}: accepted");
        assert!(stderr.contains(expected), "{record}: {stderr}");
        assert!(!out.exists(), "{record}: frames were drawn before the refusal");
    }
}

#[test]
fn a_recording_keeps_its_final_checksum_and_a_replay_says_whether_it_matches() {
    let dir = root().join("target/test-demos/record-checksum");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a folder");
    let record = dir.join("orbits.ron");
    let run = |args: &[&str]| {
        let output = Command::new(env!("CARGO_BIN_EXE_orbits"))
            .args(["--headless", "--no-frames"])
            .args(args)
            .output()
            .expect("runs");
        let stdout = text(&output.stdout);
        assert!(output.status.success(), "{stdout}\n{}", text(&output.stderr));
        stdout
    };
    let recorded = run(&["--frames", "60", "--record", record.to_str().expect("utf-8")]);
    let line = checksum_line(&recorded);
    let checksum = line.rsplit(' ').next().expect("a checksum").to_owned();
    let tick: u64 = line
        .split("the final state at tick ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .and_then(|t| t.parse().ok())
        .unwrap_or_else(|| panic!("a tick: {line}"));
    let file = std::fs::read_to_string(&record).expect("the recording");
    let kept = u64::from_str_radix(&checksum, 16).expect("hex");
    assert!(file.contains(&format!("checksum: Some({kept})")), "{file}");
    // Replayed with frames to spare: it stops at the recording's end and
    // says in one line that it matches.
    let replayed = run(&["--frames", "90", "--replay", record.to_str().expect("utf-8")]);
    let ends: Vec<&str> = replayed
        .lines()
        .filter(|l| l.contains("the replay ended") || l.contains("the final state"))
        .collect();
    assert_eq!(
        ends,
        [format!(
            "tickwork: orbits: the replay ended at tick {tick} with checksum {checksum}: it matches the recording"
        )],
        "{replayed}"
    );
    // A recording whose checksum is not the run's: where they differ.
    let other = dir.join("other.ron");
    std::fs::write(
        &other,
        file.replace(&format!("checksum: Some({kept})"), "checksum: Some(1)"),
    )
    .expect("written");
    let differs = run(&["--frames", "90", "--replay", other.to_str().expect("utf-8")]);
    assert!(
        differs.contains(&format!(
            "the replay ended at tick {tick} with checksum {checksum}: the recording ended with checksum \
             0000000000000001: this run differs from it"
        )),
        "{differs}"
    );
}

/// Runs `binary` under `--sync-test 7` with `extra`; returns its output.
fn sync_test(binary: &str, extra: &[&str]) -> String {
    let output = Command::new(binary)
        .args(["--sync-test", "7"])
        .args(extra)
        .output()
        .expect("runs");
    let stdout = text(&output.stdout);
    assert!(output.status.success(), "{binary}:\n{stdout}\n{}", text(&output.stderr));
    stdout
}

#[test]
fn every_demo_re_simulates_to_the_same_states_under_a_rollback_sync_test() {
    for (binary, name) in [
        (env!("CARGO_BIN_EXE_orbits"), "orbits"),
        (env!("CARGO_BIN_EXE_fountain"), "fountain"),
        (env!("CARGO_BIN_EXE_cloth"), "cloth"),
        (env!("CARGO_BIN_EXE_tops"), "tops"),
        (env!("CARGO_BIN_EXE_breakout"), "breakout"),
        (env!("CARGO_BIN_EXE_rally"), "rally"),
    ] {
        let stdout = sync_test(binary, &["--frames", "90"]);
        assert!(
            stdout.contains(&format!(
                "tickwork: {name}: sync test passed: 90 ticks, each rolled back 7 ticks"
            )),
            "{stdout}"
        );
    }
    // The lander on its recording: the same landing and crash as the replay,
    // every tick of it rolled back and re-simulated.
    let replay = recording();
    let stdout = sync_test(
        env!("CARGO_BIN_EXE_lander"),
        &["--replay", replay.to_str().expect("utf-8")],
    );
    assert!(
        stdout.contains("tickwork: lander: sync test passed: 723 ticks"),
        "{stdout}"
    );
    assert!(
        stdout.contains("lander: crashed (missed the pad), score 677"),
        "{stdout}"
    );
}

#[test]
fn the_integrator_option_runs_a_race_of_the_named_methods_and_is_refused_where_it_would_be_ignored() {
    // Orbits races the integrators it is given, one world each.
    let stdout = sync_test(
        env!("CARGO_BIN_EXE_orbits"),
        &["--frames", "3", "--integrator", "rk4,leapfrog"],
    );
    let line = stdout
        .lines()
        .find(|l| l.starts_with("orbits: energy error"))
        .unwrap_or_else(|| panic!("the outcome line:\n{stdout}"));
    assert_eq!(line.matches('=').count(), 2, "{line}");
    assert!(line.contains(" rk4=") && line.contains(" leapfrog="), "{line}");
    // The tops fix their angular methods' worlds: a name there would be
    // ignored, so it is refused as the one-world games refuse a list.
    for integrator in ["rk4", "rk4,leapfrog"] {
        let output = Command::new(env!("CARGO_BIN_EXE_tops"))
            .args(["--sync-test", "1", "--frames", "3", "--integrator", integrator])
            .output()
            .expect("runs");
        assert_eq!(output.status.code(), Some(1), "{integrator}: refused");
        assert_eq!(
            text(&output.stderr),
            format!(
                "error: --integrator {integrator}: tops fixes the integrator of each of its worlds \
                 (\"quaternion_euler\", \"exponential_map\"), so the option would be ignored; run it without \
                 --integrator\n"
            )
        );
    }
}

#[test]
fn a_successful_headless_run_says_nothing_about_xdg_runtime_dir() {
    // Without XDG_RUNTIME_DIR, Mesa's device-select Vulkan layer printed
    // "error: XDG_RUNTIME_DIR is invalid or not set" twice on every run
    // that found an adapter; the binaries quiet it before any thread starts.
    let dir = scratch("no-xdg");
    let scene = root().join("assets/scenes/projectile.ron");
    let runs: [(&str, Vec<String>); 2] = [
        (
            env!("CARGO_BIN_EXE_lander"),
            ["--headless", "--frames", "2", "--out"]
                .map(String::from)
                .into_iter()
                .chain([dir.join("lander").display().to_string()])
                .collect(),
        ),
        (
            env!("CARGO_BIN_EXE_tickwork"),
            [
                "render".into(),
                scene.display().to_string(),
                "--frames".into(),
                "2".into(),
                "--out".into(),
            ]
            .into_iter()
            .chain([dir.join("render").display().to_string()])
            .collect(),
        ),
    ];
    for (binary, args) in runs {
        let output = Command::new(binary)
            .args(&args)
            .env_remove("XDG_RUNTIME_DIR")
            .env_remove("NODEVICE_SELECT")
            .output()
            .expect("runs");
        let stderr = text(&output.stderr);
        assert!(output.status.success(), "{binary} {args:?}:\n{stderr}");
        assert!(
            !stderr.contains("XDG_RUNTIME_DIR"),
            "{binary} {args:?} warned about XDG_RUNTIME_DIR:\n{stderr}"
        );
        assert!(text(&output.stdout).contains("2 frames"), "{}", text(&output.stdout));
    }
}

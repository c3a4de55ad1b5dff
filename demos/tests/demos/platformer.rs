//! The platformer showcase: the autopilot crosses the Tiled level to the
//! flag (coins, the ferry over the spikes, steps), the off-screen frame
//! matches its golden image, a recorded game replays to the same state and
//! the same animation frames, and the whole run passes the rollback sync
//! test.

use std::path::PathBuf;
use std::process::Command;

use tickwork::engine::app::{FrameSource, GameSession, Recording, SessionOptions};
use tickwork::engine::render::GoldenImages;
use tickwork::prelude::*;
use tickwork_demos::platformer::Platformer;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn scratch(name: &str) -> PathBuf {
    let dir = root().join("target/test-platformer").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch directory");
    dir
}

/// Runs the platformer binary with `args`; its output, once it succeeded.
fn platformer(args: &[&str]) -> String {
    let output = Command::new(env!("CARGO_BIN_EXE_platformer"))
        .args(args)
        .output()
        .expect("runs");
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(
        output.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    stdout
}

fn session(game: Platformer, options: SessionOptions) -> GameSession<Platformer> {
    GameSession::new(game, options).expect("a session")
}

/// The hero's sprite as `session` draws it now: its atlas region and
/// whether it is flipped (the last sprite the game draws).
fn hero_frame(session: &GameSession<Platformer>) -> (Option<[u32; 4]>, bool) {
    let mut draw = Draw::default();
    session.game().draw(session.stage(), 1.0, &mut draw).expect("draws");
    let hero = draw.sprites.last().expect("the hero");
    (hero.region, hero.flip_x)
}

#[test]
fn the_autopilot_takes_every_coin_rides_the_ferry_and_reaches_the_flag() {
    let mut game = session(Platformer::new(true), SessionOptions::default());
    let mut rode = false;
    while game.game().finished.is_none() && game.ticks() < 60 * 60 {
        game.advance(1.0 / 60.0).expect("steps");
        let world = &game.stage().worlds[0].world;
        let (_, hero) = world.characters().next().expect("the hero");
        // Over the spikes (x 21 to 31) it stands on the ferry, never below.
        if (21.5..30.5).contains(&hero.position.x) {
            assert!(hero.position.y > 3.0, "above the spikes at {}", hero.position);
            rode |= hero.ground().is_some();
        }
    }
    assert!(rode, "the ferry carried the hero over the pit");
    let outcome = game.outcome().expect("an outcome");
    assert_eq!(outcome, "reached the flag at tick 917 with 3 coins and 0 deaths");
    let count = |name: &str| game.played_sounds().filter(|p| &*p.sound == name).count();
    assert_eq!(
        (count("brick"), count("lost")),
        (3, 0),
        "a sound a coin, none for a death"
    );
    // A sound a jump: over the gap, off the pillar, up the last step.
    assert_eq!(count("paddle"), 3);
}

#[test]
fn the_demo_plays_itself_off_screen_to_its_golden_frame() {
    let out = scratch("frames");
    let out_arg = out.to_str().expect("utf-8");
    let stdout = platformer(&[
        "--headless",
        "--autopilot",
        "--frames",
        "700",
        "--size",
        "480x270",
        "--out",
        out_arg,
    ]);
    assert!(
        stdout.contains("platformer: stopped before the flag with 3 coins and 0 deaths"),
        "{stdout}"
    );
    let last = image::open(out.join("frame_00699.png"))
        .expect("the last frame")
        .to_rgba8();
    let golden = GoldenImages::new(root().join("assets/golden"), root().join("target/golden"));
    golden.check("demo_platformer", &last).unwrap_or_else(|e| panic!("{e}"));
}

#[test]
fn a_recorded_game_replays_to_the_same_state_and_animation_frames() {
    let path = scratch("record").join("game.ron");
    let mut live = session(
        Platformer::new(false),
        SessionOptions {
            record: Some(path.clone()),
            ..SessionOptions::default()
        },
    );
    let mut frames = Vec::new();
    for k in 0..420u64 {
        match k {
            5 => live.key(Key::Right, true),
            40 | 150 | 300 => live.key(Key::Space, true),
            44 | 170 | 302 => live.key(Key::Space, false),
            200 => live.key(Key::Right, false),
            210 => live.key(Key::Left, true),
            240 => live.key(Key::Left, false),
            250 => live.key(Key::D, true),
            _ => {}
        }
        live.advance(if k % 3 == 0 { 0.027 } else { 0.012 }).expect("steps");
        frames.push((live.ticks(), hero_frame(&live)));
    }
    live.save_recording().expect("saved");
    let recording = Recording::load(&path).expect("loads");
    assert_eq!(recording.ticks, live.ticks());
    let flipped = frames.iter().filter(|(_, (_, flip))| *flip).count();
    let running: std::collections::BTreeSet<_> = frames.iter().map(|(_, (region, _))| *region).collect();
    assert!(
        flipped > 0 && running.len() >= 5,
        "it ran both ways through the frames: {running:?}"
    );
    // Replayed a step a frame: each tick's frame is the live run's at it.
    let mut replayed = session(
        Platformer::new(false),
        SessionOptions {
            replay: Some(recording),
            ..SessionOptions::default()
        },
    );
    while replayed.ticks() < live.ticks() {
        replayed.advance(1.0 / 60.0).expect("steps");
        if let Some((_, frame)) = frames.iter().find(|(tick, _)| *tick == replayed.ticks()) {
            assert_eq!(hero_frame(&replayed), *frame, "tick {}", replayed.ticks());
        }
    }
    assert_eq!(replayed.checksum(), live.checksum(), "the live run's exact state");
    assert_eq!(replayed.outcome(), live.outcome());
}

#[test]
fn the_whole_run_to_the_flag_passes_the_rollback_sync_test() {
    let stdout = platformer(&["--sync-test", "7", "--autopilot", "--frames", "940"]);
    assert!(
        stdout.contains("tickwork: platformer: sync test passed: 940 ticks, each rolled back 7 ticks"),
        "{stdout}"
    );
    assert!(
        stdout.contains("platformer: reached the flag at tick 917 with 3 coins and 0 deaths"),
        "{stdout}"
    );
}

#[test]
fn the_showcase_stays_within_300_lines_with_its_options_and_main() {
    let lines = |path: &str| {
        std::fs::read_to_string(root().join(path))
            .expect("the source")
            .lines()
            .count()
    };
    let total = lines("demos/src/platformer.rs") + lines("demos/src/bin/platformer.rs");
    assert!(total <= 300, "{total} lines");
}

#[test]
fn a_rollback_redraws_the_same_animation_frames() {
    // Ticks stepped directly with an input a tick, as a rollback session
    // does: run right, jump at tick 30 and 90, left from 120.
    let input = |tick: u64| {
        let mut input = TickInput::default();
        input.held.insert(if tick < 120 { Key::Right } else { Key::Left });
        if tick == 30 || tick == 90 {
            input.held.insert(Key::Space);
            input.pressed.insert(Key::Space);
        }
        input
    };
    let mut game = session(Platformer::new(false), SessionOptions::default());
    for tick in 0..60 {
        game.step_tick(tick, &[input(tick)]).expect("steps");
    }
    let saved = game.save_tick();
    let mut frames = Vec::new();
    for tick in 60..160 {
        game.step_tick(tick, &[input(tick)]).expect("steps");
        frames.push(hero_frame(&game));
    }
    let end = game.checksum();
    // Back to tick 60 and the same ticks again: the same frames, drawn.
    game.load_tick(&saved).expect("loads");
    for (k, tick) in (60..160).enumerate() {
        game.step_tick(tick, &[input(tick)]).expect("steps");
        assert_eq!(hero_frame(&game), frames[k], "tick {tick}");
    }
    assert_eq!(game.checksum(), end);
    let distinct: std::collections::BTreeSet<_> = frames.iter().collect();
    assert!(distinct.len() >= 5, "it ran, jumped and turned: {distinct:?}");
}

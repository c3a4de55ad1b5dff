//! @NAME@'s tests: its first second drawn off-screen against a golden
//! image, and a recording replayed to the same state at any frame rate.
//! `TICKWORK_BLESS=1 cargo test` rewrites the golden image after a change
//! you meant (look at it first).

use std::path::Path;

use @CRATE@::@TYPE@;
use tickwork::engine::Recording;
use tickwork::engine::app::{FrameSource, GameSession, OffscreenRun, SessionOptions, renderer_config};
use tickwork::engine::render::{GoldenImages, Gpu};

#[test]
fn the_first_second_looks_as_it_should() -> Result<(), Box<dyn std::error::Error>> {
    let gpu = Gpu::headless()?;
    let mut session = GameSession::new(@TYPE@::default(), SessionOptions::default())?;
    // Drawn as `run` draws the game (its background, its HUD at 180 px).
    let mut frames = OffscreenRun::new(&gpu, 320, 180, renderer_config(session.stage(), 180))?;
    let mut image = frames.frame(&mut session, 1.0 / 60.0, true)?;
    for _ in 1..60 {
        image = frames.frame(&mut session, 1.0 / 60.0, true)?;
    }
    assert_eq!(session.ticks(), 60);
    GoldenImages::new("tests/golden", "target/golden").check("first_second", &image)?;
    Ok(())
}

#[test]
fn the_recording_replays_to_the_same_state_at_any_frame_rate() -> Result<(), Box<dyn std::error::Error>> {
    let recording = Recording::load(Path::new("recordings/kicks.ron"))?;
    let mut checksums = Vec::new();
    for display_hz in [120.0, 144.0, 240.0] {
        let options = SessionOptions { replay: Some(recording.clone()), ..SessionOptions::default() };
        let mut session = GameSession::new(@TYPE@::default(), options)?;
        // At most one 60 Hz step a frame: every run stops at the same tick.
        for _ in 0..10_000 {
            if session.ticks() >= recording.ticks {
                break;
            }
            session.advance(1.0 / display_hz)?;
        }
        assert_eq!(session.ticks(), recording.ticks);
        assert_eq!(session.game().kicks, 3, "three presses of Space, three kicks");
        checksums.push(session.checksum());
    }
    assert!(checksums.windows(2).all(|pair| pair[0] == pair[1]), "checksums differ: {checksums:x?}");
    Ok(())
}

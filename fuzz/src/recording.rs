//! Recording cases: mutated input recordings parsed and, when accepted,
//! replayed for a few frames by the game they name (the lander, the one
//! shipped with a recording). A refusal must give a line and column.

use std::path::Path;

use tickwork_demos::lander::Lander;
use tickwork_engine::app::{FrameSource, GameSession, Recording, SessionOptions};

use crate::case::{Outcome, Stage};

/// Frames of 1/60 s replayed per accepted recording.
pub const FRAMES: u32 = 8;

/// Runs one recording case. `Err` is a defect (a refusal without a line
/// and column, an empty message); panics propagate.
///
/// # Errors
/// The defect found.
pub fn run_recording_case(text: &str) -> Result<Outcome, String> {
    let recording = match Recording::parse(text, Path::new("fuzz-recording.ron")) {
        Ok(recording) => recording,
        Err(error) => {
            let message = error.to_string();
            if !(message.contains("line ") && message.contains(", column ")) {
                return Err(format!("a recording error without a line and column: {message}"));
            }
            return Ok(Outcome::Refused(Stage::Parse, message));
        }
    };
    let options = SessionOptions {
        replay: Some(recording),
        ..SessionOptions::default()
    };
    let mut session = match GameSession::new(Lander::default(), options) {
        Ok(session) => session,
        Err(error) => return Ok(Outcome::Refused(Stage::Build, error.to_string())),
    };
    for _ in 0..FRAMES {
        if let Err(error) = session.advance(1.0 / 60.0) {
            return Ok(Outcome::Refused(Stage::Step, error.to_string()));
        }
    }
    Ok(Outcome::Stepped)
}

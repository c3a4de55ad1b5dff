//! Sounds: decoded from WAV bytes, started at the tick that asked for them,
//! once each however often rollback runs a tick, and logged (silently
//! here: a test machine has no audio device).

use tickwork_engine::FixedStep;
use tickwork_engine::app::{
    FrameSource, Game, GameError, GameSession, Played, SessionOptions, Settings, Sound, Stage, TickInput, sync_test,
};

/// A mono 16-bit PCM WAV file of `samples` samples at `rate` Hz (a quiet
/// square wave).
fn wav(rate: u32, samples: u32) -> Vec<u8> {
    let data = samples * 2;
    let mut out = Vec::new();
    out.extend_from_slice(b"RIFF");
    out.extend_from_slice(&(36 + data).to_le_bytes());
    out.extend_from_slice(b"WAVEfmt ");
    out.extend_from_slice(&16u32.to_le_bytes());
    out.extend_from_slice(&1u16.to_le_bytes()); // PCM
    out.extend_from_slice(&1u16.to_le_bytes()); // mono
    out.extend_from_slice(&rate.to_le_bytes());
    out.extend_from_slice(&(rate * 2).to_le_bytes());
    out.extend_from_slice(&2u16.to_le_bytes());
    out.extend_from_slice(&16u16.to_le_bytes());
    out.extend_from_slice(b"data");
    out.extend_from_slice(&data.to_le_bytes());
    for k in 0..samples {
        let v: i16 = if (k / 20) % 2 == 0 { 2_000 } else { -2_000 };
        out.extend_from_slice(&v.to_le_bytes());
    }
    out
}

/// Plays "blip" every 20 ticks and "boom" at tick 30.
#[derive(Clone)]
struct Noisy {
    blip: Sound,
    boom: Sound,
}

impl Game for Noisy {
    fn title(&self) -> &str {
        "noisy"
    }

    fn setup(&mut self, _stage: &mut Stage, _settings: &Settings) -> Result<(), GameError> {
        Ok(())
    }

    fn fixed_update(&mut self, stage: &mut Stage, step: &FixedStep, _input: &TickInput) -> Result<(), GameError> {
        if step.tick.is_multiple_of(20) {
            stage.play(&self.blip);
        }
        if step.tick == 30 {
            stage.play(&self.boom);
        }
        Ok(())
    }
}

fn noisy() -> Noisy {
    Noisy {
        blip: Sound::from_bytes("blip", wav(8_000, 800)).expect("a WAV"),
        boom: Sound::from_bytes("boom", wav(8_000, 4_000)).expect("a WAV"),
    }
}

/// The sounds a run of `ticks` ticks should start.
fn expected(ticks: u64) -> Vec<Played> {
    let mut out = Vec::new();
    for tick in 0..ticks {
        if tick.is_multiple_of(20) {
            out.push(Played {
                tick,
                sound: "blip".into(),
            });
        }
        if tick == 30 {
            out.push(Played {
                tick,
                sound: "boom".into(),
            });
        }
    }
    out
}

#[test]
fn wav_bytes_decode_and_bad_bytes_name_the_sound() {
    let boom = Sound::from_bytes("boom", wav(8_000, 4_000)).expect("a WAV");
    assert_eq!(boom.name(), "boom");
    assert!(
        (boom.duration().as_secs_f64() - 0.5).abs() < 1e-3,
        "{:?}",
        boom.duration()
    );
    let error = Sound::from_bytes("noise", b"not audio".to_vec()).expect_err("not a WAV");
    assert!(
        error.to_string().starts_with("sound \"noise\": not WAV or Ogg Vorbis"),
        "{error}"
    );
    let error = Sound::load("no/such/boom.wav").expect_err("no file");
    assert!(error.to_string().contains("no/such/boom.wav"), "{error}");
}

#[test]
fn each_sound_starts_once_at_the_tick_that_played_it() {
    let mut session = GameSession::new(noisy(), SessionOptions::default()).expect("a session");
    while session.ticks() < 61 {
        session.advance(1.0 / 60.0).expect("steps");
    }
    let played: Vec<Played> = session.played_sounds().cloned().collect();
    assert_eq!(played, expected(session.ticks()));
    assert!(played.contains(&Played {
        tick: 30,
        sound: "boom".into()
    }));
}

#[test]
fn a_sound_in_a_tick_that_rollback_runs_again_plays_once() {
    let mut session = GameSession::new(noisy(), SessionOptions::default()).expect("a session");
    // GGRS's sync test runs every tick again from 7 ticks back.
    let report = sync_test(&mut session, 7, 100, |_, _| TickInput::default()).expect("in sync");
    assert_eq!((report.ticks, report.check_distance), (100, 7));
    let played: Vec<Played> = session.played_sounds().cloned().collect();
    assert_eq!(played, expected(100), "once each, in order");
}

#[test]
fn a_machine_without_an_audio_device_runs_silently_and_logs_the_same() {
    // A test machine has no sound card (or the build no device support):
    // opening says so in one line and the run goes on.
    let mut session = GameSession::new(noisy(), SessionOptions::default()).expect("a session");
    session.open_audio_device();
    while session.ticks() < 41 {
        session.advance(1.0 / 60.0).expect("steps");
    }
    let played: Vec<Played> = session.played_sounds().cloned().collect();
    assert_eq!(played, expected(session.ticks()));
}

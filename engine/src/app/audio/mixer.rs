//! Sound output: each sound a tick asked for starts once, however often
//! the tick runs (a rollback re-simulates ticks; GGRS's sync test runs
//! every tick again), and is logged; it plays on the machine's audio
//! device where there is one (the `audio-device` feature), silently
//! otherwise (headless runs, replays, tests, machines without sound).
//!
//! ```text
//! key of a sound = (tick, its order k among that tick's sounds)
//! started once per key: per tick, how many have started (k below that count
//! has); ticks older than KEPT_TICKS before the newest are forgotten
//! (rollback never reaches that far back)
//! ```
//!
//! A sound started in a predicted tick that a rollback then re-simulates
//! differently has already been heard: it is not taken back (as in every
//! rollback engine).

use std::collections::VecDeque;
use std::sync::Arc;

use crate::app::audio::sound::Sound;

/// Ticks a started sound's key is kept: 10 s at 60 Hz, far past GGRS's
/// prediction window (8 ticks) and the sync test's check distance.
const KEPT_TICKS: u64 = 600;

/// Sounds kept in the log (the oldest go first).
pub const LOGGED_SOUNDS: usize = 65_536;

/// A sound that started: the tick that asked for it and its name.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Played {
    /// The tick whose `fixed_update` played it.
    pub tick: u64,
    /// The sound's name (shared with the sound: logging allocates nothing).
    pub sound: Arc<str>,
}

/// The sounds started (their keys, their log) and the device, if open.
pub(crate) struct Audio {
    /// Per tick that started sounds, in tick order: how many it started.
    started: VecDeque<(u64, usize)>,
    newest: u64,
    log: VecDeque<Played>,
    #[cfg(feature = "audio-device")]
    device: Option<kira::AudioManager<kira::DefaultBackend>>,
}

impl core::fmt::Debug for Audio {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Audio")
            .field("started", &self.started.len())
            .field("logged", &self.log.len())
            .field("device", &self.has_device())
            .finish()
    }
}

impl Audio {
    /// No device: every sound logged, none heard.
    pub(crate) fn silent() -> Self {
        Self {
            started: VecDeque::new(),
            newest: 0,
            log: VecDeque::new(),
            #[cfg(feature = "audio-device")]
            device: None,
        }
    }

    /// Opens the machine's audio device.
    ///
    /// # Errors
    /// Why there is none (no device, or a build without the
    /// `audio-device` feature): the run goes on silently.
    pub(crate) fn open_device(&mut self) -> Result<(), String> {
        #[cfg(feature = "audio-device")]
        {
            let manager = kira::AudioManager::<kira::DefaultBackend>::new(kira::AudioManagerSettings::default())
                .map_err(|e| format!("no audio device ({e})"))?;
            self.device = Some(manager);
            Ok(())
        }
        #[cfg(not(feature = "audio-device"))]
        Err("this build has no audio device support (build with the audio-device feature)".into())
    }

    fn has_device(&self) -> bool {
        #[cfg(feature = "audio-device")]
        return self.device.is_some();
        #[cfg(not(feature = "audio-device"))]
        false
    }

    /// Starts the sounds tick `tick` asked for, but those it already
    /// started (a tick run again).
    pub(crate) fn tick(&mut self, tick: u64, sounds: &[Sound]) {
        if tick > self.newest {
            self.newest = tick;
            let oldest = tick.saturating_sub(KEPT_TICKS);
            while self.started.front().is_some_and(|&(t, _)| t < oldest) {
                self.started.pop_front();
            }
        }
        if sounds.is_empty() {
            return;
        }
        // A tick run again is near the newest: searched from the back.
        let at = self.started.iter().rposition(|&(t, _)| t <= tick);
        let already = match at {
            Some(k) if self.started[k].0 == tick => {
                let count = &mut self.started[k].1;
                let already = *count;
                *count = (*count).max(sounds.len());
                already
            }
            Some(k) => {
                self.started.insert(k + 1, (tick, sounds.len()));
                0
            }
            None => {
                self.started.push_front((tick, sounds.len()));
                0
            }
        };
        for sound in sounds.iter().skip(already) {
            if self.log.len() == LOGGED_SOUNDS {
                self.log.pop_front();
            }
            self.log.push_back(Played {
                tick,
                sound: sound.name.clone(),
            });
            #[cfg(feature = "audio-device")]
            if let Some(device) = &mut self.device
                && device.play(sound.data.clone()).is_err()
            {
                // Past kira's sound capacity: this one is not heard (it is
                // still logged); the next may be.
            }
        }
    }

    /// Forgets what started (a restart runs the ticks anew).
    pub(crate) fn forget(&mut self) {
        self.started.clear();
        self.newest = 0;
    }

    /// The sounds started, oldest first (the last [`LOGGED_SOUNDS`]).
    pub(crate) fn played(&self) -> impl Iterator<Item = &Played> {
        self.log.iter()
    }
}

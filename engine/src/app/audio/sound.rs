//! Sounds a game plays: decoded once (WAV or Ogg Vorbis, by kira's decoder,
//! the same natively and in a page) and cheap to clone.

use core::fmt;
use std::io::Cursor;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Duration;

use kira::sound::static_sound::StaticSoundData;

/// A sound effect or a piece of music, ready to play:
/// [`Stage::play`](crate::app::Stage::play) in `fixed_update`.
#[derive(Clone)]
pub struct Sound {
    pub(crate) name: Arc<str>,
    pub(crate) data: StaticSoundData,
}

impl fmt::Debug for Sound {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Sound {:?} ({:.3} s)", self.name, self.duration().as_secs_f64())
    }
}

/// A sound that could not be made.
#[derive(Debug)]
pub enum SoundError {
    /// The file could not be read.
    Read {
        /// The file.
        path: PathBuf,
        /// Why.
        error: std::io::Error,
    },
    /// The bytes are not audio the decoder reads (WAV or Ogg Vorbis).
    Decode {
        /// The sound's name.
        name: String,
        /// The decoder's message.
        message: String,
    },
}

impl fmt::Display for SoundError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Read { path, error } => write!(f, "sound {}: {error}", path.display()),
            Self::Decode { name, message } => write!(
                f,
                "sound {name:?}: not WAV or Ogg Vorbis audio the decoder reads: {message}"
            ),
        }
    }
}

impl std::error::Error for SoundError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Read { error, .. } => Some(error),
            Self::Decode { .. } => None,
        }
    }
}

impl Sound {
    /// A sound named `name` (what logs and tests call it) from a WAV or
    /// Ogg Vorbis file's bytes (embedded with `include_bytes!`, or fetched
    /// by a page).
    ///
    /// # Errors
    /// [`SoundError::Decode`] naming the sound.
    pub fn from_bytes(name: impl Into<String>, bytes: Vec<u8>) -> Result<Self, SoundError> {
        let name = name.into();
        let data = StaticSoundData::from_cursor(Cursor::new(bytes)).map_err(|e| SoundError::Decode {
            name: name.clone(),
            message: e.to_string(),
        })?;
        Ok(Self {
            name: name.into(),
            data,
        })
    }

    /// A sound from a WAV or Ogg Vorbis asset file, named by its file's
    /// stem (`"boom"` for `sounds/boom.wav`): natively read from disk, in a
    /// page the bytes it fetched for `path` (list the path in
    /// [`Game::assets`](crate::app::Game::assets)); a relative path is found as
    /// [`platform::read_asset`](crate::platform::read_asset) says.
    ///
    /// # Errors
    /// [`SoundError::Read`] naming the file, or as
    /// [`from_bytes`](Self::from_bytes).
    pub fn load(path: impl AsRef<Path>) -> Result<Self, SoundError> {
        let path = path.as_ref();
        let bytes = crate::platform::read_asset(path).map_err(|error| SoundError::Read {
            path: path.to_path_buf(),
            error,
        })?;
        let name = path
            .file_stem()
            .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
        Self::from_bytes(name, bytes)
    }

    /// Its name.
    #[must_use]
    pub fn name(&self) -> &str {
        &self.name
    }

    /// How long it plays.
    #[must_use]
    pub fn duration(&self) -> Duration {
        self.data.duration()
    }
}

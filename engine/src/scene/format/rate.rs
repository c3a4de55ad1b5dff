//! The scene's fixed step, as steps per second or seconds per step.

use core::fmt;

use serde::{Deserialize, Serialize};

use super::numbers::Positive;

/// The fixed step.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum RateSpec {
    /// Steps per second.
    Hz(Positive),
    /// Step in seconds.
    Dt(Positive),
}

impl fmt::Display for RateSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Hz(hz) => write!(f, "{} Hz", hz.0),
            Self::Dt(dt) => write!(f, "dt = {} s", dt.0),
        }
    }
}

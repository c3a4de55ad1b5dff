//! Why the clock refused a frame duration or a setting.

use core::fmt;

use super::Number;

/// A rejected frame duration or setting.
#[derive(Clone, Debug, PartialEq)]
pub enum ClockError {
    /// A frame duration that is negative, NaN or infinite.
    InvalidFrameTime {
        /// The value given, in seconds.
        value: f64,
    },
    /// A rate or step that is zero, negative, not finite or out of range.
    InvalidRate {
        /// Which quantity.
        what: &'static str,
        /// The value given.
        value: f64,
        /// The accepted range.
        expected: &'static str,
    },
    /// A setting out of range.
    InvalidSetting {
        /// The field.
        field: &'static str,
        /// The value given.
        value: f64,
        /// What is allowed.
        expected: &'static str,
    },
}

impl fmt::Display for ClockError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::InvalidFrameTime { value } => {
                write!(
                    f,
                    "invalid frame duration: {} s (must be finite and not negative)",
                    Number(*value)
                )
            }
            Self::InvalidRate { what, value, expected } => {
                write!(f, "invalid {what}: {} (accepted: {expected})", Number(*value))
            }
            Self::InvalidSetting { field, value, expected } => {
                write!(
                    f,
                    "invalid clock setting {field}: {} (expected {expected})",
                    Number(*value)
                )
            }
        }
    }
}

impl std::error::Error for ClockError {}

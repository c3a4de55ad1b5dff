//! Gamepads as a fixed step sees them: buttons latched per tick exactly as
//! keys are (held, pressed, released), and sticks and triggers as values
//! quantised to 16 bits, so a tick's input is the same bits on every
//! machine, in a recording and on the wire.
//!
//! ```text
//! stored  q = round(clamp(v, -1, 1) * 32767)      read  v = q / 32767
//! ```

use core::fmt;

use serde::{Deserialize, Serialize};

/// Gamepads a tick holds: the first four connected.
pub const MAX_PADS: usize = 4;

/// A gamepad button, by its place (the south face button is A on an Xbox
/// pad, Cross on a PlayStation one).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[allow(missing_docs)]
pub enum PadButton {
    South,
    East,
    West,
    North,
    LeftBumper,
    RightBumper,
    LeftTrigger,
    RightTrigger,
    Select,
    Start,
    LeftStick,
    RightStick,
    DPadUp,
    DPadDown,
    DPadLeft,
    DPadRight,
}

impl PadButton {
    /// Every button, in bit order.
    pub const ALL: [PadButton; 16] = [
        PadButton::South,
        PadButton::East,
        PadButton::West,
        PadButton::North,
        PadButton::LeftBumper,
        PadButton::RightBumper,
        PadButton::LeftTrigger,
        PadButton::RightTrigger,
        PadButton::Select,
        PadButton::Start,
        PadButton::LeftStick,
        PadButton::RightStick,
        PadButton::DPadUp,
        PadButton::DPadDown,
        PadButton::DPadLeft,
        PadButton::DPadRight,
    ];

    fn bit(self) -> u16 {
        1 << (self as u16)
    }
}

/// A gamepad's sticks and analogue triggers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[allow(missing_docs)]
pub enum PadAxis {
    LeftX,
    LeftY,
    RightX,
    RightY,
    LeftTrigger,
    RightTrigger,
}

/// A set of [`PadButton`]s, written in recordings as a list of names.
#[derive(Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(from = "Vec<PadButton>", into = "Vec<PadButton>")]
pub struct PadButtons(u16);

impl PadButtons {
    /// Whether `button` is in the set.
    #[must_use]
    pub fn contains(self, button: PadButton) -> bool {
        self.0 & button.bit() != 0
    }

    /// Adds `button`.
    pub fn insert(&mut self, button: PadButton) {
        self.0 |= button.bit();
    }

    /// Removes `button`.
    pub fn remove(&mut self, button: PadButton) {
        self.0 &= !button.bit();
    }

    /// Whether the set is empty.
    #[must_use]
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// The set as a bit mask (bit `k` for the button numbered `k`).
    #[must_use]
    pub fn bits(self) -> u16 {
        self.0
    }

    /// The set of a bit mask from [`bits`](Self::bits).
    #[must_use]
    pub fn from_bits(bits: u16) -> Self {
        Self(bits)
    }
}

impl From<Vec<PadButton>> for PadButtons {
    fn from(buttons: Vec<PadButton>) -> Self {
        let mut set = Self::default();
        for button in buttons {
            set.insert(button);
        }
        set
    }
}

impl From<PadButtons> for Vec<PadButton> {
    fn from(set: PadButtons) -> Self {
        PadButton::ALL.into_iter().filter(|b| set.contains(*b)).collect()
    }
}

impl fmt::Debug for PadButtons {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_set().entries(Vec::<PadButton>::from(*self)).finish()
    }
}

/// One gamepad as a fixed step sees it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PadInput {
    /// Buttons down during this step.
    #[serde(default)]
    pub held: PadButtons,
    /// Buttons pressed since the previous step began (seen by one step).
    #[serde(default)]
    pub pressed: PadButtons,
    /// Buttons released since the previous step began (seen by one step).
    #[serde(default)]
    pub released: PadButtons,
    /// Each [`PadAxis`] quantised: `round(v * 32767)` for `v` in `[-1, 1]`.
    #[serde(default)]
    pub axes: [i16; 6],
}

impl PadInput {
    /// Whether `button` is held during this step.
    #[must_use]
    pub fn held(&self, button: PadButton) -> bool {
        self.held.contains(button)
    }

    /// Whether `button` went down since the previous step.
    #[must_use]
    pub fn pressed(&self, button: PadButton) -> bool {
        self.pressed.contains(button)
    }

    /// Whether `button` went up since the previous step.
    #[must_use]
    pub fn released(&self, button: PadButton) -> bool {
        self.released.contains(button)
    }

    /// `axis` in `[-1, 1]` (triggers `[0, 1]`), as quantised.
    #[must_use]
    pub fn axis(&self, axis: PadAxis) -> f32 {
        f32::from(self.axes[axis as usize]) / 32767.0
    }

    /// Whether nothing is held, pressed, released or moved.
    #[must_use]
    pub fn is_idle(&self) -> bool {
        *self == Self::default()
    }
}

/// `value` as stored: clamped to `[-1, 1]`, a NaN as 0.
#[must_use]
pub fn quantise(value: f32) -> i16 {
    if value.is_nan() {
        return 0;
    }
    // In [-32767, 32767]: the cast cannot wrap.
    (value.clamp(-1.0, 1.0) * 32767.0).round() as i16
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axes_quantise_to_the_same_bits_and_read_back_within_half_a_step() {
        for v in [-1.0f32, -0.5, 0.0, 0.25, 0.999, 1.0] {
            let q = quantise(v);
            let back = PadInput {
                axes: [q; 6],
                ..PadInput::default()
            }
            .axis(PadAxis::LeftX);
            assert!((back - v).abs() <= 0.5 / 32767.0 + 1e-7, "{v} -> {q} -> {back}");
        }
        assert_eq!(quantise(7.0), 32767);
        assert_eq!(quantise(f32::NAN), 0);
        assert_eq!(quantise(-1.0), -32767);
    }
}

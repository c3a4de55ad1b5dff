//! Per-tick input, in one place: the keys and mouse buttons a game reads
//! ([`Key`], [`KeySet`]) and gamepads ([`PadInput`]), what one fixed step sees ([`TickInput`]), the
//! queue that hands each window event to the step whose simulated time it
//! arrived in ([`InputQueue`]), and the [`Recording`] of a run's inputs by
//! tick that replays it bit for bit.
//!
//! A step sees only its tick's input, never the frame it ran in, so the
//! same recording gives the same states whatever the display did.

mod keys;
mod pad;
mod queue;
mod recording;
mod tick;

pub use keys::{Key, KeySet};
pub use pad::{MAX_PADS, PadAxis, PadButton, PadButtons, PadInput, quantise};
pub use queue::{InputEvent, InputQueue};
pub use recording::{RecordedControl, Recording, RecordingError};
pub use tick::TickInput;

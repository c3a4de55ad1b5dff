//! What one fixed step sees of the player: [`TickInput`].

use glam::Vec2;
use serde::{Deserialize, Serialize};

use super::keys::{Key, KeySet};
use super::pad::{MAX_PADS, PadButtons, PadInput};

/// What one fixed step sees of the keyboard, the mouse and the gamepads.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TickInput {
    /// Keys down during this step (thrust while held).
    #[serde(default)]
    pub held: KeySet,
    /// Keys pressed since the previous step began: seen by exactly one step,
    /// even if released before it ran (fire, restart).
    #[serde(default)]
    pub pressed: KeySet,
    /// Keys released since the previous step began: seen by exactly one
    /// step, so a tap shorter than a step is both pressed and released in
    /// it (a charged shot let go). Absent from recordings made before it
    /// existed, which replay unchanged.
    #[serde(default, skip_serializing_if = "no_keys")]
    pub released: KeySet,
    /// Where the mouse pointer last was over the window, as `[x, y]` in
    /// world metres on the `z = 0` plane (none before it first moved over
    /// a part of the view that sees that plane; kept when it leaves). A
    /// world point, not a pixel, so a replay at another window size steers
    /// the same way.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pointer: Option<[f32; 2]>,
    /// The first [`MAX_PADS`] gamepads (by the order they connected),
    /// their buttons latched as keys are and their axes quantised. Absent
    /// from recordings where no pad did anything.
    #[serde(default, skip_serializing_if = "no_pads")]
    pub pads: [PadInput; MAX_PADS],
}

impl TickInput {
    /// Whether `key` is held during this step.
    #[must_use]
    pub fn held(&self, key: Key) -> bool {
        self.held.contains(key)
    }

    /// Whether `key` went down since the previous step.
    #[must_use]
    pub fn pressed(&self, key: Key) -> bool {
        self.pressed.contains(key)
    }

    /// Whether `key` went up since the previous step.
    #[must_use]
    pub fn released(&self, key: Key) -> bool {
        self.released.contains(key)
    }

    /// Gamepad `k` (0 for the first connected); an idle pad past
    /// [`MAX_PADS`].
    #[must_use]
    pub fn pad(&self, k: usize) -> PadInput {
        self.pads.get(k).copied().unwrap_or_default()
    }

    /// The pointer as a vector (see [`pointer`](Self::pointer)).
    #[must_use]
    pub fn pointer_at(&self) -> Option<Vec2> {
        self.pointer.map(Vec2::from)
    }

    /// The input of the following step if nothing changes: the same keys
    /// held and pointer, none newly pressed or released.
    #[must_use]
    pub fn carried(&self) -> Self {
        let mut pads = self.pads;
        for pad in &mut pads {
            pad.pressed = PadButtons::default();
            pad.released = PadButtons::default();
        }
        Self {
            pressed: KeySet::EMPTY,
            released: KeySet::EMPTY,
            pads,
            ..*self
        }
    }
}

/// Whether no pad did anything.
fn no_pads(pads: &[PadInput; MAX_PADS]) -> bool {
    pads.iter().all(PadInput::is_idle)
}

/// Whether `keys` is empty (serde's `skip_serializing_if` passes a reference).
fn no_keys(keys: &KeySet) -> bool {
    keys.is_empty()
}

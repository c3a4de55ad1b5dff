//! The keys and mouse buttons a game reads, and sets of them.

use core::fmt;

use serde::{Deserialize, Serialize};

/// The keys a game can read: every letter and digit, the arrows, Space,
/// Enter, Shift, Escape, Tab, Backspace and F1 to F12; mouse buttons are
/// keys too (held and pressed alike).
///
/// The rule for the runner's keys (the one the window and the page
/// follow): the runner's own keys (P pause, Tab and 1-9 integrator, F1
/// panel, F5 restart, F12 screenshot, Escape quit) stay the runner's unless
/// the game claims them in `setup` (`stage.claimed_keys.insert(Key::Escape)`
/// for a pause menu); every other key is the game's; and with Ctrl held,
/// any key is the runner's (Ctrl+Escape quits a game that claimed Escape;
/// Ctrl is never a game key).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[allow(missing_docs)]
pub enum Key {
    Left,
    Right,
    Up,
    Down,
    Space,
    Enter,
    Shift,
    W,
    A,
    S,
    D,
    Q,
    E,
    R,
    F,
    Z,
    X,
    C,
    MouseLeft,
    MouseRight,
    MouseMiddle,
    B,
    G,
    H,
    I,
    J,
    K,
    L,
    M,
    N,
    O,
    P,
    T,
    U,
    V,
    Y,
    Digit0,
    Digit1,
    Digit2,
    Digit3,
    Digit4,
    Digit5,
    Digit6,
    Digit7,
    Digit8,
    Digit9,
    Escape,
    Tab,
    Backspace,
    F1,
    F2,
    F3,
    F4,
    F5,
    F6,
    F7,
    F8,
    F9,
    F10,
    F11,
    F12,
}

impl Key {
    /// Every key, in bit order.
    pub const ALL: [Key; 61] = [
        Key::Left,
        Key::Right,
        Key::Up,
        Key::Down,
        Key::Space,
        Key::Enter,
        Key::Shift,
        Key::W,
        Key::A,
        Key::S,
        Key::D,
        Key::Q,
        Key::E,
        Key::R,
        Key::F,
        Key::Z,
        Key::X,
        Key::C,
        Key::MouseLeft,
        Key::MouseRight,
        Key::MouseMiddle,
        Key::B,
        Key::G,
        Key::H,
        Key::I,
        Key::J,
        Key::K,
        Key::L,
        Key::M,
        Key::N,
        Key::O,
        Key::P,
        Key::T,
        Key::U,
        Key::V,
        Key::Y,
        Key::Digit0,
        Key::Digit1,
        Key::Digit2,
        Key::Digit3,
        Key::Digit4,
        Key::Digit5,
        Key::Digit6,
        Key::Digit7,
        Key::Digit8,
        Key::Digit9,
        Key::Escape,
        Key::Tab,
        Key::Backspace,
        Key::F1,
        Key::F2,
        Key::F3,
        Key::F4,
        Key::F5,
        Key::F6,
        Key::F7,
        Key::F8,
        Key::F9,
        Key::F10,
        Key::F11,
        Key::F12,
    ];

    fn bit(self) -> u64 {
        1 << (self as u64)
    }
}

/// A set of [`Key`]s (a bit mask), written in recordings as a list of names.
#[derive(Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(from = "Vec<Key>", into = "Vec<Key>")]
pub struct KeySet(u64);

impl KeySet {
    /// No keys.
    pub const EMPTY: Self = Self(0);

    /// Whether `key` is in the set.
    #[must_use]
    pub fn contains(self, key: Key) -> bool {
        self.0 & key.bit() != 0
    }

    /// Adds `key`.
    pub fn insert(&mut self, key: Key) {
        self.0 |= key.bit();
    }

    /// Removes `key`.
    pub fn remove(&mut self, key: Key) {
        self.0 &= !key.bit();
    }

    /// Whether the set is empty.
    #[must_use]
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// The set as a bit mask, bit `k` for the key numbered `k` (a fixed-size
    /// form for the network).
    #[must_use]
    pub fn bits(self) -> u64 {
        self.0
    }

    /// The set of a bit mask from [`bits`](Self::bits); bits that name no
    /// key are dropped.
    #[must_use]
    pub fn from_bits(bits: u64) -> Self {
        let known = Key::ALL.iter().fold(0, |mask, key| mask | key.bit());
        Self(bits & known)
    }

    /// The keys in the set, in [`Key::ALL`] order.
    pub fn iter(self) -> impl Iterator<Item = Key> {
        Key::ALL.into_iter().filter(move |k| self.contains(*k))
    }
}

impl From<Vec<Key>> for KeySet {
    fn from(keys: Vec<Key>) -> Self {
        let mut set = Self::EMPTY;
        for key in keys {
            set.insert(key);
        }
        set
    }
}

impl From<KeySet> for Vec<Key> {
    fn from(set: KeySet) -> Self {
        set.iter().collect()
    }
}

impl fmt::Debug for KeySet {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_set().entries(self.iter()).finish()
    }
}

//! The keys and mouse buttons a game reads, and sets of them.

use core::fmt;

use serde::{Deserialize, Serialize};

/// The keys a game can read; mouse buttons are keys too (held and pressed
/// alike). Keys outside this set drive the runner's controls (P pause,
/// Period step, `+`/`-` time scale, Tab and 1-9 integrator, F1 panel, F5
/// restart, F12 screenshot, Escape quit).
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
}

impl Key {
    /// Every key, in bit order.
    pub const ALL: [Key; 21] = [
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
    ];

    fn bit(self) -> u32 {
        1 << (self as u32)
    }
}

/// A set of [`Key`]s (a bit mask), written in recordings as a list of names.
#[derive(Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(from = "Vec<Key>", into = "Vec<Key>")]
pub struct KeySet(u32);

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
    pub fn bits(self) -> u32 {
        self.0
    }

    /// The set of a bit mask from [`bits`](Self::bits); bits that name no
    /// key are dropped.
    #[must_use]
    pub fn from_bits(bits: u32) -> Self {
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

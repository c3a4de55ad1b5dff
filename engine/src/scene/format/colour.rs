//! A colour of the scene file: four numbers from 0 to 1, sRGB.

use serde::{Deserialize, Serialize};

use super::numbers::Unit;

/// A colour `(r, g, b, a)`, each from 0 to 1, sRGB.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ColourSpec(pub Unit, pub Unit, pub Unit, pub Unit);

impl ColourSpec {
    /// As 8-bit sRGB.
    #[must_use]
    pub fn to_rgba8(self) -> [u8; 4] {
        [self.0, self.1, self.2, self.3].map(|c| (c.0 * 255.0).round() as u8)
    }
}

pub(super) fn white() -> ColourSpec {
    ColourSpec(Unit(1.0), Unit(1.0), Unit(1.0), Unit(1.0))
}

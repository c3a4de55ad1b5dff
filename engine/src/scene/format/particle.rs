//! One particle of the scene: where, how fast, how heavy, how large, what
//! colour and for how long.

use serde::{Deserialize, Serialize};

use super::colour::{ColourSpec, white};
use super::numbers::{NonNegative, Positive};
use super::vectors::{Vector, origin};

/// A particle.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParticleSpec {
    /// m.
    pub position: Vector,
    /// m/s (default: zero).
    #[serde(default = "origin")]
    pub velocity: Vector,
    /// kg (default: 1).
    #[serde(default = "one")]
    pub mass: Positive,
    /// Infinite mass (default: false).
    #[serde(default)]
    pub immovable: bool,
    /// m (default: 0.05).
    #[serde(default = "small_radius")]
    pub radius: NonNegative,
    /// Colour (default: white).
    #[serde(default = "white")]
    pub colour: ColourSpec,
    /// Seconds to live (default: forever).
    #[serde(default)]
    pub lifetime: Option<Positive>,
}

pub(super) fn one() -> Positive {
    Positive(1.0)
}
pub(super) fn small_radius() -> NonNegative {
    NonNegative(0.05)
}

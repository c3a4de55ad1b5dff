//! A block of identical particles on a lattice, and the limit on how many
//! one lattice may hold, checked while read.

use serde::de::{self, Deserializer};
use serde::{Deserialize, Serialize};

use super::colour::{ColourSpec, white};
use super::numbers::{NonNegative, Positive};
use super::particle::{one, small_radius};
use super::vectors::{Vector, origin};

/// A block of identical particles on a lattice: `count` along each axis,
/// `spacing` apart, starting at `origin`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LatticeSpec {
    /// First particle's position.
    pub origin: Vector,
    /// Particles along x, y, z (at most [`MAX_LATTICE_PARTICLES`] in all).
    pub count: LatticeCount,
    /// Distance between neighbours, m.
    pub spacing: Positive,
    /// Every particle's velocity (default: zero).
    #[serde(default = "origin")]
    pub velocity: Vector,
    /// kg (default: 1).
    #[serde(default = "one")]
    pub mass: Positive,
    /// m (default: 0.05).
    #[serde(default = "small_radius")]
    pub radius: NonNegative,
    /// Colour (default: white).
    #[serde(default = "white")]
    pub colour: ColourSpec,
}

/// The most particles one lattice may hold: ten million (about a gigabyte
/// of world). A larger request is an error naming this limit, not an
/// allocation that aborts the process; split the lattice to go past it.
pub const MAX_LATTICE_PARTICLES: u64 = 10_000_000;

/// A lattice's particle counts along x, y and z, whose product is checked
/// against [`MAX_LATTICE_PARTICLES`] while read.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct LatticeCount(pub u32, pub u32, pub u32);

impl LatticeCount {
    /// Particles in the lattice: in u128, since three u32 can pass u64
    /// (494967295 x 10 x 4294967295 did).
    #[must_use]
    pub fn total(self) -> u128 {
        u128::from(self.0) * u128::from(self.1) * u128::from(self.2)
    }
}

impl<'de> Deserialize<'de> for LatticeCount {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let (x, y, z) = <(u32, u32, u32)>::deserialize(d)?;
        let total = Self(x, y, z).total();
        if total > u128::from(MAX_LATTICE_PARTICLES) {
            return Err(de::Error::custom(format_args!(
                "expected at most {MAX_LATTICE_PARTICLES} particles in a lattice (MAX_LATTICE_PARTICLES), \
                 got {x} x {y} x {z} = {total}; split it into several lattices"
            )));
        }
        Ok(Self(x, y, z))
    }
}

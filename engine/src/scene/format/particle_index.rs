//! A spring end's particle: an index into the scene's `particles` list,
//! checked while read against the number of particles the scene lists
//! (which `Scene::parse` sets in [`PARTICLE_COUNT`] for its second pass).

use core::cell::Cell;

use serde::de::{self, Deserializer};
use serde::{Deserialize, Serialize};

thread_local! {
    /// Number of particles in the scene being read, for checking spring ends
    /// (set by the second pass of `Scene::parse`; `usize::MAX` = not checked).
    pub(crate) static PARTICLE_COUNT: Cell<usize> = const { Cell::new(usize::MAX) };
}

/// The index of a particle in the scene's `particles` list.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ParticleIndex(pub usize);

impl<'de> Deserialize<'de> for ParticleIndex {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let index = usize::deserialize(d)?;
        let count = PARTICLE_COUNT.with(Cell::get);
        if index >= count {
            return Err(de::Error::custom(format_args!(
                "particle index {index} is out of range: the scene lists {count} particles"
            )));
        }
        Ok(Self(index))
    }
}

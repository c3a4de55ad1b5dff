//! Checks across the fields of one list item, run once the item is read,
//! so that the error carries the item's path and position.

use serde::Deserialize;
use serde::de::{self, Deserializer};

/// Checks across the fields of one list item (a box's two corners, a rigid
/// body's mass and extents), run once the item is read: the error then
/// carries the item's path (`colliders[2]`) and the position just past it,
/// and names the fields inside.
pub(crate) trait CheckItem {
    /// `Err` says which fields disagree and what is required.
    fn check(&self) -> Result<(), String>;
}

struct Checked<T>(T);

impl<'de, T: Deserialize<'de> + CheckItem> Deserialize<'de> for Checked<T> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let item = T::deserialize(d)?;
        item.check().map_err(de::Error::custom)?;
        Ok(Self(item))
    }
}

pub(super) fn checked_list<'de, D, T>(d: D) -> Result<Vec<T>, D::Error>
where
    D: Deserializer<'de>,
    T: Deserialize<'de> + CheckItem,
{
    let items = Vec::<Checked<T>>::deserialize(d)?;
    Ok(items.into_iter().map(|item| item.0).collect())
}

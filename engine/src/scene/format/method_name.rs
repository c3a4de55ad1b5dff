//! The scene's integrator: a name the registry of
//! `tickwork-integrators` knows, checked while read.

use serde::de::{self, Deserializer};
use serde::{Deserialize, Serialize};

/// An integrator name that the registry knows.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MethodName(pub String);

impl<'de> Deserialize<'de> for MethodName {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let name = String::deserialize(d)?;
        match tickwork_integrators::find(&name) {
            Ok(info) => Ok(Self(info.name.to_owned())),
            Err(unknown) => Err(de::Error::custom(unknown)),
        }
    }
}

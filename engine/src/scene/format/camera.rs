//! The scene's camera hint: how a renderer should frame the scene (2D or
//! 3D, where it looks, how much it shows).

use serde::{Deserialize, Serialize};

use super::numbers::{Finite, Positive};
use super::vectors::{Vector, origin};

/// Projection hint for renderers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Projection {
    /// Orthographic, looking down -z (default).
    #[default]
    TwoD,
    /// Perspective orbit camera.
    ThreeD,
}

/// Where a renderer should look.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraHint {
    /// 2D or 3D (default: `TwoD`).
    #[serde(default)]
    pub projection: Projection,
    /// The point looked at (default: origin).
    #[serde(default = "origin")]
    pub target: Vector,
    /// Visible height in metres (2D) or distance from the target (3D) (default: `10.0`).
    #[serde(default = "ten")]
    pub extent: Positive,
    /// Orbit angles in degrees, yaw and pitch (3D) (default: `(30, 20)`).
    #[serde(default = "default_angles")]
    pub angles: (Finite, Finite),
}

impl Default for CameraHint {
    fn default() -> Self {
        Self {
            projection: Projection::TwoD,
            target: origin(),
            extent: ten(),
            angles: default_angles(),
        }
    }
}

fn ten() -> Positive {
    Positive(10.0)
}
fn default_angles() -> (Finite, Finite) {
    (Finite(30.0), Finite(20.0))
}

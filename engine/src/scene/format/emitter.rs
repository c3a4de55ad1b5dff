//! An emitter of the scene: where, which way and how fast particles appear,
//! and what they are like; turned into the engine's emitter and checked as
//! the engine would check it, once read, so an error has a position.

use serde::{Deserialize, Serialize};

use super::check_item::CheckItem;
use super::colour::ColourSpec;
use super::numbers::{NonNegative, Positive, Unit};
use super::vectors::{Direction, Vector};

/// An emitter.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EmitterSpec {
    /// Where particles appear.
    pub position: Vector,
    /// Launch direction, of non-zero, finite length (default: +y).
    #[serde(default = "up")]
    pub direction: Direction,
    /// Cone half-angle, degrees (default: 15).
    #[serde(default = "fifteen")]
    pub spread_degrees: NonNegative,
    /// m/s.
    pub speed: NonNegative,
    /// Relative speed variation, 0 to 1 (default: 0.2).
    #[serde(default = "fifth")]
    pub speed_jitter: Unit,
    /// Particles per second.
    pub rate: NonNegative,
    /// Seconds each particle lives.
    pub lifetime: Positive,
    /// Colour (default: orange).
    #[serde(default = "orange")]
    pub colour: ColourSpec,
    /// m (default: 0.03).
    #[serde(default = "tiny_radius")]
    pub radius: NonNegative,
    /// kg (default: 0.01).
    #[serde(default = "centigram")]
    pub mass: Positive,
}

fn up() -> Direction {
    Direction([0.0, 1.0, 0.0])
}
fn fifteen() -> NonNegative {
    NonNegative(15.0)
}
fn fifth() -> Unit {
    Unit(0.2)
}
fn orange() -> ColourSpec {
    ColourSpec(Unit(1.0), Unit(0.63), Unit(0.24), Unit(1.0))
}
fn tiny_radius() -> NonNegative {
    NonNegative(0.03)
}
fn centigram() -> Positive {
    Positive(0.01)
}

impl EmitterSpec {
    /// The engine's emitter with these settings.
    #[must_use]
    pub fn emitter(&self) -> crate::emitter::Emitter {
        crate::emitter::Emitter {
            position: self.position.into(),
            direction: self.direction.into(),
            spread: self.spread_degrees.0.to_radians(),
            speed: self.speed.0,
            speed_jitter: self.speed_jitter.0,
            rate: self.rate.0,
            lifetime: self.lifetime.0,
            colour: self.colour.to_rgba8(),
            radius: self.radius.0,
            mass: self.mass.0,
            owed: 0.0,
        }
    }
}

impl CheckItem for EmitterSpec {
    fn check(&self) -> Result<(), String> {
        // The same check as `World::add_emitter` (a jittered speed past f32,
        // a spread past 180 degrees), here so that it has a position.
        self.emitter().validate().map_err(|e| e.to_string())
    }
}

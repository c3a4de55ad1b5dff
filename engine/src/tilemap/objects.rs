//! A map's objects in metres: spawn points, areas (coins, hazards, the
//! goal) and their custom properties, and a sensor for an area.

use std::collections::BTreeMap;

use glam::{Vec2, Vec3};

use crate::sensor::Sensor;

/// A custom property of an object, as Tiled types it.
#[derive(Clone, Debug, PartialEq)]
pub enum MapValue {
    /// `bool`.
    Bool(bool),
    /// `int`.
    Int(i32),
    /// `float`.
    Float(f32),
    /// `string` and `file` (a file's path as written, relative to the
    /// map), and `color` as `#aarrggbb`.
    Text(String),
    /// `object`: the id of the object it names (0 if none).
    Object(u32),
}

/// An object's outline, in metres (the world's y up).
#[derive(Clone, Debug, PartialEq)]
pub enum MapShape {
    /// A point (a spawn point): [`MapObject::position`].
    Point,
    /// A rectangle from `min` to `max`.
    Rect {
        /// Its bottom-left corner.
        min: Vec2,
        /// Its top-right corner.
        max: Vec2,
    },
    /// An ellipse inside the rectangle from `min` to `max`.
    Ellipse {
        /// Its box's bottom-left corner.
        min: Vec2,
        /// Its box's top-right corner.
        max: Vec2,
    },
    /// A path of points (Tiled's polyline), world positions.
    Polyline(Vec<Vec2>),
    /// A closed outline (Tiled's polygon), world positions.
    Polygon(Vec<Vec2>),
}

/// One object of an object layer, in metres.
#[derive(Clone, Debug, PartialEq)]
pub struct MapObject {
    /// Tiled's id, unique in the map.
    pub id: u32,
    /// Its name (several may share one: `coin`).
    pub name: String,
    /// Its class (Tiled's "Class", formerly "Type"): `spawn`, `hazard`.
    pub class: String,
    /// Where Tiled places it, in the world: a point's position, a
    /// rectangle's or ellipse's centre, a path's first point.
    pub position: Vec2,
    /// Its outline.
    pub shape: MapShape,
    /// Its custom properties by name.
    pub properties: BTreeMap<String, MapValue>,
}

impl MapObject {
    /// Its area's corners (bottom-left, top-right) for a rectangle or an
    /// ellipse; `None` for a point or a path.
    #[must_use]
    pub fn area(&self) -> Option<(Vec2, Vec2)> {
        match self.shape {
            MapShape::Rect { min, max } | MapShape::Ellipse { min, max } => Some((min, max)),
            _ => None,
        }
    }

    /// A sensor over its area, `depth` metres deep on z about 0: a box for
    /// a rectangle, a ball of the smaller half-side for an ellipse (add it
    /// with [`World::add_sensor`](crate::World::add_sensor)).
    ///
    /// # Errors
    /// A message naming the object when it has no area (a point or a path).
    pub fn sensor(&self, depth: f32) -> Result<Sensor, String> {
        match self.shape {
            MapShape::Rect { min, max } => Ok(Sensor::cuboid(min.extend(-depth / 2.0), max.extend(depth / 2.0))),
            MapShape::Ellipse { min, max } => {
                let radius = ((max - min) / 2.0).min_element();
                Ok(Sensor::sphere(((min + max) / 2.0).extend(0.0), radius))
            }
            _ => Err(format!(
                "object \"{}\" (class \"{}\", id {}) is a point or a path: a sensor needs a rectangle or an \
                 ellipse",
                self.name, self.class, self.id
            )),
        }
    }

    /// The property `name` as a number (an `int` or a `float`).
    #[must_use]
    pub fn number(&self, name: &str) -> Option<f32> {
        match self.properties.get(name)? {
            MapValue::Float(v) => Some(*v),
            MapValue::Int(v) => Some(*v as f32),
            _ => None,
        }
    }

    /// Its position on the z = 0 plane, where particles move.
    #[must_use]
    pub fn position3(&self) -> Vec3 {
        self.position.extend(0.0)
    }
}

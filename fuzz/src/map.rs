//! Map cases: the shipped Tiled level mutated, read as a map beside its
//! tileset, and, when it reads, made into a world (every tile layer's
//! merged boxes, every area object's sensor, a character dropped at the
//! first point object) that steps a few times, with every layer drawn. A
//! refusal must name the file.

use std::path::Path;

use tickwork_engine::app::Draw;
use tickwork_engine::clock::FixedStep;
use tickwork_engine::glam::Vec2;
use tickwork_engine::tilemap::{MapOptions, MapShape, TileMap};
use tickwork_engine::{Character, CharacterConfig, Material, World};

use crate::case::{Outcome, STEPS, Stage};

/// Where a case's map is read from, beside the shipped level (its tileset
/// is found there).
pub const MAP_PATH: &str = "assets/maps/fuzz-case.tmx";

/// The cells a case's map may have: a mutated size costs an error, not
/// memory.
pub const MAX_TILES: u64 = 1 << 16;

/// Runs one map case. `Err` is a defect (a refusal that does not name the
/// file); panics propagate.
///
/// # Errors
/// The defect found.
pub fn run_map_case(text: &str) -> Result<Outcome, String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let options = MapOptions {
        max_tiles: MAX_TILES,
        ..MapOptions::default()
    };
    let map = match TileMap::parse(text.as_bytes(), root.join(MAP_PATH), options) {
        Ok(map) => map,
        Err(error) => {
            let message = error.to_string();
            if !message.contains("fuzz-case.tmx") && !message.contains("tiles") {
                return Err(format!("a map error that names no file: {message}"));
            }
            return Ok(Outcome::Refused(Stage::Parse, message));
        }
    };
    let mut world = World::default();
    let mut draw = Draw::default();
    let names: Vec<String> = map.tile_layer_names().map(str::to_owned).collect();
    for name in &names {
        let layer = map
            .tile_layer(name)
            .map_err(|e| format!("a listed layer is missing: {e}"))?;
        if let Err(error) = map.add_colliders(&mut world, layer, Material::default()) {
            return Ok(Outcome::Refused(Stage::Build, error.to_string()));
        }
        draw.tiles(&map, layer);
    }
    let mut spawn = None;
    let layers: Vec<String> = map.object_layer_names().map(str::to_owned).collect();
    for name in &layers {
        let objects = map
            .objects(name)
            .map_err(|e| format!("a listed layer is missing: {e}"))?;
        for object in objects {
            match object.sensor(1.0) {
                Ok(sensor) => {
                    if let Err(error) = world.add_sensor(sensor) {
                        return Ok(Outcome::Refused(Stage::Build, error.to_string()));
                    }
                }
                Err(_) if object.shape == MapShape::Point => spawn = spawn.or(Some(object.position)),
                Err(_) => {}
            }
        }
    }
    let start = spawn.unwrap_or(Vec2::new(1.0, 8.0));
    let hero = match world.add_character(Character::new(start, CharacterConfig::default())) {
        Ok(hero) => hero,
        Err(error) => return Ok(Outcome::Refused(Stage::Build, error.to_string())),
    };
    for tick in 0..STEPS {
        if let Ok(character) = world.character_mut(hero) {
            character.run(5.0);
        }
        let step = FixedStep {
            tick,
            time: tick as f64 / 60.0,
            dt: 1.0 / 60.0,
        };
        if let Err(error) = world.step(step) {
            return Ok(Outcome::Refused(Stage::Step, error.to_string()));
        }
    }
    Ok(Outcome::Stepped)
}

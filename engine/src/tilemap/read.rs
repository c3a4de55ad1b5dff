//! Reading a `.tmx` map through the `tiled` crate into a [`TileMap`]: the
//! one place that crate is named.
//!
//! Before the crate sees a map, a pass over its XML checks what the crate
//! would trust: each tile layer's size against [`MapOptions::max_tiles`],
//! its data holding exactly width x height cells (the crate indexes its
//! cells unchecked), no compressed data (it would be inflated without a
//! bound before any size is known: Tiled's default, CSV, is what it takes)
//! and at most [`MAX_NESTING`] levels of elements. It reads the XML as the
//! crate does: elements and attributes by local name, the last of a
//! repeated attribute, a data's first piece of text (unescaped) or CDATA.

use std::io::Cursor;
use std::path::{Component, Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use glam::Vec2;

use super::objects::{MapObject, MapShape, MapValue};
use super::{Cell, Layer, MapError, MapOptions, TileMap, Tileset};
use crate::render::Texture;

/// The deepest nesting of XML elements a map may have (groups of groups
/// of layers): the crate reads them by recursion.
pub const MAX_NESTING: usize = 64;

/// Each map read gets its own number: a [`TileLayerId`](super::TileLayerId)
/// of another map is refused.
static NEXT_MAP: AtomicU64 = AtomicU64::new(1);

/// Serves the map's own text for its path and every other file (a
/// tileset, a template) as an asset, its path made plain first (`a/../b`
/// is `b`, as a page's list of assets names it).
struct Assets {
    main: PathBuf,
    text: Vec<u8>,
}

impl tiled::ResourceReader for Assets {
    type Resource = Cursor<Vec<u8>>;
    type Error = std::io::Error;

    fn read_from(&mut self, path: &Path) -> Result<Self::Resource, Self::Error> {
        let path = plain(path);
        if path == self.main {
            return Ok(Cursor::new(self.text.clone()));
        }
        crate::platform::read_asset(&path).map(Cursor::new)
    }
}

/// `path` without `.` and with each `..` taking off the folder before it.
pub(crate) fn plain(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for part in path.components() {
        match part {
            Component::CurDir => {}
            Component::ParentDir if matches!(out.components().next_back(), Some(Component::Normal(_))) => {
                out.pop();
            }
            other => out.push(other.as_os_str()),
        }
    }
    out
}

/// Reads the map at `path` as an asset.
pub(super) fn load(path: &Path, options: MapOptions) -> Result<TileMap, MapError> {
    let text = crate::platform::read_asset(&plain(path)).map_err(|error| MapError::Read {
        path: path.to_path_buf(),
        message: error.to_string(),
    })?;
    parse(&text, path, options)
}

/// Reads a map from `text` as if it were the file at `path`.
pub(super) fn parse(text: &[u8], path: &Path, options: MapOptions) -> Result<TileMap, MapError> {
    let invalid = |what: String| MapError::Invalid {
        path: path.to_path_buf(),
        what,
    };
    if !(options.tile_metres.is_finite() && options.tile_metres > 0.0) {
        return Err(invalid(format!(
            "MapOptions::tile_metres is {}: it must be finite and above 0",
            options.tile_metres
        )));
    }
    if !options.origin.is_finite() {
        return Err(invalid(format!(
            "MapOptions::origin is {}: it must be finite",
            options.origin
        )));
    }
    if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("tmj") || e.eq_ignore_ascii_case("json"))
    {
        return Err(MapError::Unsupported {
            path: path.to_path_buf(),
            what: "a map in Tiled's JSON format: the tiled crate reads the XML format, so save it as a .tmx \
                   (File > Save As, \"Tiled map files (*.tmx)\")"
                .to_owned(),
        });
    }
    check_layers(text, path, options.max_tiles)?;
    let main = plain(path);
    let mut loader = tiled::Loader::with_reader(Assets {
        main: main.clone(),
        text: text.to_vec(),
    });
    let map = loader.load_tmx_map(&main).map_err(|error| MapError::Read {
        path: path.to_path_buf(),
        message: error.to_string(),
    })?;
    convert(&map, path, options)
}

/// The pass over the XML before the crate's (see the module's docs).
fn check_layers(text: &[u8], path: &Path, max_tiles: u64) -> Result<(), MapError> {
    use quick_xml::events::Event;
    let error = |what: String, at: u64| MapError::Invalid {
        path: path.to_path_buf(),
        what: format!("{what} (byte {at})"),
    };
    let mut reader = quick_xml::Reader::from_reader(text);
    let mut buffer = Vec::new();
    let mut depth = 0usize;
    // The tile layer being read: its name and cells, and its data's count.
    let mut layer: Option<(String, u128)> = None;
    // Inside a `<data>`: whether CSV, and its cells once its first piece of
    // text was read (the crate reads that piece only).
    let mut in_data: Option<(bool, Option<u128>)> = None;
    loop {
        let at = reader.buffer_position() as u64;
        let event = reader
            .read_event_into(&mut buffer)
            .map_err(|e| error(format!("not well-formed XML: {e}"), at))?;
        match event {
            Event::Start(ref element) | Event::Empty(ref element) => {
                let empty = matches!(event, Event::Empty(_));
                if !empty {
                    depth += 1;
                    if depth > MAX_NESTING {
                        return Err(error(
                            format!("elements nest deeper than {MAX_NESTING} levels (tilemap::MAX_NESTING)"),
                            at,
                        ));
                    }
                }
                // As the crate reads them: by local name (a namespace
                // prefix aside), the last of a repeated attribute.
                let attribute = |name: &[u8]| -> Option<String> {
                    element
                        .attributes()
                        .flatten()
                        .filter(|a| a.key.local_name().as_ref() == name)
                        .last()
                        .map(|a| String::from_utf8_lossy(&a.value).into_owned())
                };
                match element.local_name().as_ref() {
                    b"map" | b"layer" => {
                        let kind = if element.local_name().as_ref() == b"map" {
                            "the map"
                        } else {
                            "a layer"
                        };
                        let name = attribute(b"name").unwrap_or_default();
                        let size = |key: &[u8]| -> Result<u128, MapError> {
                            let value = attribute(key).unwrap_or_else(|| "0".to_owned());
                            value.trim().parse::<u32>().map(u128::from).map_err(|_| {
                                error(
                                    format!(
                                        "{kind} \"{name}\" has {} \"{value}\": a whole number of cells from 0 to {} \
                                         is expected",
                                        String::from_utf8_lossy(key),
                                        u32::MAX
                                    ),
                                    at,
                                )
                            })
                        };
                        let cells = size(b"width")? * size(b"height")?;
                        if cells > u128::from(max_tiles) {
                            return Err(MapError::TooLarge {
                                path: path.to_path_buf(),
                                tiles: cells,
                                limit: max_tiles,
                            });
                        }
                        if kind == "a layer" {
                            layer = Some((name, cells));
                        }
                    }
                    b"data" => {
                        if let Some(compression) = attribute(b"compression") {
                            return Err(MapError::Unsupported {
                                path: path.to_path_buf(),
                                what: format!(
                                    "layer \"{}\" keeps its cells compressed ({compression}): save the map with \
                                     the tile layer format CSV (Map > Map Properties), Tiled's default",
                                    layer.as_ref().map_or("", |(n, _)| n.as_str())
                                ),
                            });
                        }
                        let csv = match attribute(b"encoding").as_deref() {
                            Some("csv") => true,
                            Some("base64") => false,
                            other => {
                                return Err(MapError::Unsupported {
                                    path: path.to_path_buf(),
                                    what: format!(
                                        "layer \"{}\" keeps its cells as {}: save the map with the tile layer \
                                         format CSV (Map > Map Properties)",
                                        layer.as_ref().map_or("", |(n, _)| n.as_str()),
                                        other.map_or("XML elements".to_owned(), |o| format!("\"{o}\""))
                                    ),
                                });
                            }
                        };
                        if empty {
                            check_count(&layer, 0, path)?;
                        } else {
                            in_data = Some((csv, None));
                        }
                    }
                    b"chunk" => {
                        return Err(MapError::Unsupported {
                            path: path.to_path_buf(),
                            what: "an infinite map (its layers are in chunks): turn Infinite off in Map > Map \
                                   Properties"
                                .to_owned(),
                        });
                    }
                    _ => {}
                }
            }
            Event::Text(ref content) => {
                if let Some((csv, count @ None)) = &mut in_data {
                    let text = content
                        .unescape()
                        .map_err(|e| error(format!("not well-formed XML: {e}"), at))?;
                    *count = Some(cells_in(&text, *csv));
                }
            }
            Event::CData(ref content) => {
                if let Some((csv, count @ None)) = &mut in_data {
                    *count = Some(cells_in(&String::from_utf8_lossy(content.as_ref()), *csv));
                }
            }
            Event::End(ref element) => {
                depth = depth.saturating_sub(1);
                if element.local_name().as_ref() == b"data"
                    && let Some((_, count)) = in_data.take()
                {
                    check_count(&layer, count.unwrap_or(0), path)?;
                }
            }
            Event::Eof => return Ok(()),
            _ => {}
        }
        buffer.clear();
    }
}

/// The cells the crate reads from a layer's data `text`: CSV, one a
/// comma-separated value; base64, four bytes a cell (`=` padding less).
fn cells_in(text: &str, csv: bool) -> u128 {
    if csv {
        return text.split(',').count() as u128;
    }
    let letters: Vec<u8> = text.bytes().filter(|b| !b.is_ascii_whitespace()).collect();
    let padding = letters.iter().rev().take_while(|&&b| b == b'=').count().min(2);
    let bytes = (letters.len() / 4 * 3).saturating_sub(padding);
    (bytes / 4) as u128
}

/// A layer's data holds exactly its width x height cells.
fn check_count(layer: &Option<(String, u128)>, count: u128, path: &Path) -> Result<(), MapError> {
    match layer {
        Some((name, cells)) if *cells != count => Err(MapError::Invalid {
            path: path.to_path_buf(),
            what: format!("layer \"{name}\" has {count} cells of data where its size says {cells}"),
        }),
        _ => Ok(()),
    }
}

/// The crate's map as the engine's (see [`TileMap`]).
fn convert(map: &tiled::Map, path: &Path, options: MapOptions) -> Result<TileMap, MapError> {
    let unsupported = |what: String| MapError::Unsupported {
        path: path.to_path_buf(),
        what,
    };
    let invalid = |what: String| MapError::Invalid {
        path: path.to_path_buf(),
        what,
    };
    if map.orientation != tiled::Orientation::Orthogonal {
        return Err(unsupported(format!(
            "a map of {} orientation: Tickwork takes orthogonal maps",
            map.orientation
        )));
    }
    if map.infinite() {
        return Err(unsupported(
            "an infinite map: turn Infinite off in Map > Map Properties".to_owned(),
        ));
    }
    if map.tile_width == 0 || map.tile_height == 0 {
        return Err(invalid(format!(
            "its tiles are {} x {} pixels: both must be at least 1",
            map.tile_width, map.tile_height
        )));
    }
    let mut tilesets = Vec::new();
    for set in map.tilesets() {
        let Some(image) = &set.image else {
            return Err(unsupported(format!(
                "tileset \"{}\" is a collection of separate images: Tickwork draws tilesets made from one image",
                set.name
            )));
        };
        let texture = Texture::load(plain(&image.source)).map_err(MapError::Texture)?;
        if set.tile_width == 0 || set.tile_height == 0 || set.columns == 0 {
            return Err(invalid(format!(
                "tileset \"{}\" has tiles of {} x {} pixels in {} columns: each must be at least 1",
                set.name, set.tile_width, set.tile_height, set.columns
            )));
        }
        tilesets.push(Tileset {
            texture,
            tile: [set.tile_width, set.tile_height],
            columns: set.columns,
            margin: set.margin,
            spacing: set.spacing,
            count: set.tilecount,
        });
    }
    let metres_per_pixel = options.tile_metres / map.tile_width as f32;
    let height_px = map.height as f32 * map.tile_height as f32;
    let mut layers = Vec::new();
    let mut object_layers = Vec::new();
    // Each layer with what its groups give it: their offsets added, their
    // opacities multiplied, hidden if any is.
    let top = (Vec2::ZERO, 1.0f32, true);
    let mut pending: Vec<(tiled::Layer<'_>, (Vec2, f32, bool))> = map.layers().map(|l| (l, top)).collect();
    pending.reverse();
    while let Some((layer, (group_offset, group_opacity, group_visible))) = pending.pop() {
        let offset = group_offset + Vec2::new(layer.offset_x, layer.offset_y);
        let opacity = group_opacity * layer.opacity;
        let visible = group_visible && layer.visible;
        if !offset.is_finite() || !opacity.is_finite() {
            return Err(invalid(format!(
                "layer \"{}\" has offset {offset} and opacity {opacity} (with its groups'): they must be finite",
                layer.name
            )));
        }
        match layer.layer_type() {
            tiled::LayerType::Tiles(tiles) => {
                let tiled::TileLayer::Finite(finite) = tiles else {
                    return Err(unsupported(format!(
                        "layer \"{}\" is infinite: turn Infinite off in Map > Map Properties",
                        layer.name
                    )));
                };
                if finite.width() != map.width || finite.height() != map.height {
                    return Err(invalid(format!(
                        "layer \"{}\" is {} x {} cells in a map of {} x {}: a layer covers the map",
                        layer.name,
                        finite.width(),
                        finite.height(),
                        map.width,
                        map.height
                    )));
                }
                let mut cells = Vec::with_capacity((map.width as usize).saturating_mul(map.height as usize));
                for y in 0..map.height {
                    for x in 0..map.width {
                        let data = i32::try_from(x)
                            .ok()
                            .zip(i32::try_from(y).ok())
                            .and_then(|(x, y)| finite.get_tile_data(x, y));
                        cells.push(match data {
                            None => None,
                            Some(data) => Some(cell(data, &tilesets, &layer.name, [x, y]).map_err(&invalid)?),
                        });
                    }
                }
                let solid = matches!(
                    layer.properties.get("solid"),
                    Some(tiled::PropertyValue::BoolValue(true))
                );
                layers.push(Layer {
                    name: layer.name.clone(),
                    visible,
                    solid,
                    cells,
                    offset,
                    opacity,
                });
            }
            tiled::LayerType::Objects(group) => {
                let mut objects = Vec::new();
                for object in group.objects() {
                    let place = (metres_per_pixel, height_px, options.origin, offset);
                    objects.push(map_object(&object, place).map_err(&invalid)?);
                }
                object_layers.push((layer.name.clone(), objects));
            }
            tiled::LayerType::Group(group) => {
                // Its layers next, in their order.
                let inner: Vec<tiled::Layer<'_>> = group.layers().collect();
                pending.extend(inner.into_iter().rev().map(|l| (l, (offset, opacity, visible))));
            }
            tiled::LayerType::Image(_) => {}
        }
    }
    Ok(TileMap {
        id: NEXT_MAP.fetch_add(1, Ordering::Relaxed),
        path: path.to_path_buf(),
        options,
        size: [map.width, map.height],
        cell: [map.tile_width, map.tile_height],
        layers,
        tilesets,
        object_layers,
    })
}

/// A cell's tile, its region checked against its tileset's image.
fn cell(data: &tiled::LayerTileData, tilesets: &[Tileset], layer: &str, [x, y]: [u32; 2]) -> Result<Cell, String> {
    let set = data.tileset_index();
    let tile = data.id();
    let Some(tileset) = tilesets.get(set) else {
        return Err(format!(
            "layer \"{layer}\", cell ({x}, {y}): tileset {set} does not exist"
        ));
    };
    let [rx, ry, rw, rh] = tileset.region(tile).unwrap_or([u32::MAX, u32::MAX, 0, 0]);
    let (w, h) = (tileset.texture.width(), tileset.texture.height());
    let fits = tile < tileset.count.max(1)
        && rx.checked_add(rw).is_some_and(|r| r <= w)
        && ry.checked_add(rh).is_some_and(|b| b <= h);
    if !fits {
        return Err(format!(
            "layer \"{layer}\", cell ({x}, {y}): tile {tile} of a tileset of {} tiles lies at [{rx}, {ry}, {rw}, \
             {rh}], outside its {w} x {h} image",
            tileset.count
        ));
    }
    Ok(Cell {
        tileset: set,
        tile,
        flips: [data.flip_h, data.flip_v, data.flip_d],
    })
}

/// An object in metres (y up), placed by `(metres a pixel, the map's
/// height in pixels, the map's origin, its layer's offset in pixels)`.
fn map_object(object: &tiled::Object<'_>, place: (f32, f32, Vec2, Vec2)) -> Result<MapObject, String> {
    let (scale, height_px, origin, offset) = place;
    let name = |problem: String| format!("object \"{}\" (id {}): {problem}", object.name, object.id());
    let world = |x: f32, y: f32| origin + Vec2::new(x + offset.x, height_px - (y + offset.y)) * scale;
    if !(object.x.is_finite() && object.y.is_finite() && object.rotation.is_finite()) {
        return Err(name(format!(
            "its x {}, y {} and rotation {} must be finite",
            object.x, object.y, object.rotation
        )));
    }
    // A tile object stands on its (x, y); a rectangle hangs from it.
    let standing = object.tile_data().is_some();
    let area = |width: f32, height: f32| -> Result<(Vec2, Vec2), String> {
        if !(width.is_finite() && height.is_finite() && width >= 0.0 && height >= 0.0) {
            return Err(name(format!(
                "its size {width} x {height} must be finite and at least 0"
            )));
        }
        if object.rotation != 0.0 {
            return Err(name(format!(
                "it is turned {} degrees: Tickwork's areas are upright (set its rotation to 0)",
                object.rotation
            )));
        }
        let top = if standing { object.y - height } else { object.y };
        Ok((world(object.x, top + height), world(object.x + width, top)))
    };
    let points = |points: &[(f32, f32)]| -> Result<Vec<Vec2>, String> {
        if object.rotation != 0.0 {
            return Err(name(format!(
                "it is turned {} degrees: Tickwork reads paths as drawn unturned (set its rotation to 0)",
                object.rotation
            )));
        }
        points
            .iter()
            .map(|&(x, y)| {
                let p = world(object.x + x, object.y + y);
                if p.is_finite() {
                    Ok(p)
                } else {
                    Err(name(format!("its point ({x}, {y}) is not finite")))
                }
            })
            .collect()
    };
    let (position, shape) = match &object.shape {
        tiled::ObjectShape::Point(..) => (world(object.x, object.y), MapShape::Point),
        tiled::ObjectShape::Rect { width, height }
        | tiled::ObjectShape::Capsule { width, height }
        | tiled::ObjectShape::Text { width, height, .. } => {
            let (min, max) = area(*width, *height)?;
            ((min + max) / 2.0, MapShape::Rect { min, max })
        }
        tiled::ObjectShape::Ellipse { width, height } => {
            let (min, max) = area(*width, *height)?;
            ((min + max) / 2.0, MapShape::Ellipse { min, max })
        }
        tiled::ObjectShape::Polyline { points: p } => (world(object.x, object.y), MapShape::Polyline(points(p)?)),
        tiled::ObjectShape::Polygon { points: p } => (world(object.x, object.y), MapShape::Polygon(points(p)?)),
    };
    if !position.is_finite() {
        return Err(name(format!("its position {position} is not finite in metres")));
    }
    let mut properties = std::collections::BTreeMap::new();
    for (key, value) in &object.properties {
        let value = match value {
            tiled::PropertyValue::BoolValue(v) => MapValue::Bool(*v),
            tiled::PropertyValue::IntValue(v) => MapValue::Int(*v),
            tiled::PropertyValue::FloatValue(v) => MapValue::Float(*v),
            tiled::PropertyValue::StringValue(v) | tiled::PropertyValue::FileValue(v) => MapValue::Text(v.clone()),
            tiled::PropertyValue::ColorValue(c) => {
                MapValue::Text(format!("#{:02x}{:02x}{:02x}{:02x}", c.alpha, c.red, c.green, c.blue))
            }
            tiled::PropertyValue::ObjectValue(id) => MapValue::Object(*id),
            // Lists and classes have no single value: left out.
            _ => continue,
        };
        properties.insert(key.clone(), value);
    }
    Ok(MapObject {
        id: object.id(),
        name: object.name.clone(),
        class: object.user_type.clone(),
        position,
        shape,
        properties,
    })
}

//! Tile maps made in the [Tiled](https://www.mapeditor.org) editor: a
//! level's solid tiles as a few merged static boxes, its tile layers drawn
//! as one batch each, and its object layers as named spawn points, areas
//! and sensors (the `tiled` feature).
//!
//! ```text
//! .tmx (+ .tsx, .png)  --tiled crate-->  TileMap  --solid_boxes--> BoxCollider::solid, one per merged rectangle
//!                                            |----draw.tiles-----> one sprite batch per layer (one draw call)
//!                                            '----objects/object--> positions, areas, sensors, properties
//! ```
//!
//! A map is read once (in `Game::setup`), through the maintained `tiled`
//! crate, and converted into what the engine uses: the tiles of each
//! layer, each tileset's image as a [`Texture`], the objects in metres.
//! Nothing of it is kept in a world's state: a map is a level's
//! description, like a scene, and its colliders and sensors are ordinary
//! ones (saved in snapshots, covered by the checksum).
//!
//! **Coordinates.** Tiled's are pixels with y down from the map's top-left
//! corner; the map's are metres with y up, the map's bottom-left corner at
//! [`MapOptions::origin`] and a tile [`MapOptions::tile_metres`] wide, so a
//! physics step sees sizes it was tuned for whatever the art's resolution.
//!
//! **Limits.** Orthogonal, finite maps in Tiled's XML format (`.tmx`, what
//! the `tiled` crate reads; a `.tmj` is refused with how to save it as
//! one) of tilesets made from one image each (Tiled's default); an
//! isometric or infinite map, or a tileset of separate images, is refused
//! by name. At most
//! [`MapOptions::max_tiles`] cells a map.
//!
//! In a page a map is fetched like any asset: list the `.tmx`, each
//! `.tsx` it uses and their images in [`Game::assets`](crate::app::Game::assets).

mod merge;
mod objects;
mod read;
#[cfg(test)]
mod tests;

use std::path::{Path, PathBuf};

use glam::Vec2;

use crate::colliders::{BoxCollider, ColliderId, Material};
use crate::render::{Sprite, Texture, TextureError};
use crate::world::World;

pub use merge::merge_cells;
pub use objects::{MapObject, MapShape, MapValue};

/// How a map is placed in the world and how large it may be.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapOptions {
    /// Metres a tile is wide (default 1); a tile's height keeps the
    /// tileset's aspect ratio.
    pub tile_metres: f32,
    /// Where the map's bottom-left corner sits in the world (default the
    /// origin).
    pub origin: Vec2,
    /// The most cells (width x height) a map may have (default 4 194 304,
    /// 2048 x 2048): a limit on the memory and the work of reading it.
    pub max_tiles: u64,
}

impl Default for MapOptions {
    fn default() -> Self {
        Self {
            tile_metres: 1.0,
            origin: Vec2::ZERO,
            max_tiles: 1 << 22,
        }
    }
}

/// What went wrong reading or using a map; each names the file and where.
#[derive(Debug)]
pub enum MapError {
    /// The file (or a tileset or image it names) could not be read or is
    /// not a map Tiled wrote: the `tiled` crate's message.
    Read {
        /// The map.
        path: PathBuf,
        /// What the reader said, with the file it was reading.
        message: String,
    },
    /// The map uses what Tickwork does not take (and how to avoid it).
    Unsupported {
        /// The map.
        path: PathBuf,
        /// What and how to change it.
        what: String,
    },
    /// The map has more cells than [`MapOptions::max_tiles`].
    TooLarge {
        /// The map.
        path: PathBuf,
        /// Its cells, width x height.
        tiles: u128,
        /// The limit.
        limit: u64,
    },
    /// A value of the map or of the options is out of range.
    Invalid {
        /// The map.
        path: PathBuf,
        /// What (layer, cell, object, field), its value and the range.
        what: String,
    },
    /// No layer or object of that name (the ones there are, listed).
    NotFound {
        /// The map.
        path: PathBuf,
        /// What was asked for and what the map has.
        what: String,
    },
    /// A tileset's image.
    Texture(TextureError),
}

impl std::fmt::Display for MapError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Read { path, message } => write!(f, "{}: {message}", path.display()),
            Self::Unsupported { path, what } => write!(f, "{}: {what}", path.display()),
            Self::TooLarge { path, tiles, limit } => write!(
                f,
                "{}: {tiles} cells is more than the limit of {limit} (MapOptions::max_tiles): split the level or \
                 raise the limit",
                path.display()
            ),
            Self::Invalid { path, what } | Self::NotFound { path, what } => write!(f, "{}: {what}", path.display()),
            Self::Texture(error) => write!(f, "{error}"),
        }
    }
}

impl std::error::Error for MapError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Texture(error) => Some(error),
            _ => None,
        }
    }
}

/// A handle on one tile layer of a [`TileMap`], kept from
/// [`TileMap::tile_layer`] rather than looked up by name each frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TileLayerId {
    map: u64,
    index: usize,
}

/// One cell's tile: which tileset, which tile of it, how it is flipped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Cell {
    pub(crate) tileset: usize,
    pub(crate) tile: u32,
    /// Tiled's flips: horizontal, vertical, diagonal (done first).
    pub(crate) flips: [bool; 3],
}

/// A tile layer: a name, whether Tiled shows it, its cells row by row from
/// the top, its offset and opacity.
#[derive(Clone, Debug)]
pub(crate) struct Layer {
    pub(crate) name: String,
    pub(crate) visible: bool,
    pub(crate) solid: bool,
    pub(crate) cells: Vec<Option<Cell>>,
    /// Tiled's offset, pixels (x right, y down).
    pub(crate) offset: Vec2,
    pub(crate) opacity: f32,
}

/// A tileset: its image, its tiles' size in pixels, where they are in it.
#[derive(Clone, Debug)]
pub(crate) struct Tileset {
    pub(crate) texture: Texture,
    pub(crate) tile: [u32; 2],
    pub(crate) columns: u32,
    pub(crate) margin: u32,
    pub(crate) spacing: u32,
    pub(crate) count: u32,
}

impl Tileset {
    /// The region of tile `tile` in the image, `[x, y, width, height]`
    /// (`None` past `u32`: a tileset's numbers are the map's, unchecked).
    pub(crate) fn region(&self, tile: u32) -> Option<[u32; 4]> {
        let (column, row) = (tile % self.columns.max(1), tile / self.columns.max(1));
        let [w, h] = self.tile;
        let at = |k: u32, size: u32| size.checked_add(self.spacing)?.checked_mul(k)?.checked_add(self.margin);
        Some([at(column, w)?, at(row, h)?, w, h])
    }
}

/// A level made in Tiled, in metres: its tile layers, tilesets and
/// objects ([the module](self) says what is taken and how it is placed).
#[derive(Clone, Debug)]
pub struct TileMap {
    id: u64,
    path: PathBuf,
    options: MapOptions,
    /// Cells across and down.
    size: [u32; 2],
    /// The map's cell in pixels.
    cell: [u32; 2],
    layers: Vec<Layer>,
    tilesets: Vec<Tileset>,
    object_layers: Vec<(String, Vec<MapObject>)>,
}

impl TileMap {
    /// Reads the Tiled map at `path` (`.tmx`) with the default
    /// [`MapOptions`] (a tile a metre wide, the map's bottom-left corner at
    /// the origin). The tilesets and images it names are read relative to
    /// it; a relative `path` is found as
    /// [`platform::read_asset`](crate::platform::read_asset) says.
    ///
    /// # Errors
    /// A [`MapError`] naming the file and what was wrong.
    pub fn load(path: impl AsRef<Path>) -> Result<Self, MapError> {
        Self::load_with(path, MapOptions::default())
    }

    /// Reads the map at `path` placed and limited by `options`.
    ///
    /// # Errors
    /// As [`load`](Self::load); [`MapError::Invalid`] for options out of
    /// range.
    pub fn load_with(path: impl AsRef<Path>, options: MapOptions) -> Result<Self, MapError> {
        read::load(path.as_ref(), options)
    }

    /// Reads a map from the text of a `.tmx` file, as if read from `path`
    /// (which names it in errors and places the tilesets and images it
    /// names, read as assets).
    ///
    /// # Errors
    /// As [`load_with`](Self::load_with).
    pub fn parse(text: &[u8], path: impl AsRef<Path>, options: MapOptions) -> Result<Self, MapError> {
        read::parse(text, path.as_ref(), options)
    }

    /// The file it was read from.
    #[must_use]
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Cells across and down.
    #[must_use]
    pub fn size_in_tiles(&self) -> [u32; 2] {
        self.size
    }

    /// A cell's size in metres (width, height).
    #[must_use]
    pub fn tile_size(&self) -> Vec2 {
        let s = self.metres_per_pixel();
        Vec2::new(self.cell[0] as f32 * s, self.cell[1] as f32 * s)
    }

    /// The map's corners in metres (bottom-left, top-right): bounds for a
    /// camera ([`Follow::bounds`](crate::render::Follow)).
    #[must_use]
    pub fn bounds(&self) -> (Vec2, Vec2) {
        let size = self.tile_size() * Vec2::new(self.size[0] as f32, self.size[1] as f32);
        (self.options.origin, self.options.origin + size)
    }

    /// The names of the tile layers, in Tiled's order (bottom first).
    pub fn tile_layer_names(&self) -> impl Iterator<Item = &str> {
        self.layers.iter().map(|l| l.name.as_str())
    }

    /// The tile layer named `name`, to draw ([`Draw::tiles`](crate::app::Draw::tiles))
    /// and to make solid.
    ///
    /// # Errors
    /// [`MapError::NotFound`] listing the map's tile layers.
    pub fn tile_layer(&self, name: &str) -> Result<TileLayerId, MapError> {
        match self.layers.iter().position(|l| l.name == name) {
            Some(index) => Ok(TileLayerId { map: self.id, index }),
            None => Err(self.not_found(format!(
                "no tile layer named \"{name}\"; its tile layers: {}",
                list(self.layers.iter().map(|l| l.name.as_str()))
            ))),
        }
    }

    /// The tile layers Tiled marks solid (a custom property `solid` set
    /// to true), in order.
    pub fn solid_layers(&self) -> impl Iterator<Item = TileLayerId> + '_ {
        self.layers
            .iter()
            .enumerate()
            .filter(|(_, l)| l.solid)
            .map(|(index, _)| TileLayerId { map: self.id, index })
    }

    /// The filled cells of `layer` merged into as few rectangles as the
    /// greedy rule finds (rows first, then down; the same map gives the same
    /// boxes in the same order), as `(min, max)` corners in metres.
    ///
    /// # Errors
    /// [`MapError::NotFound`] for a layer of another map.
    pub fn solid_rectangles(&self, layer: TileLayerId) -> Result<Vec<(Vec2, Vec2)>, MapError> {
        let layer = self.layer(layer)?;
        let [width, height] = self.size;
        let filled: Vec<bool> = layer.cells.iter().map(Option::is_some).collect();
        let tile = self.tile_size();
        let offset = self.pixel_offset(layer.offset);
        Ok(merge_cells(&filled, width, height)
            .into_iter()
            .map(|[x, y, w, h]| {
                // Rows count down from the top; the world's y goes up.
                let left = self.options.origin.x + x as f32 * tile.x + offset.x;
                let top = self.options.origin.y + (height - y) as f32 * tile.y + offset.y;
                (
                    Vec2::new(left, top - h as f32 * tile.y),
                    Vec2::new(left + w as f32 * tile.x, top),
                )
            })
            .collect())
    }

    /// Adds `layer`'s merged rectangles to `world` as static solid boxes of
    /// `material`, a tile deep on z (from `-depth / 2` to `depth / 2`, the
    /// tile's width), and returns their handles, in the order of
    /// [`solid_rectangles`](Self::solid_rectangles).
    ///
    /// # Errors
    /// [`MapError::NotFound`] for a layer of another map.
    pub fn add_colliders(
        &self,
        world: &mut World,
        layer: TileLayerId,
        material: Material,
    ) -> Result<Vec<ColliderId>, MapError> {
        let half_depth = self.tile_size().x / 2.0;
        Ok(self
            .solid_rectangles(layer)?
            .into_iter()
            .map(|(min, max)| {
                world.add_collider(BoxCollider::solid(
                    min.extend(-half_depth),
                    max.extend(half_depth),
                    material,
                ))
            })
            .collect())
    }

    /// The names of the object layers, in Tiled's order.
    pub fn object_layer_names(&self) -> impl Iterator<Item = &str> {
        self.object_layers.iter().map(|(name, _)| name.as_str())
    }

    /// The objects of the object layer `name`, in Tiled's order.
    ///
    /// # Errors
    /// [`MapError::NotFound`] listing the map's object layers.
    pub fn objects(&self, name: &str) -> Result<&[MapObject], MapError> {
        match self.object_layers.iter().find(|(n, _)| n == name) {
            Some((_, objects)) => Ok(objects),
            None => Err(self.not_found(format!(
                "no object layer named \"{name}\"; its object layers: {}",
                list(self.object_layers.iter().map(|(n, _)| n.as_str()))
            ))),
        }
    }

    /// The first object named `name` in any object layer (a spawn point,
    /// the goal).
    ///
    /// # Errors
    /// [`MapError::NotFound`] listing the names there are.
    pub fn object(&self, name: &str) -> Result<&MapObject, MapError> {
        let mut all = self.object_layers.iter().flat_map(|(_, objects)| objects);
        match all.clone().find(|o| o.name == name) {
            Some(object) => Ok(object),
            None => {
                let mut names: Vec<&str> = all.by_ref().map(|o| o.name.as_str()).collect();
                names.sort_unstable();
                names.dedup();
                Err(self.not_found(format!(
                    "no object named \"{name}\"; its objects' names: {}",
                    list(names.into_iter())
                )))
            }
        }
    }

    /// The sprites that draw `layer` (one a filled cell, in Tiled's
    /// right-down order; none for a layer Tiled hides), appended to
    /// `sprites`. [`Draw::tiles`](crate::app::Draw::tiles) calls it.
    ///
    /// # Errors
    /// [`MapError::NotFound`] for a layer of another map.
    pub fn sprites_of(&self, layer: TileLayerId, sprites: &mut Vec<Sprite>) -> Result<(), MapError> {
        let layer = self.layer(layer)?;
        if !layer.visible {
            return Ok(());
        }
        let [width, height] = self.size;
        let s = self.metres_per_pixel();
        let cell = self.tile_size();
        let offset = self.pixel_offset(layer.offset);
        let alpha = (layer.opacity.clamp(0.0, 1.0) * 255.0).round() as u8;
        for (k, cell_tile) in layer.cells.iter().enumerate() {
            let Some(tile) = cell_tile else { continue };
            // Cells are rows of `width` (at most u32::MAX of them).
            let (x, y) = ((k % width as usize) as u32, (k / width as usize) as u32);
            let set = &self.tilesets[tile.tileset];
            let size = Vec2::new(set.tile[0] as f32 * s, set.tile[1] as f32 * s);
            // A tile larger than the cell stands on the cell's bottom-left.
            let bottom_left =
                self.options.origin + offset + Vec2::new(x as f32 * cell.x, (height - 1 - y) as f32 * cell.y);
            let (rotation, flip_x, flip_y) = orientation(tile.flips);
            let mut sprite = Sprite::new(&set.texture, bottom_left + size / 2.0, size);
            // Checked when read: every cell's region is in its image.
            sprite.region = set.region(tile.tile);
            sprite.rotation = rotation;
            sprite.flip_x = flip_x;
            sprite.flip_y = flip_y;
            sprite.tint = [alpha; 4];
            sprites.push(sprite);
        }
        Ok(())
    }

    fn metres_per_pixel(&self) -> f32 {
        self.options.tile_metres / self.cell[0] as f32
    }

    /// A layer's offset in Tiled's pixels as metres (y up).
    fn pixel_offset(&self, offset: Vec2) -> Vec2 {
        Vec2::new(offset.x, -offset.y) * self.metres_per_pixel()
    }

    fn layer(&self, id: TileLayerId) -> Result<&Layer, MapError> {
        match self.layers.get(id.index) {
            Some(layer) if id.map == self.id => Ok(layer),
            _ => Err(self.not_found(format!(
                "the tile layer handle {id:?} is not one of this map's (keep the handles of the map they came from)"
            ))),
        }
    }

    fn not_found(&self, what: String) -> MapError {
        MapError::NotFound {
            path: self.path.clone(),
            what,
        }
    }
}

/// `names` as `"a", "b"`, or `none`.
fn list<'a>(names: impl Iterator<Item = &'a str>) -> String {
    let quoted: Vec<String> = names.map(|n| format!("\"{n}\"")).collect();
    if quoted.is_empty() {
        "none".to_owned()
    } else {
        quoted.join(", ")
    }
}

/// The sprite's turn (radians) and flips that draw a tile as Tiled's flips
/// `[horizontal, vertical, diagonal]` say: the diagonal flip (a swap of the
/// image's x and y) first, then the horizontal, then the vertical.
pub(crate) fn orientation([h, v, d]: [bool; 3]) -> (f32, bool, bool) {
    // In the world (y up) the image's swap of x and y is (x, y) -> (-y, -x),
    // a quarter turn after a mirror in x; the image's horizontal flip is the
    // world's x -> -x, its vertical flip y -> -y.
    let mut m = [[1i8, 0], [0, 1]];
    let mul = |a: [[i8; 2]; 2], b: [[i8; 2]; 2]| {
        [
            [
                a[0][0] * b[0][0] + a[0][1] * b[1][0],
                a[0][0] * b[0][1] + a[0][1] * b[1][1],
            ],
            [
                a[1][0] * b[0][0] + a[1][1] * b[1][0],
                a[1][0] * b[0][1] + a[1][1] * b[1][1],
            ],
        ]
    };
    if d {
        m = mul([[0, -1], [-1, 0]], m);
    }
    if h {
        m = mul([[-1, 0], [0, 1]], m);
    }
    if v {
        m = mul([[1, 0], [0, -1]], m);
    }
    // The sprite draws turn(quarters) . mirror_x(fx) . mirror_y(fy).
    for quarters in 0..4u8 {
        let (c, s) = [(1i8, 0i8), (0, 1), (-1, 0), (0, -1)][usize::from(quarters)];
        for fx in [false, true] {
            for fy in [false, true] {
                let mirror = [[if fx { -1 } else { 1 }, 0], [0, if fy { -1 } else { 1 }]];
                if mul([[c, -s], [s, c]], mirror) == m {
                    return (f32::from(quarters) * core::f32::consts::FRAC_PI_2, fx, fy);
                }
            }
        }
    }
    // The eight flips of a square are its four turns, mirrored or not:
    // every `m` was matched above.
    (0.0, false, false)
}

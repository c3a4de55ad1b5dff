//! Tiled maps: `assets/maps/level.tmx` read into merged boxes a ball lands
//! on, objects in metres, a tile layer drawn in one batch against a golden
//! image, and every kind of bad map refused with what and where.

use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3};
use tickwork_engine::app::{
    Draw, Game, GameError, GameSession, OffscreenRun, SessionOptions, Settings, Stage, renderer_config,
};
use tickwork_engine::render::{Camera, GoldenImages};
use tickwork_engine::tilemap::{MapError, MapOptions, MapShape, MapValue, TileLayerId, TileMap};
use tickwork_engine::{BoxCollider, FixedClock, Material, Particle, Sensor, World, WorldConfig};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn level() -> TileMap {
    TileMap::load(root().join("assets/maps/level.tmx")).unwrap_or_else(|e| panic!("{e}"))
}

/// The level's text with `from` replaced by `to`, read as if it were
/// `assets/maps/<name>.tmx` (so its tileset is found beside it).
fn edited(from: &str, to: &str, options: MapOptions) -> Result<TileMap, MapError> {
    let text = std::fs::read_to_string(root().join("assets/maps/level.tmx")).expect("the level");
    assert!(text.contains(from), "the level has {from:?}");
    TileMap::parse(
        text.replacen(from, to, 1).as_bytes(),
        root().join("assets/maps/edited.tmx"),
        options,
    )
}

/// The filled cells of the level's tile layer `k`, counted in its text.
fn filled_cells(k: usize) -> usize {
    let text = std::fs::read_to_string(root().join("assets/maps/level.tmx")).expect("the level");
    let data = text.split("<data encoding=\"csv\">").nth(k + 1).expect("data");
    let data = data.split("</data>").next().expect("data");
    data.split(',').filter(|v| v.trim() != "0").count()
}

#[test]
fn the_level_reads_in_metres_with_its_layers_and_a_floor_of_one_box() {
    let map = level();
    assert_eq!(map.size_in_tiles(), [40, 12]);
    assert_eq!(map.tile_size(), Vec2::ONE);
    assert_eq!(map.bounds(), (Vec2::ZERO, Vec2::new(40.0, 12.0)));
    assert_eq!(map.tile_layer_names().collect::<Vec<_>>(), ["ground", "decor"]);
    assert_eq!(map.object_layer_names().collect::<Vec<_>>(), ["objects"]);
    let ground = map.tile_layer("ground").expect("a ground layer");
    assert_eq!(
        map.solid_layers().collect::<Vec<_>>(),
        [ground],
        "Tiled's `solid` property"
    );
    let boxes = map.solid_rectangles(ground).expect("boxes");
    // The first floor, 7 tiles by 3, is one box from the map's bottom.
    assert_eq!(boxes.iter().filter(|b| b.0.y == 0.0).count(), 3, "{boxes:?}");
    assert!(boxes.contains(&(Vec2::new(0.0, 0.0), Vec2::new(7.0, 3.0))), "{boxes:?}");
    // The bricks floating at row 2, three tiles: one box 9 to 10 m high.
    assert!(
        boxes.contains(&(Vec2::new(14.0, 9.0), Vec2::new(17.0, 10.0))),
        "{boxes:?}"
    );
    // Each filled cell is covered once: the boxes' areas add up to the cells.
    let area: f32 = boxes.iter().map(|(min, max)| (max.x - min.x) * (max.y - min.y)).sum();
    let filled = filled_cells(0);
    assert_eq!(area, filled as f32);
    assert!(boxes.len() < filled / 4, "{} boxes for {filled} tiles", boxes.len());
    // Scaled and moved: half a metre a tile, from (-10, -2).
    let small = TileMap::load_with(
        root().join("assets/maps/level.tmx"),
        MapOptions {
            tile_metres: 0.5,
            origin: Vec2::new(-10.0, -2.0),
            ..MapOptions::default()
        },
    )
    .expect("reads");
    let ground = small.tile_layer("ground").expect("ground");
    assert!(
        small
            .solid_rectangles(ground)
            .expect("boxes")
            .contains(&(Vec2::new(-10.0, -2.0), Vec2::new(-6.5, -0.5)))
    );
    assert_eq!(
        small.object("player").expect("a spawn").position,
        Vec2::new(-8.75, -0.25)
    );
}

#[test]
fn a_ball_dropped_on_the_levels_colliders_comes_to_rest_on_the_floor() {
    let map = level();
    let mut world = World::new(WorldConfig::default()).expect("a world");
    world.add_force(tickwork_engine::Gravity::EARTH);
    let ground = map.tile_layer("ground").expect("ground");
    let ids = map
        .add_colliders(&mut world, ground, Material::default())
        .expect("colliders");
    assert_eq!(ids.len(), map.solid_rectangles(ground).expect("boxes").len());
    let first = world.collider::<BoxCollider>(ids[0]).expect("a box");
    assert_eq!(first.velocity, Vec3::ZERO, "static");
    let spawn = map.object("player").expect("the spawn");
    let ball = world
        .spawn(Particle {
            position: spawn.position3(),
            radius: 0.25,
            ..Particle::default()
        })
        .expect("spawned");
    let mut clock = FixedClock::default();
    for step in clock.step(240).fixed_steps() {
        world.step(step).expect("steps");
    }
    let at = world.position(ball).expect("there");
    assert!((at.y - 3.25).abs() < 1e-3, "resting on the floor's top at 3 m: {at}");
    assert!((at.x - 2.5).abs() < 1e-6, "straight down: {at}");
}

#[test]
fn objects_come_with_their_areas_classes_properties_and_sensors() {
    let map = level();
    let objects = map.objects("objects").expect("the object layer");
    assert_eq!(objects.len(), 7);
    let spawn = map.object("player").expect("a spawn");
    assert_eq!((spawn.class.as_str(), &spawn.shape), ("spawn", &MapShape::Point));
    assert_eq!(spawn.position, Vec2::new(2.5, 3.5));
    let coins: Vec<_> = objects.iter().filter(|o| o.class == "coin").collect();
    assert_eq!(coins.len(), 3);
    assert_eq!(coins[0].area(), Some((Vec2::new(8.5, 5.5), Vec2::new(9.5, 6.5))));
    assert_eq!(coins[0].position, Vec2::new(9.0, 6.0));
    let spikes = map.object("spikes").expect("spikes");
    assert_eq!(spikes.area(), Some((Vec2::new(21.0, 1.0), Vec2::new(31.0, 1.75))));
    let sensor = spikes.sensor(1.0).expect("a box");
    assert_eq!(
        sensor,
        Sensor::cuboid(Vec3::new(21.0, 1.0, -0.5), Vec3::new(31.0, 1.75, 0.5))
    );
    let mut world = World::default();
    world.add_sensor(sensor).expect("added");
    let flag = map.object("flag").expect("the goal");
    assert_eq!(flag.properties.get("next"), Some(&MapValue::Text("level2.tmx".into())));
    let ferry = map.object("ferry").expect("the ferry");
    assert_eq!((ferry.number("speed"), ferry.number("travel")), (Some(1.5), Some(7.0)));
    let error = spawn.sensor(1.0).expect_err("a point has no area");
    assert!(
        error.contains("object \"player\" (class \"spawn\", id 1) is a point"),
        "{error}"
    );
}

#[test]
fn names_not_in_the_map_are_errors_listing_what_it_has() {
    let map = level();
    let error = map.tile_layer("walls").expect_err("no walls").to_string();
    assert!(
        error.ends_with("level.tmx: no tile layer named \"walls\"; its tile layers: \"ground\", \"decor\""),
        "{error}"
    );
    let error = map.objects("enemies").expect_err("no enemies").to_string();
    assert!(error.contains("its object layers: \"objects\""), "{error}");
    let error = map.object("boss").expect_err("no boss").to_string();
    assert!(
        error.contains(
            "no object named \"boss\"; its objects' names: \"coin\", \"ferry\", \"flag\", \"player\", \"spikes\""
        ),
        "{error}"
    );
    // A handle is its map's: another map's is refused, not misread.
    let other = level();
    let theirs: TileLayerId = other.tile_layer("ground").expect("ground");
    let error = map.solid_rectangles(theirs).expect_err("another map's").to_string();
    assert!(error.contains("is not one of this map's"), "{error}");
}

#[test]
fn bad_maps_are_refused_with_what_and_where() {
    let options = MapOptions::default();
    let refused = |from: &str, to: &str, options: MapOptions| {
        edited(from, to, options)
            .expect_err(&format!("{from} -> {to}"))
            .to_string()
    };
    // Compressed cells: refused before they are inflated.
    let error = refused(
        "<data encoding=\"csv\">",
        "<data encoding=\"base64\" compression=\"zlib\">",
        options,
    );
    assert!(
        error.contains("edited.tmx: layer \"ground\" keeps its cells compressed (zlib): save the map with the tile layer format CSV"),
        "{error}"
    );
    // Fewer cells than the size says (the reader would index past them).
    let error = refused("<data encoding=\"csv\">\n0,", "<data encoding=\"csv\">\n", options);
    assert!(
        error.contains("layer \"ground\" has 479 cells of data where its size says 480"),
        "{error}"
    );
    // Past the limit, which the error names.
    let error = refused(
        "width=\"40\" height=\"12\" tilewidth",
        "width=\"400000\" height=\"120000\" tilewidth",
        options,
    );
    assert!(
        error.contains("48000000000 cells is more than the limit of 4194304 (MapOptions::max_tiles)"),
        "{error}"
    );
    let small = MapOptions {
        max_tiles: 100,
        ..MapOptions::default()
    };
    assert!(refused("orientation", "orientation", small).contains("480 cells is more than the limit of 100"));
    let error = refused("orientation=\"orthogonal\"", "orientation=\"isometric\"", options);
    assert!(
        error.contains("a map of isometric orientation: Tickwork takes orthogonal maps"),
        "{error}"
    );
    let error = refused("infinite=\"0\"", "infinite=\"1\"", options);
    assert!(error.contains("infinite"), "{error}");
    let error = refused("source=\"tiles.tsx\"", "source=\"missing.tsx\"", options);
    assert!(error.contains("missing.tsx"), "{error}");
    let error = refused(
        "<object id=\"5\" name=\"spikes\"",
        "<object id=\"5\" name=\"spikes\" rotation=\"30\"",
        options,
    );
    assert!(
        error.contains("object \"spikes\" (id 5): it is turned 30 degrees: Tickwork's areas are upright"),
        "{error}"
    );
    let error = refused("<map version", "<map><map><map version", options);
    assert!(
        error.contains("not well-formed XML") || error.contains("edited.tmx"),
        "{error}"
    );
    let deep = format!("{}<map version", "<g>".repeat(70));
    let error = refused("<map version", &deep, options);
    assert!(
        error.contains("nest deeper than 64 levels (tilemap::MAX_NESTING)"),
        "{error}"
    );
    let json = TileMap::parse(b"{}", root().join("assets/maps/level.tmj"), options)
        .expect_err("JSON")
        .to_string();
    assert!(
        json.contains(
            "level.tmj: a map in Tiled's JSON format: the tiled crate reads the XML format, so save it as a .tmx"
        ),
        "{json}"
    );
    let error = TileMap::load(root().join("assets/maps/none.tmx"))
        .expect_err("no such file")
        .to_string();
    assert!(error.contains("none.tmx"), "{error}");
    let error = TileMap::load_with(
        root().join("assets/maps/level.tmx"),
        MapOptions {
            tile_metres: 0.0,
            ..MapOptions::default()
        },
    )
    .expect_err("a tile of 0 m")
    .to_string();
    assert!(
        error.contains("MapOptions::tile_metres is 0: it must be finite and above 0"),
        "{error}"
    );
    // Read as the crate reads it: a comment splitting the data (the crate
    // reads its first piece), a namespaced layer, a repeated attribute and
    // base64 padding are counted as the crate counts them, and refused.
    let error = refused(
        "<data encoding=\"csv\">\n0,",
        "<data encoding=\"csv\">\n0<!-- x -->,",
        options,
    );
    assert!(
        error.contains("layer \"ground\" has 1 cells of data where its size says 480"),
        "{error}"
    );
    let error = refused(
        "<layer id=\"1\" name=\"ground\" width=\"40\"",
        "<layer id=\"1\" name=\"ground\" width=\"40\" t:width=\"41\"",
        options,
    );
    assert!(
        error.contains("layer \"ground\" has 480 cells of data where its size says 492"),
        "{error}"
    );
    let base64 =
        "<layer id=\"9\" name=\"b\" width=\"2\" height=\"1\"><data encoding=\"base64\">AQAAAAEAAA==</data></layer>";
    let error = refused(
        " <layer id=\"2\" name=\"decor\"",
        &format!(" {base64}\n <layer id=\"2\" name=\"decor\""),
        options,
    );
    assert!(
        error.contains("layer \"b\" has 1 cells of data where its size says 2"),
        "{error}"
    );
    // A tile past its tileset's image.
    let error = refused("<data encoding=\"csv\">\n0,", "<data encoding=\"csv\">\n9,", options);
    assert!(error.contains("layer \"ground\", cell (0, 0)"), "{error}");
}

/// Draws the level's two tile layers with a camera over the whole map.
struct Level {
    map: TileMap,
    layers: Vec<TileLayerId>,
}

impl Game for Level {
    fn title(&self) -> &str {
        "level"
    }

    fn setup(&mut self, stage: &mut Stage, _settings: &Settings) -> Result<(), GameError> {
        let (min, max) = self.map.bounds();
        stage.camera = Camera::TwoD {
            center: (min + max) / 2.0,
            height: max.y - min.y,
        };
        stage.background = [30, 36, 60, 255];
        Ok(())
    }

    fn draw(&self, _stage: &Stage, _alpha: f32, draw: &mut Draw) -> Result<(), GameError> {
        for &layer in &self.layers {
            draw.tiles(&self.map, layer);
        }
        Ok(())
    }
}

#[test]
fn tile_layers_draw_in_one_batch_each_and_match_their_golden_image() {
    let map = level();
    let layers = vec![
        map.tile_layer("ground").expect("ground"),
        map.tile_layer("decor").expect("decor"),
    ];
    // One call a layer gives one batch of sprites a layer.
    let mut draw = Draw::default();
    draw.tiles(&map, layers[0]);
    assert_eq!(draw.batches.len(), 1);
    assert_eq!(draw.sprites.len(), filled_cells(0));
    assert!(
        draw.sprites.windows(2).all(|w| w[0].texture == w[1].texture),
        "one texture: one draw call"
    );
    assert_eq!(draw.problem(), None);
    let mut session = GameSession::new(Level { map, layers }, SessionOptions::default()).expect("a session");
    let gpu = crate::support::gpu();
    let mut run = OffscreenRun::new(gpu, 640, 192, renderer_config(session.stage(), 192)).expect("a target");
    let image = run.frame(&mut session, 1.0 / 60.0, false).expect("a frame");
    GoldenImages::new(root().join("assets/golden"), root().join("target/golden"))
        .check("tilemap_level", &image)
        .unwrap_or_else(|error| panic!("{error}"));
}

/// Every attribute value of the level, as (start, end) byte ranges.
fn attribute_values(text: &str) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut from = 0;
    while let Some(at) = text[from..].find("=\"") {
        let start = from + at + 2;
        let Some(len) = text[start..].find('"') else { break };
        out.push((start, start + len));
        from = start + len + 1;
    }
    out
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 300, ..proptest::prelude::ProptestConfig::default() })]

    /// Any attribute set to a hostile value, or a few bytes anywhere
    /// changed: a map or an error, never a panic, and a map that reads
    /// gives boxes, objects and sprites.
    #[test]
    fn hostile_maps_are_read_or_refused_never_a_panic(
        picks in proptest::collection::vec((0usize..10_000, 0usize..12), 1..4),
        bytes in proptest::collection::vec((0usize..100_000, proptest::num::u8::ANY), 0..6),
    ) {
        let text = std::fs::read_to_string(root().join("assets/maps/level.tmx")).expect("the level");
        let values = attribute_values(&text);
        let hostile = [
            "-1", "0", "4294967296", "99999", "1e39", "NaN", "inf", "", "x", "2147483648", "-2147483649", "3.5",
        ];
        let mut edited = text.clone();
        for (value, pick) in picks {
            let values = attribute_values(&edited);
            let (start, end) = values[value % values.len()];
            edited.replace_range(start..end, hostile[pick]);
        }
        let mut bytes_of = edited.into_bytes();
        for (at, byte) in bytes {
            let at = at % bytes_of.len();
            bytes_of[at] = byte;
        }
        assert!(!values.is_empty());
        if let Ok(map) = TileMap::parse(&bytes_of, root().join("assets/maps/hostile.tmx"), MapOptions::default()) {
            let mut draw = Draw::default();
            for name in map.tile_layer_names().map(str::to_owned).collect::<Vec<_>>() {
                let layer = map.tile_layer(&name).expect("listed");
                map.solid_rectangles(layer).expect("its own layer");
                draw.tiles(&map, layer);
            }
            for name in map.object_layer_names().map(str::to_owned).collect::<Vec<_>>() {
                for object in map.objects(&name).expect("listed") {
                    let _ = object.sensor(1.0).map(|s| s.validate());
                }
            }
        }
    }
}

#[test]
fn a_map_at_the_size_limit_reads_and_one_cell_past_it_is_refused() {
    // 2048 x 2048 cells, every one solid: one box.
    let side = 2048;
    let row = vec!["1"; side].join(",");
    let data = vec![row; side].join(",\n");
    let text = format!(
        "<?xml version=\"1.0\"?>\n<map version=\"1.10\" orientation=\"orthogonal\" renderorder=\"right-down\" \
         width=\"{side}\" height=\"{side}\" tilewidth=\"16\" tileheight=\"16\" infinite=\"0\">\n \
         <tileset firstgid=\"1\" source=\"tiles.tsx\"/>\n <layer id=\"1\" name=\"all\" width=\"{side}\" \
         height=\"{side}\">\n  <data encoding=\"csv\">\n{data}\n</data>\n </layer>\n</map>\n"
    );
    let path = root().join("assets/maps/huge.tmx");
    let map = TileMap::parse(text.as_bytes(), &path, MapOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let layer = map.tile_layer("all").expect("the layer");
    assert_eq!(
        map.solid_rectangles(layer).expect("boxes"),
        [(Vec2::ZERO, Vec2::splat(2048.0))]
    );
    let limit = MapOptions {
        max_tiles: 2048 * 2048 - 1,
        ..MapOptions::default()
    };
    let error = TileMap::parse(text.as_bytes(), &path, limit).expect_err("past the limit");
    assert!(
        error
            .to_string()
            .contains("4194304 cells is more than the limit of 4194303 (MapOptions::max_tiles)"),
        "{error}"
    );
}

#[test]
fn a_groups_offset_opacity_and_visibility_reach_its_layers_and_objects() {
    let text = std::fs::read_to_string(root().join("assets/maps/level.tmx")).expect("the level");
    let grouped = |attributes: &str| {
        let text = text
            .replacen(
                " <layer id=\"2\" name=\"decor\"",
                &format!(" <group id=\"7\" name=\"g\" {attributes}>\n <layer id=\"2\" name=\"decor\""),
                1,
            )
            .replacen(
                " <objectgroup",
                " </group>\n <group id=\"8\" name=\"h\" offsety=\"16\">\n <objectgroup",
                1,
            )
            .replacen("</objectgroup>", "</objectgroup>\n </group>", 1);
        TileMap::parse(
            text.as_bytes(),
            root().join("assets/maps/grouped.tmx"),
            MapOptions::default(),
        )
        .unwrap_or_else(|e| panic!("{e}"))
    };
    let plain = level();
    let decor = |map: &TileMap| {
        let mut draw = Draw::default();
        draw.tiles(map, map.tile_layer("decor").expect("decor"));
        draw.sprites
    };
    let (before, after) = (decor(&plain), decor(&grouped("offsetx=\"16\" opacity=\"0.5\"")));
    assert_eq!(before.len(), after.len());
    for (a, b) in before.iter().zip(&after) {
        assert_eq!(b.at - a.at, Vec2::new(1.0, 0.0), "the group's 16 px to the right");
        assert_eq!((a.tint[3], b.tint[3]), (255, 128), "half its opacity");
    }
    assert!(
        decor(&grouped("visible=\"0\"")).is_empty(),
        "a hidden group hides its layers"
    );
    // The objects' group is 16 px lower: a metre.
    let map = grouped("");
    assert_eq!(map.object("player").expect("the spawn").position, Vec2::new(2.5, 2.5));
}

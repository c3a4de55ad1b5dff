//! What a game draws, read off headless frames: filled polygons, thick
//! lines, the viewport `draw` is told, and the stage's background and HUD
//! size, drawn as `run` draws them (through `renderer_config`).
//!
//! These need a graphics adapter; `scripts/test` installs Mesa's software
//! Vulkan driver. Without one they fail with the error that names the
//! packages; they never skip.
#![cfg(feature = "render")]

use std::cell::Cell;

use glam::Vec2;
use tickwork_engine::app::{
    Draw, Game, GameError, GameSession, OffscreenRun, SessionOptions, Settings, Stage, Viewport, renderer_config,
};
use tickwork_engine::render::{Camera, Gpu, RgbaImage};
use tickwork_engine::world::Colour;

const RED: Colour = [220, 40, 40, 255];
const GREEN: Colour = [40, 200, 60, 255];
const BLACK: Colour = [0, 0, 0, 255];

/// A 200x100 frame of a 2D camera 10 m high: 10 pixels a metre, the world
/// origin at the frame's centre.
const WIDTH: u32 = 200;
const HEIGHT: u32 = 100;

/// Shapes on a black stage, and HUD text at `hud_size`.
struct Shapes {
    hud_size: f32,
    /// The viewport the last `draw` was told.
    told: Cell<Option<Viewport>>,
}

impl Game for Shapes {
    fn title(&self) -> &str {
        "shapes"
    }

    fn setup(&mut self, stage: &mut Stage, _settings: &Settings) -> Result<(), GameError> {
        stage.camera = Camera::TwoD {
            center: Vec2::ZERO,
            height: 10.0,
        };
        stage.background = BLACK;
        stage.hud_size = self.hud_size;
        Ok(())
    }

    fn draw(&self, _stage: &Stage, _alpha: f32, draw: &mut Draw) -> Result<(), GameError> {
        self.told.set(Some(draw.viewport()));
        // A convex quadrilateral (two triangles of its fan), lower left.
        let corners = [
            Vec2::new(-8.0, -4.0),
            Vec2::new(-4.0, -4.0),
            Vec2::new(-5.0, -1.0),
            Vec2::new(-8.0, -1.0),
        ];
        draw.polygon(&corners, RED);
        // A line 1 m (10 px) wide, lower right.
        draw.thick_line(Vec2::new(2.0, -2.0), Vec2::new(8.0, -2.0), 1.0, GREEN);
        draw.hud.push_str("HUD 1234");
        Ok(())
    }
}

/// The session and the first frame it draws, as `run` would.
fn frame(gpu: &Gpu, hud_size: f32) -> (GameSession<Shapes>, RgbaImage) {
    let game = Shapes {
        hud_size,
        told: Cell::new(None),
    };
    let mut session = GameSession::new(game, SessionOptions::default()).expect("a session");
    let mut run = OffscreenRun::new(gpu, WIDTH, HEIGHT, renderer_config(session.stage(), HEIGHT)).expect("a target");
    let image = run.frame(&mut session, 1.0 / 60.0, true).expect("a frame");
    (session, image)
}

/// The pixel at world point `(x, y)` (metres).
fn at(image: &RgbaImage, x: f32, y: f32) -> [u8; 4] {
    let px = (x * 10.0 + WIDTH as f32 / 2.0) as u32;
    let py = (HEIGHT as f32 / 2.0 - y * 10.0) as u32;
    image.get_pixel(px, py).0
}

/// Rows of the top-left quarter holding HUD text: (first, last).
fn hud_rows(image: &RgbaImage) -> (u32, u32) {
    let rows: Vec<u32> = (0..HEIGHT / 2)
        .filter(|&y| (0..WIDTH / 2).any(|x| image.get_pixel(x, y).0[..3].iter().any(|&c| c > 100)))
        .collect();
    match (rows.first(), rows.last()) {
        (Some(&first), Some(&last)) => (first, last),
        _ => panic!("no HUD text in the top-left quarter"),
    }
}

#[test]
fn polygons_thick_lines_the_viewport_and_the_hud_size_reach_the_frame() {
    let gpu = Gpu::headless().unwrap_or_else(|error| panic!("render tests need an adapter: {error}"));
    let (session, image) = frame(&gpu, 16.0);
    assert_eq!(
        session.game().told.get(),
        Some(Viewport {
            width: WIDTH,
            height: HEIGHT,
            pixels_per_metre: 10.0,
        }),
        "draw is told the frame's size and scale"
    );
    // The stage's background, where nothing is drawn.
    assert_eq!(image.get_pixel(WIDTH - 1, HEIGHT - 1).0, BLACK);
    assert_eq!(at(&image, 0.0, -4.0), BLACK);
    // The polygon fills both triangles of its fan and stops at its slanted
    // edge (x = -4.83 m at y = -1.5 m).
    assert_eq!(at(&image, -7.5, -3.5), RED, "the first triangle");
    assert_eq!(at(&image, -7.5, -1.5), RED, "the second triangle");
    assert_eq!(at(&image, -5.2, -1.5), RED, "inside the slanted edge");
    assert_eq!(at(&image, -4.4, -1.5), BLACK, "outside the slanted edge");
    // The thick line is 10 pixels wide across, centred on y = -2 m, and
    // spans its length (x 2 m to 8 m: columns 120 to 179).
    let column: Vec<u32> = (0..HEIGHT).filter(|&y| image.get_pixel(150, y).0 == GREEN).collect();
    assert_eq!(column, (65..75).collect::<Vec<_>>(), "rows of the line at column 150");
    let row: Vec<u32> = (0..WIDTH).filter(|&x| image.get_pixel(x, 70).0 == GREEN).collect();
    assert_eq!(row, (120..180).collect::<Vec<_>>(), "columns of the line at row 70");
    // The HUD at twice the size is twice as tall (10 and 20 px text in a
    // 100 px frame: `run` scales HUD sizes down to 10/16 below 540 px).
    let (top, bottom) = hud_rows(&image);
    let small = bottom - top + 1;
    let (_, big_image) = frame(&gpu, 32.0);
    let (top, bottom) = hud_rows(&big_image);
    let big = bottom - top + 1;
    assert!(
        (5..=10).contains(&small),
        "16 px HUD text in a 100 px frame is 10 px: {small} rows"
    );
    let ratio = f64::from(big) / f64::from(small);
    assert!(
        (1.7..=2.3).contains(&ratio),
        "HUD text rows: {small} at 16, {big} at 32"
    );
    // The shapes are the same at either HUD size.
    assert_eq!(at(&big_image, -7.5, -3.5), RED);
    assert_eq!(at(&big_image, 5.0, -2.0), GREEN);
}

const BLUE: Colour = [40, 60, 220, 255];
const YELLOW: Colour = [230, 210, 30, 255];
const GREY: Colour = [90, 90, 90, 255];

/// Shapes that overlap, drawn out of layer order, and a world whose one
/// particle (radius 1 m, green, at the origin) sits on layer 0.
struct Layers;

impl Game for Layers {
    fn title(&self) -> &str {
        "layers"
    }

    fn setup(&mut self, stage: &mut Stage, _settings: &Settings) -> Result<(), GameError> {
        stage.camera = Camera::TwoD {
            center: Vec2::ZERO,
            height: 10.0,
        };
        stage.background = BLACK;
        let mut world = tickwork_engine::World::default();
        world.spawn(tickwork_engine::Particle {
            radius: 1.0,
            colour: GREEN,
            ..tickwork_engine::Particle::default()
        })?;
        stage.add_world("ball", world);
        Ok(())
    }

    fn draw(&self, _stage: &Stage, _alpha: f32, draw: &mut Draw) -> Result<(), GameError> {
        // Added first, on layer 1: over the particle and everything on 0.
        draw.layer(1);
        draw.rect(Vec2::new(0.5, -0.5), Vec2::new(3.0, 0.5), YELLOW);
        // Layer 0, in call order: a blue field, a white line across it, a
        // red block over part of the line.
        draw.layer(0);
        draw.rect(Vec2::new(-9.0, -4.5), Vec2::new(9.0, 4.5), BLUE);
        draw.line(
            glam::Vec3::new(-8.0, 3.05, 0.0),
            glam::Vec3::new(8.0, 3.05, 0.0),
            [255, 255, 255, 255],
        );
        draw.rect(Vec2::new(-6.0, 2.0), Vec2::new(-4.0, 4.0), RED);
        // Added last, on layer -1: under the blue field, so never seen.
        draw.layer(-1);
        draw.rect(Vec2::new(5.0, -4.0), Vec2::new(7.0, -2.0), GREY);
        Ok(())
    }
}

#[test]
fn shapes_are_drawn_in_call_order_within_a_layer_and_by_layer_above_it() {
    let gpu = Gpu::headless().unwrap_or_else(|error| panic!("render tests need an adapter: {error}"));
    let mut session = GameSession::new(Layers, SessionOptions::default()).expect("a session");
    let mut run = OffscreenRun::new(&gpu, WIDTH, HEIGHT, renderer_config(session.stage(), HEIGHT)).expect("a target");
    let image = run.frame(&mut session, 1.0 / 60.0, true).expect("a frame");
    if let Ok(path) = std::env::var("TICKWORK_SAVE_LAYERS") {
        image.save(path).expect("saved");
    }
    // The line is drawn after the blue field (visible on it) and before
    // the red block (hidden under it).
    let white = |p: [u8; 4]| p[..3].iter().all(|&c| c > 200);
    let rows: Vec<u32> = (0..HEIGHT).filter(|&y| white(image.get_pixel(100, y).0)).collect();
    assert!(
        rows == [19],
        "the line over the field, through the centre of row 19 (y = 3.05 m): rows {rows:?}"
    );
    for &y in &rows {
        assert!(white(image.get_pixel(170, y).0), "along its length");
        assert!(
            (45..55).all(|x| image.get_pixel(x, y).0 == RED),
            "the red block covers the line on row {y}"
        );
    }
    assert_eq!(at(&image, -5.0, 3.5), RED);
    assert_eq!(at(&image, -7.0, -1.0), BLUE, "the field");
    // The grey block on layer -1 is under the field.
    assert_eq!(at(&image, 6.0, -3.0), BLUE, "layer -1 is under layer 0");
    // The particle is over the field (its layer's shapes come first), and
    // the yellow panel on layer 1 over the particle, though added first.
    let ball = at(&image, -0.5, 0.0);
    assert!(
        ball[1] > 150 && ball[0] < 100 && ball[2] < 100,
        "the particle over the field: {ball:?}"
    );
    assert_eq!(at(&image, 0.7, 0.0), YELLOW, "layer 1 over the particle");
    assert_eq!(at(&image, 2.5, 0.0), YELLOW, "and over the field");
    // Moving the particles up a layer puts them over the panel.
    struct Over;
    impl Game for Over {
        fn title(&self) -> &str {
            "over"
        }
        fn setup(&mut self, stage: &mut Stage, settings: &Settings) -> Result<(), GameError> {
            Layers.setup(stage, settings)
        }
        fn draw(&self, stage: &Stage, alpha: f32, draw: &mut Draw) -> Result<(), GameError> {
            Layers.draw(stage, alpha, draw)?;
            draw.particle_layer(1);
            Ok(())
        }
    }
    let mut session = GameSession::new(Over, SessionOptions::default()).expect("a session");
    let image = run.frame(&mut session, 1.0 / 60.0, true).expect("a frame");
    let ball = at(&image, 0.7, 0.0);
    assert!(
        ball[1] > 150 && ball[2] < 100 && ball != YELLOW,
        "the particle over the panel: {ball:?}"
    );
}

/// A 16 x 9 m field, letterboxed, and a red block far larger than it.
struct Boxed;

impl Game for Boxed {
    fn title(&self) -> &str {
        "boxed"
    }

    fn setup(&mut self, stage: &mut Stage, _settings: &Settings) -> Result<(), GameError> {
        stage.camera = Camera::Field {
            center: Vec2::ZERO,
            size: Vec2::new(16.0, 9.0),
            fit: tickwork_engine::render::Fit::Letterbox,
        };
        stage.background = BLACK;
        Ok(())
    }

    fn draw(&self, _stage: &Stage, _alpha: f32, draw: &mut Draw) -> Result<(), GameError> {
        draw.rect(Vec2::splat(-100.0), Vec2::splat(100.0), RED);
        draw.hud.push_str("HUD");
        Ok(())
    }
}

#[test]
fn a_letterboxed_field_draws_nothing_in_its_bars_and_the_stage_knows_the_frame() {
    let gpu = Gpu::headless().unwrap_or_else(|error| panic!("render tests need an adapter: {error}"));
    let mut session = GameSession::new(Boxed, SessionOptions::default()).expect("a session");
    let mut run = OffscreenRun::new(&gpu, WIDTH, HEIGHT, renderer_config(session.stage(), HEIGHT)).expect("a target");
    let image = run.frame(&mut session, 1.0 / 60.0, true).expect("a frame");
    // 2:1 frame, 16:9 field: pillars at the sides, the field 178 px wide
    // from x = 11 (100 px high).
    let red: Vec<u32> = (0..WIDTH).filter(|&x| image.get_pixel(x, 80).0 == RED).collect();
    assert_eq!(
        red,
        (11..189).collect::<Vec<_>>(),
        "the block stops at the field's edges"
    );
    assert_eq!(image.get_pixel(5, 80).0, BLACK, "the left pillar is the background");
    assert_eq!(image.get_pixel(195, 80).0, BLACK, "the right pillar");
    // The HUD is drawn over the whole frame.
    let (top, _) = hud_rows(&image);
    assert!(top < 20, "HUD text at the top: row {top}");
    // The stage knows the frame it was drawn in, for `update`.
    let stage = session.stage();
    assert_eq!((stage.viewport().width, stage.viewport().height), (WIDTH, HEIGHT));
    let (min, max) = stage.visible().expect("2D");
    assert!(min.abs_diff_eq(Vec2::new(-8.0, -4.5), 0.05) && max.abs_diff_eq(Vec2::new(8.0, 4.5), 0.05));
    let centre = stage.screen_to_world(Vec2::new(100.0, 50.0)).expect("on the plane");
    assert!(centre.abs_diff_eq(Vec2::ZERO, 1e-3), "{centre}");
    let corner = stage.world_to_screen(glam::Vec3::new(-8.0, 4.5, 0.0)).expect("2D");
    assert!(corner.abs_diff_eq(Vec2::new(11.0, 0.0), 0.2), "{corner}");
}

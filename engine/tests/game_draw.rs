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

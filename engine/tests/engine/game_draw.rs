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

/// A 2D camera 10 m high (10 pixels a metre in the frame) over a black stage.
fn black_stage(stage: &mut Stage) {
    stage.camera = Camera::TwoD {
        center: Vec2::ZERO,
        height: 10.0,
    };
    stage.background = BLACK;
}

/// The first frame `game` draws, `WIDTH` x `HEIGHT`, as `run` would.
fn first_frame<G: Game>(gpu: &Gpu, game: G) -> Result<RgbaImage, tickwork_engine::app::RunError> {
    let mut session = GameSession::new(game, SessionOptions::default()).expect("a session");
    let mut run = OffscreenRun::new(gpu, WIDTH, HEIGHT, renderer_config(session.stage(), HEIGHT)).expect("a target");
    run.frame(&mut session, 1.0 / 60.0, true)
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
    let gpu = crate::support::gpu().clone();
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
        black_stage(stage);
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
    let gpu = crate::support::gpu().clone();
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
    // A second world of its own layer (1): its red particle over the
    // panel, while the first world's stays under it; stepped on the CPU,
    // and on the GPU (drawn from its buffers, on its layer too).
    struct TwoWorlds {
        gpu: bool,
        sparks: Option<tickwork_engine::app::WorldId>,
    }
    impl Game for TwoWorlds {
        fn title(&self) -> &str {
            "two worlds"
        }
        fn setup(&mut self, stage: &mut Stage, settings: &Settings) -> Result<(), GameError> {
            Layers.setup(stage, settings)?;
            let mut sparks = tickwork_engine::World::default();
            sparks.spawn(tickwork_engine::Particle {
                position: glam::Vec3::new(2.5, 0.0, 0.0),
                radius: 0.4,
                colour: RED,
                ..tickwork_engine::Particle::default()
            })?;
            if self.gpu {
                sparks.set_backend(tickwork_engine::world::Backend::Gpu);
            }
            self.sparks = Some(stage.add_world("sparks", sparks).layer(1).id());
            Ok(())
        }
        fn draw(&self, stage: &Stage, alpha: f32, draw: &mut Draw) -> Result<(), GameError> {
            Layers.draw(stage, alpha, draw)
        }
    }
    for gpu in [false, true] {
        let game = TwoWorlds { gpu, sparks: None };
        let mut session = GameSession::new(game, SessionOptions::default()).expect("a session");
        let image = run.frame(&mut session, 1.0 / 60.0, true).expect("a frame");
        let sparks = session.game().sparks.expect("set up");
        assert_eq!(
            session.stage().shown(sparks).map(|w| w.on_gpu()).ok(),
            Some(gpu),
            "where the sparks step"
        );
        assert_eq!(at(&image, 0.7, 0.0), YELLOW, "the first world under the panel");
        let spark = at(&image, 2.5, 0.0);
        assert!(
            spark[0] > 150 && spark[1] < 100 && spark[2] < 100,
            "the second world's particle over the panel (on the GPU: {gpu}): {spark:?}"
        );
    }
}

/// Texts and shapes that overlap, over and under one another by call
/// order and layer, and a particle (green, radius 1 m, at the origin).
struct TextOrder;

impl Game for TextOrder {
    fn title(&self) -> &str {
        "text order"
    }

    fn setup(&mut self, stage: &mut Stage, settings: &Settings) -> Result<(), GameError> {
        Layers.setup(stage, settings)
    }

    fn draw(&self, _stage: &Stage, _alpha: f32, draw: &mut Draw) -> Result<(), GameError> {
        let white = [255, 255, 255, 255];
        // Left (x -9..-5): a text, then a red block over it.
        draw.text("MMMM", glam::Vec3::new(-7.0, 2.0, 0.0))
            .size(30.0)
            .colour(white);
        draw.rect(Vec2::new(-9.0, 0.5), Vec2::new(-5.0, 3.5), RED);
        // Right (x 5..9): a red block, then a text over it.
        draw.rect(Vec2::new(5.0, 0.5), Vec2::new(9.0, 3.5), RED);
        draw.text("MMMM", glam::Vec3::new(7.0, 2.0, 0.0))
            .size(30.0)
            .colour(white);
        // Below the middle: a text on layer 1, over the blue block drawn
        // after it on layer 0.
        draw.layer(1);
        draw.text("MMMM", glam::Vec3::new(7.0, -2.5, 0.0))
            .size(30.0)
            .colour(white);
        draw.layer(0);
        draw.rect(Vec2::new(5.0, -4.0), Vec2::new(9.0, -1.0), BLUE);
        // The particle's layer (0): a text there is under the particle.
        draw.text("MMMM", glam::Vec3::ZERO).size(30.0).colour(white);
        Ok(())
    }
}

#[test]
fn texts_are_drawn_in_call_order_with_the_shapes_and_by_layer() {
    let gpu = crate::support::gpu().clone();
    let mut session = GameSession::new(TextOrder, SessionOptions::default()).expect("a session");
    let mut run = OffscreenRun::new(&gpu, WIDTH, HEIGHT, renderer_config(session.stage(), HEIGHT)).expect("a target");
    let image = run.frame(&mut session, 1.0 / 60.0, true).expect("a frame");
    if let Ok(path) = std::env::var("TICKWORK_SAVE_TEXT_ORDER") {
        image.save(path).expect("saved");
    }
    // Pixels that are text (bright, near white) in a world rectangle.
    let white_in = |image: &RgbaImage, (x0, y0): (f32, f32), (x1, y1): (f32, f32)| {
        let pixel = |x: f32, y: f32| (((x + 10.0) * 10.0) as u32, ((5.0 - y) * 10.0) as u32);
        let ((left, bottom), (right, top)) = (pixel(x0, y0), pixel(x1, y1));
        (left..right)
            .flat_map(|x| (top..bottom).map(move |y| (x, y)))
            .filter(|&(x, y)| image.get_pixel(x, y).0[..3].iter().all(|&c| c > 200))
            .count()
    };
    let white = |a, b| white_in(&image, a, b);
    assert_eq!(
        white((-9.0, 0.5), (-5.0, 3.5)),
        0,
        "the block drawn after the text covers it"
    );
    assert!(
        white((5.0, 0.5), (9.0, 3.5)) > 40,
        "the text drawn after the block is over it"
    );
    assert_eq!(at(&image, 8.9, 0.6), RED);
    assert!(
        white((5.0, -4.0), (9.0, -1.0)) > 40,
        "layer 1's text is over layer 0's block"
    );
    assert_eq!(at(&image, 5.1, -3.9), BLUE);
    // The particle covers the middle of the text under it; the text shows
    // beside it.
    assert_eq!(white((-0.6, -0.6), (0.6, 0.6)), 0, "the particle over its layer's text");
    assert!(white((-3.0, -1.0), (-1.0, 1.0)) > 10, "the text beside the particle");
    // Each text between two shapes is a run of its own: past the limit,
    // the frame is an error that names it.
    struct Runs;
    impl Game for Runs {
        fn title(&self) -> &str {
            "runs"
        }
        fn setup(&mut self, stage: &mut Stage, _settings: &Settings) -> Result<(), GameError> {
            black_stage(stage);
            Ok(())
        }
        fn draw(&self, _stage: &Stage, _alpha: f32, draw: &mut Draw) -> Result<(), GameError> {
            for _ in 0..=tickwork_engine::render::MAX_TEXT_RUNS {
                draw.text("a", glam::Vec3::ZERO);
                draw.rect(Vec2::ZERO, Vec2::ONE, RED);
            }
            Ok(())
        }
    }
    // Labels on a layer of their own, each added after its shape on
    // another: side by side once sorted, they are one run.
    struct Labels;
    impl Game for Labels {
        fn title(&self) -> &str {
            "labels"
        }
        fn setup(&mut self, stage: &mut Stage, _settings: &Settings) -> Result<(), GameError> {
            black_stage(stage);
            Ok(())
        }
        fn draw(&self, _stage: &Stage, _alpha: f32, draw: &mut Draw) -> Result<(), GameError> {
            for k in 0..2 * tickwork_engine::render::MAX_TEXT_RUNS {
                let x = (k % 20) as f32 - 10.0;
                draw.layer(0);
                draw.rect(Vec2::new(x, 4.0), Vec2::new(x + 0.5, 4.5), RED);
                draw.layer(1);
                draw.text("a", glam::Vec3::new(x, -3.0, 0.0));
            }
            Ok(())
        }
    }
    let mut session = GameSession::new(Labels, SessionOptions::default()).expect("a session");
    let labels = run.frame(&mut session, 1.0 / 60.0, true).expect("labels are one run");
    assert!(
        white_in(&labels, (-9.0, -4.0), (9.0, -2.0)) > 20,
        "the labels are drawn"
    );
    let mut session = GameSession::new(Runs, SessionOptions::default()).expect("a session");
    let error = run.frame(&mut session, 1.0 / 60.0, true).expect_err("too many runs");
    assert!(
        error.to_string().contains("1025 runs of text") && error.to_string().contains("render::MAX_TEXT_RUNS"),
        "{error}"
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
    let gpu = crate::support::gpu().clone();
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

/// One text, "Tick\nwork 42", at the world origin, in yellow.
struct Label {
    anchor: tickwork_engine::render::Anchor,
    size: f32,
    unit: tickwork_engine::render::TextUnit,
    /// The camera's height in metres.
    zoom: f32,
    /// What `measure` said, in pixels.
    measured: Cell<Option<Vec2>>,
}

impl Game for Label {
    fn title(&self) -> &str {
        "label"
    }

    fn setup(&mut self, stage: &mut Stage, _settings: &Settings) -> Result<(), GameError> {
        stage.camera = Camera::TwoD {
            center: Vec2::ZERO,
            height: self.zoom,
        };
        stage.background = BLACK;
        stage.hud_size = 1.0;
        Ok(())
    }

    fn draw(&self, _stage: &Stage, _alpha: f32, draw: &mut Draw) -> Result<(), GameError> {
        use tickwork_engine::render::TextUnit;
        let text = "Tick\nwork 42";
        let pixels = match self.unit {
            TextUnit::Pixels => self.size,
            TextUnit::Metres => self.size * draw.viewport().pixels_per_metre,
            TextUnit::FrameHeight => self.size * draw.viewport().height as f32,
        };
        self.measured.set(Some(draw.measure(text, pixels)));
        let placed = draw.text(text, glam::Vec3::ZERO).colour(YELLOW).anchor(self.anchor);
        match self.unit {
            TextUnit::Pixels => placed.size(self.size),
            TextUnit::Metres => placed.size_metres(self.size),
            TextUnit::FrameHeight => placed.size_of_frame(self.size),
        };
        Ok(())
    }
}

/// The box (left, top, right, bottom; pixels) of the label's lit pixels in
/// a `width` x `height` frame, and what `measure` said.
fn label_box(
    gpu: &Gpu,
    anchor: tickwork_engine::render::Anchor,
    size: f32,
    unit: tickwork_engine::render::TextUnit,
    zoom: f32,
    (width, height): (u32, u32),
) -> ([u32; 4], Vec2, u32) {
    let game = Label {
        anchor,
        size,
        unit,
        zoom,
        measured: Cell::new(None),
    };
    let mut session = GameSession::new(game, SessionOptions::default()).expect("a session");
    let mut run = OffscreenRun::new(gpu, width, height, renderer_config(session.stage(), height)).expect("a target");
    let image = run.frame(&mut session, 1.0 / 60.0, true).expect("a frame");
    let lit = |x: u32, y: u32| image.get_pixel(x, y).0[0] > 60;
    let xs: Vec<u32> = (0..width).filter(|&x| (0..height).any(|y| lit(x, y))).collect();
    let ys: Vec<u32> = (0..height).filter(|&y| (0..width).any(|x| lit(x, y))).collect();
    let (Some(&left), Some(&right), Some(&top), Some(&bottom)) = (xs.first(), xs.last(), ys.first(), ys.last()) else {
        panic!("no text drawn for {anchor:?}")
    };
    let measured = session.game().measured.get().expect("drawn");
    // The right end of the first line ("Tick"): its rows are the top third.
    let first_line = top + (bottom - top) / 3;
    let first_right = (0..width)
        .filter(|&x| (top..=first_line).any(|y| lit(x, y)))
        .max()
        .unwrap_or(0);
    ([left, top, right, bottom], measured, first_right)
}

#[test]
fn text_sits_on_any_of_nine_anchors_measures_as_drawn_and_scales_by_its_unit() {
    use tickwork_engine::render::{Anchor, TextUnit};
    let gpu = crate::support::gpu().clone();
    // The origin is pixel (200, 150) of a 400 x 300 frame.
    let frame = (400, 300);
    let (cx, cy) = (200i64, 150i64);
    for anchor in [
        Anchor::TopLeft,
        Anchor::Top,
        Anchor::TopRight,
        Anchor::Left,
        Anchor::Centre,
        Anchor::Right,
        Anchor::BottomLeft,
        Anchor::Bottom,
        Anchor::BottomRight,
    ] {
        let ([left, top, right, bottom], measured, first_right) =
            label_box(&gpu, anchor, 30.0, TextUnit::Pixels, 10.0, frame);
        let (fx, fy) = anchor.fractions();
        // The measured box put at the anchor holds the lit pixels, within
        // a few pixels of side bearing and line spacing.
        let boxed_left = cx as f32 - fx * measured.x;
        let boxed_top = cy as f32 - fy * measured.y;
        let near = |a: f32, b: u32, slack: f32| (a - b as f32).abs() <= slack;
        assert!(
            near(boxed_left, left, 4.0) && near(boxed_left + measured.x, right, 4.0),
            "{anchor:?}: columns {left}..{right}, measured {measured} from {boxed_left}"
        );
        assert!(
            near(boxed_top, top, 9.0) && near(boxed_top + measured.y, bottom, 9.0),
            "{anchor:?}: rows {top}..{bottom}, measured {measured} from {boxed_top}"
        );
        // Right-anchored text ends at the point, each line right-aligned
        // (the short first line too); left-anchored lines start together.
        if fx == 1.0 {
            assert!((i64::from(right) - cx).abs() <= 3, "{anchor:?} ends at x = {right}");
            assert!(
                right - first_right <= 3,
                "{anchor:?}: the first line ends at {first_right}"
            );
        } else if fx == 0.0 {
            assert!(right - first_right > 20, "{anchor:?}: the first line is the shorter");
        }
    }
    // World units: half the camera's height, twice the pixels.
    let (near_box, _, _) = label_box(&gpu, Anchor::Centre, 1.0, TextUnit::Metres, 20.0, frame);
    let (far_box, _, _) = label_box(&gpu, Anchor::Centre, 1.0, TextUnit::Metres, 10.0, frame);
    let tall = |b: [u32; 4]| f64::from(b[3] - b[1] + 1);
    let ratio = tall(far_box) / tall(near_box);
    assert!((1.8..=2.2).contains(&ratio), "zoomed in twice: {ratio}");
    // A fraction of the frame: twice the frame, twice the text.
    let (small, _, _) = label_box(&gpu, Anchor::Centre, 0.1, TextUnit::FrameHeight, 10.0, (400, 300));
    let (big, _, _) = label_box(&gpu, Anchor::Centre, 0.1, TextUnit::FrameHeight, 10.0, (800, 600));
    let ratio = tall(big) / tall(small);
    assert!((1.8..=2.2).contains(&ratio), "a frame twice as high: {ratio}");
}

/// A concave L, a square with a hole and a stroke `stroke_px` pixels wide,
/// under a camera `zoom` metres high; or a polygon with a NaN corner.
struct Outlines {
    zoom: f32,
    nan: bool,
}

impl Game for Outlines {
    fn title(&self) -> &str {
        "outlines"
    }

    fn setup(&mut self, stage: &mut Stage, _settings: &Settings) -> Result<(), GameError> {
        stage.camera = Camera::TwoD {
            center: Vec2::ZERO,
            height: self.zoom,
        };
        stage.background = BLACK;
        Ok(())
    }

    fn draw(&self, _stage: &Stage, _alpha: f32, draw: &mut Draw) -> Result<(), GameError> {
        use tickwork_engine::render::Stroke;
        if self.nan {
            draw.polygon(&[Vec2::ZERO, Vec2::new(f32::NAN, 1.0), Vec2::ONE], RED);
            return Ok(());
        }
        // An L from (-4.5, -2) of three 1 m squares; its notch at (-3, -0.5).
        let l = [
            Vec2::new(-4.5, -2.0),
            Vec2::new(-2.5, -2.0),
            Vec2::new(-2.5, -1.0),
            Vec2::new(-3.5, -1.0),
            Vec2::new(-3.5, 0.0),
            Vec2::new(-4.5, 0.0),
        ];
        draw.polygon(&l, RED);
        // A 3 m square at (1.5, -2) with a 1 m hole in its middle.
        let square = [
            Vec2::new(0.0, -3.5),
            Vec2::new(3.0, -3.5),
            Vec2::new(3.0, -0.5),
            Vec2::new(0.0, -0.5),
        ];
        let hole = [
            Vec2::new(1.0, -2.5),
            Vec2::new(2.0, -2.5),
            Vec2::new(2.0, -1.5),
            Vec2::new(1.0, -1.5),
        ];
        draw.polygon_with_holes(&square, &[&hole], GREEN);
        // A horizontal stroke 4 pixels wide along y = 2 m (a pixel edge at
        // both zooms), whatever the zoom.
        draw.stroke(
            &[Vec2::new(-4.0, 2.0), Vec2::new(4.0, 2.0)],
            false,
            Stroke::pixels(4.0),
            YELLOW,
        );
        Ok(())
    }
}

#[test]
fn concave_and_holed_polygons_and_strokes_in_pixels_reach_the_frame_and_a_nan_is_an_error() {
    let gpu = crate::support::gpu().clone();
    let draw = |zoom: f32| first_frame(&gpu, Outlines { zoom, nan: false }).expect("a frame");
    let image = draw(10.0);
    assert_eq!(at(&image, -4.0, -1.5), RED, "the L's corner square");
    assert_eq!(at(&image, -4.0, -0.5), RED, "its upright");
    assert_eq!(at(&image, -3.0, -1.5), RED, "its foot");
    assert_eq!(at(&image, -3.0, -0.5), BLACK, "the notch of the concave L");
    assert_eq!(at(&image, 0.5, -3.0), GREEN, "the square");
    assert_eq!(at(&image, 1.5, -2.0), BLACK, "its hole");
    // The stroke is 4 pixels thick at 10 px a metre and at 5.
    for (zoom, image) in [(10.0, image), (20.0, draw(20.0))] {
        let rows: Vec<u32> = (0..HEIGHT).filter(|&y| image.get_pixel(100, y).0 == YELLOW).collect();
        assert_eq!(rows.len(), 4, "a camera {zoom} m high: rows {rows:?}");
    }
    let error = first_frame(&gpu, Outlines { zoom: 10.0, nan: true }).expect_err("a NaN corner");
    assert!(
        error.to_string().contains("Draw::polygon: point 1 is [NaN, 1]"),
        "{error}"
    );
}

/// One green particle of radius 1 m at the origin, hidden or not.
struct Ghost {
    visible: bool,
}

impl Game for Ghost {
    fn title(&self) -> &str {
        "ghost"
    }

    fn setup(&mut self, stage: &mut Stage, _settings: &Settings) -> Result<(), GameError> {
        black_stage(stage);
        let mut world = tickwork_engine::World::default();
        let ghost = world.spawn(tickwork_engine::Particle {
            radius: 1.0,
            colour: GREEN,
            ..tickwork_engine::Particle::default()
        })?;
        world.set_visible(ghost, self.visible)?;
        stage.add_world("ghost", world);
        Ok(())
    }
}

#[test]
fn a_hidden_particle_is_not_drawn() {
    let gpu = crate::support::gpu().clone();
    for visible in [true, false] {
        let image = first_frame(&gpu, Ghost { visible }).expect("a frame");
        let centre = at(&image, 0.0, 0.0);
        if visible {
            assert!(centre[1] > 150, "drawn: {centre:?}");
        } else {
            assert_eq!(centre, BLACK, "hidden");
        }
    }
}

/// A 2 x 2 texture (red, green over blue, white) drawn four ways.
struct Sprites {
    texture: tickwork_engine::render::Texture,
    bad_region: bool,
}

impl Game for Sprites {
    fn title(&self) -> &str {
        "sprites"
    }

    fn setup(&mut self, stage: &mut Stage, _settings: &Settings) -> Result<(), GameError> {
        black_stage(stage);
        Ok(())
    }

    fn draw(&self, _stage: &Stage, _alpha: f32, draw: &mut Draw) -> Result<(), GameError> {
        if self.bad_region {
            draw.sprite(&self.texture, Vec2::ZERO, Vec2::ONE).region([1, 1, 2, 1]);
            return Ok(());
        }
        // As is, 4 m square, centred at (-5, 0).
        draw.sprite(&self.texture, Vec2::new(-5.0, 0.0), Vec2::splat(4.0));
        // Turned a quarter turn counter-clockwise about its centre (3, 0).
        draw.sprite(&self.texture, Vec2::new(3.0, 0.0), Vec2::splat(4.0))
            .rotation(core::f32::consts::FRAC_PI_2);
        // Mirrored both ways, 2 m square, centred at (-1, 0).
        draw.sprite(&self.texture, Vec2::new(-1.0, 0.0), Vec2::splat(2.0))
            .flip_x(true)
            .flip_y(true);
        // The white texel alone, tinted yellow, its bottom-left corner at (6, 2).
        draw.sprite(&self.texture, Vec2::new(6.0, 2.0), Vec2::splat(2.0))
            .region([1, 1, 1, 1])
            .pivot(Vec2::ZERO)
            .tint(YELLOW);
        Ok(())
    }
}

#[test]
fn sprites_are_drawn_placed_turned_flipped_tinted_and_cut_from_an_atlas() {
    use tickwork_engine::render::{RgbaImage, Texture};
    let gpu = crate::support::gpu().clone();
    // Through a PNG file, as a game loads one.
    let mut png = RgbaImage::new(2, 2);
    for (x, y, colour) in [(0, 0, RED), (1, 0, GREEN), (0, 1, BLUE), (1, 1, [255, 255, 255, 255])] {
        png.put_pixel(x, y, tickwork_engine::render::Rgba(colour));
    }
    let path = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("sprite-2x2.png");
    png.save(&path).expect("saved");
    let texture = Texture::load(&path).expect("a PNG");
    assert_eq!((texture.width(), texture.height()), (2, 2));
    let frame = |bad_region| {
        let game = Sprites {
            texture: texture.clone(),
            bad_region,
        };
        first_frame(&gpu, game)
    };
    let image = frame(false).expect("a frame");
    let white = [255, 255, 255, 255];
    // As is: the texture's top row at the top.
    assert_eq!(at(&image, -6.0, 1.0), RED);
    assert_eq!(at(&image, -4.0, 1.0), GREEN);
    assert_eq!(at(&image, -6.0, -1.0), BLUE);
    assert_eq!(at(&image, -4.0, -1.0), white);
    assert_eq!(at(&image, -7.5, 2.5), BLACK, "outside it");
    // A quarter turn counter-clockwise: the top-left texel goes bottom-left.
    assert_eq!(at(&image, 2.0, -1.0), RED);
    assert_eq!(at(&image, 2.0, 1.0), GREEN);
    assert_eq!(at(&image, 4.0, 1.0), white);
    assert_eq!(at(&image, 4.0, -1.0), BLUE);
    // Mirrored on x and y: the top-left texel goes bottom-right.
    assert_eq!(at(&image, -1.5, 0.5), white);
    assert_eq!(at(&image, -0.5, 0.5), BLUE);
    assert_eq!(at(&image, -1.5, -0.5), GREEN);
    assert_eq!(at(&image, -0.5, -0.5), RED);
    // One texel of the atlas, tinted, placed by its bottom-left corner.
    let tinted = at(&image, 7.0, 3.0);
    assert!(tinted.iter().zip(YELLOW).all(|(a, b)| a.abs_diff(b) <= 2), "{tinted:?}");
    assert_eq!(at(&image, 5.5, 3.0), BLACK, "nothing left of its corner");
    // A region past the texture is an error naming the sprite.
    let error = frame(true).expect_err("a region past the texture");
    assert!(
        error
            .to_string()
            .contains("sprite 0 of the frame: its region [1, 1, 2, 1]"),
        "{error}"
    );
    // A file that is not a PNG names itself.
    let error = Texture::load(path.with_extension("missing")).expect_err("no file");
    assert!(error.to_string().contains("sprite-2x2.missing"), "{error}");
}

/// One white particle of radius 1 m at the origin, its world drawn as
/// sprites of the 2 x 2 texture.
struct Coins {
    texture: tickwork_engine::render::Texture,
}

impl Game for Coins {
    fn title(&self) -> &str {
        "coins"
    }

    fn setup(&mut self, stage: &mut Stage, _settings: &Settings) -> Result<(), GameError> {
        black_stage(stage);
        let mut world = tickwork_engine::World::default();
        world.spawn(tickwork_engine::Particle {
            radius: 1.0,
            colour: [255, 255, 255, 255],
            ..tickwork_engine::Particle::default()
        })?;
        stage.add_world("coins", world).sprites(&self.texture);
        Ok(())
    }
}

#[test]
fn a_worlds_particles_can_be_drawn_as_sprites() {
    use tickwork_engine::render::Texture;
    let gpu = crate::support::gpu().clone();
    let pixels = [RED, GREEN, BLUE, [255, 255, 255, 255]].concat();
    let texture = Texture::from_rgba(2, 2, pixels).expect("2 x 2");
    let image = first_frame(&gpu, Coins { texture }).expect("a frame");
    // The sprite is the disc's square (2 m); the white disc is not drawn
    // over it.
    assert_eq!(at(&image, -0.5, 0.5), RED);
    assert_eq!(at(&image, 0.5, 0.5), GREEN);
    assert_eq!(at(&image, -0.5, -0.5), BLUE);
    assert_eq!(at(&image, 0.9, 0.9), GREEN, "the square's corner, outside the disc");
    assert_eq!(at(&image, 1.5, 0.0), BLACK);
}

/// Every part of the kit in one frame: a layered backdrop, a concave rock,
/// a stroked path, sprites from an atlas turned and tinted, a world drawn
/// as sprites, a letterboxed field, and labels on several anchors.
struct Kit {
    atlas: tickwork_engine::render::Texture,
}

impl Game for Kit {
    fn title(&self) -> &str {
        "kit"
    }

    fn setup(&mut self, stage: &mut Stage, _settings: &Settings) -> Result<(), GameError> {
        stage.camera = Camera::Field {
            center: Vec2::ZERO,
            size: Vec2::new(16.0, 9.0),
            fit: tickwork_engine::render::Fit::Letterbox,
        };
        stage.background = [20, 20, 30, 255];
        let mut world = tickwork_engine::World::default();
        for k in 0..5 {
            world.spawn(tickwork_engine::Particle {
                position: glam::Vec3::new(-6.0 + 1.2 * k as f32, -3.0, 0.0),
                radius: 0.5,
                colour: [255, 200 - 30 * k as u8, 80, 255],
                ..tickwork_engine::Particle::default()
            })?;
        }
        stage.add_world("coins", world).sprites(&self.atlas);
        Ok(())
    }

    fn draw(&self, _stage: &Stage, _alpha: f32, draw: &mut Draw) -> Result<(), GameError> {
        use tickwork_engine::render::{Anchor, Cap, Join, Stroke};
        draw.rect(Vec2::new(-8.0, -4.5), Vec2::new(8.0, 4.5), [30, 40, 60, 255]);
        let rock = [
            Vec2::new(-6.0, 1.0),
            Vec2::new(-4.0, 0.5),
            Vec2::new(-4.5, 2.0),
            Vec2::new(-3.5, 3.0),
            Vec2::new(-5.5, 3.5),
            Vec2::new(-5.0, 2.2),
        ];
        draw.polygon(&rock, [120, 110, 100, 255]);
        let path = [
            Vec2::new(-2.0, -1.0),
            Vec2::new(0.0, 2.0),
            Vec2::new(2.0, -1.0),
            Vec2::new(4.0, 2.0),
        ];
        draw.stroke(
            &path,
            false,
            Stroke::metres(0.3).join(Join::Miter).cap(Cap::Round),
            GREEN,
        );
        draw.sprite(&self.atlas, Vec2::new(5.0, 2.0), Vec2::splat(2.0))
            .rotation(0.4)
            .tint([255, 255, 255, 255]);
        draw.sprite(&self.atlas, Vec2::new(6.5, -1.0), Vec2::splat(1.0))
            .region([0, 0, 1, 1])
            .smooth();
        draw.layer(1);
        draw.rect(Vec2::new(-8.0, -4.5), Vec2::new(-2.5, -2.0), [0, 0, 0, 160]);
        draw.text("SCORE 1200", glam::Vec3::new(7.8, 4.3, 0.0))
            .anchor(Anchor::TopRight)
            .size_of_frame(0.08);
        draw.text("left\nand below", glam::Vec3::new(-7.8, 4.3, 0.0))
            .anchor(Anchor::TopLeft)
            .size_metres(0.5);
        draw.text("BOTTOM", glam::Vec3::new(0.0, -4.3, 0.0))
            .anchor(Anchor::Bottom)
            .size(12.0);
        Ok(())
    }
}

#[test]
fn the_game_kit_frame_matches_its_golden_image() {
    use tickwork_engine::render::{GoldenImages, Texture};
    let gpu = crate::support::gpu().clone();
    let pixels = [RED, GREEN, BLUE, [255, 255, 255, 255]].concat();
    let atlas = Texture::from_rgba(2, 2, pixels).expect("2 x 2");
    let mut session = GameSession::new(Kit { atlas }, SessionOptions::default()).expect("a session");
    let mut run = OffscreenRun::new(&gpu, 400, 300, renderer_config(session.stage(), 300)).expect("a target");
    let image = run.frame(&mut session, 1.0 / 60.0, true).expect("a frame");
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let golden = GoldenImages::new(root.join("assets/golden"), root.join("target/golden"));
    golden
        .check("game_kit", &image)
        .unwrap_or_else(|error| panic!("{error}"));
}

/// A red block far larger than the frame, clipped to a 4 m square, then a
/// green bar after the clip is lifted.
struct Clipped;

impl Game for Clipped {
    fn title(&self) -> &str {
        "clipped"
    }

    fn setup(&mut self, stage: &mut Stage, _settings: &Settings) -> Result<(), GameError> {
        black_stage(stage);
        Ok(())
    }

    fn draw(&self, _stage: &Stage, _alpha: f32, draw: &mut Draw) -> Result<(), GameError> {
        draw.clip(Some((Vec2::new(-2.0, -2.0), Vec2::new(2.0, 2.0))));
        draw.rect(Vec2::splat(-100.0), Vec2::splat(100.0), RED);
        draw.clip(None);
        draw.rect(Vec2::new(5.0, -4.0), Vec2::new(9.0, 4.0), GREEN);
        Ok(())
    }
}

#[test]
fn a_clip_rectangle_keeps_shapes_inside_it_until_lifted() {
    let gpu = crate::support::gpu().clone();
    let image = first_frame(&gpu, Clipped).expect("a frame");
    // 4 m at 10 px a metre: columns 80..120 on the middle row.
    let red: Vec<u32> = (0..WIDTH).filter(|&x| image.get_pixel(x, 50).0 == RED).collect();
    assert_eq!(red, (80..120).collect::<Vec<_>>());
    assert_eq!(at(&image, 0.0, 3.0), BLACK, "above the clip");
    assert_eq!(at(&image, 7.0, 0.0), GREEN, "after the clip is lifted");
}

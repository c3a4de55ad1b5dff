//! Hermite interpolation on the GPU (`Interpolation::Hermite`): a
//! projectile drawn between two steps lands on its arc, where lerp draws it
//! on the chord, by the quads and by the compute splat, and the GPU puts it
//! where the CPU twin (`Interpolation::position`) says; a game asks for it
//! through its stage and the runner passes the clock's step.
//!
//! These need a graphics adapter; `scripts/test` installs Mesa's software
//! Vulkan driver. Without an adapter they fail with the error that names the
//! packages; they never skip.
#![cfg(feature = "render")]

use glam::{Vec2, Vec3};
use tickwork_engine::app::{FrameSource, Game, GameError, GameSession, OffscreenRun, SessionOptions, Settings, Stage};
use tickwork_engine::interpolation::{Interpolation, hermite_from_end, lerp};
use tickwork_engine::render::{
    Camera, FrameView, OFFSCREEN_FORMAT, OffscreenTarget, Renderer, RendererConfig, RgbaImage,
};
use tickwork_engine::{ClockConfig, FixedClock, Gravity, Material, Particle, Plane, Rate, World, WorldConfig};

use crate::support::gpu;

/// The fixed step: 2 Hz, so the chord runs `g dt^2 / 8` = 0.31 m below
/// the arc half-way through a step.
const DT: f32 = 0.5;
const RATE_HZ: u32 = 2;
const G: f32 = 9.81;
const START: Vec3 = Vec3::new(-1.5, -1.0, 0.0);
const LAUNCH: Vec3 = Vec3::new(3.0, 4.0, 0.0);
const WIDTH: u32 = 320;
const HEIGHT: u32 = 180;

/// 4.5 m tall over 180 px: 40 px per metre, so the chord's 0.31 m is
/// 12.3 px.
fn camera() -> Camera {
    Camera::TwoD {
        center: Vec2::ZERO,
        height: 4.5,
    }
}

/// The exact arc `s` seconds after the launch.
fn arc(s: f32) -> Vec3 {
    START + LAUNCH * s + 0.5 * Vec3::new(0.0, -G, 0.0) * s * s
}

/// A ball of radius 0.05 m (2 px: small enough for the splat) launched from
/// `START` at `LAUNCH` under gravity and stepped once by `integrator`.
fn launched(integrator: &str) -> World {
    let mut world = World::new(WorldConfig {
        integrator: integrator.into(),
        ..WorldConfig::default()
    })
    .expect("integrator");
    world.add_force(Gravity::EARTH);
    world
        .spawn(Particle {
            position: START,
            velocity: LAUNCH,
            radius: 0.05,
            colour: [255, 255, 255, 255],
            ..Particle::default()
        })
        .expect("spawn");
    let mut clock = FixedClock::new(ClockConfig {
        rate: Rate::hz(RATE_HZ).expect("rate"),
        ..ClockConfig::default()
    })
    .expect("clock");
    for step in clock.step(1).fixed_steps() {
        world.step(step).expect("step");
    }
    world
}

/// The ball's previous and current position and its velocity.
fn columns(world: &World) -> (Vec3, Vec3, Vec3) {
    let particles = world.particles();
    let row = |column: &tickwork_engine::world::Vec3Column| Vec3::from(column.get(0).expect("one particle"));
    (
        row(&particles.previous_position),
        row(&particles.position),
        row(&particles.velocity),
    )
}

/// Quads only, or the compute splat for every frame.
fn config(splat: bool, interpolation: Interpolation) -> RendererConfig {
    RendererConfig {
        interpolation,
        splat_threshold: Some(if splat { 0 } else { usize::MAX }),
        ..RendererConfig::default()
    }
}

fn draw(renderer: &mut Renderer, world: &World, alpha: f32) -> RgbaImage {
    let target = OffscreenTarget::new(gpu(), WIDTH, HEIGHT, renderer.config().samples).expect("target");
    target
        .render(gpu(), renderer, &FrameView::new(world, alpha, camera()))
        .expect("frame")
}

/// Where `p` is on the image, in pixels (x right, y down, pixel centres at
/// +0.5).
fn pixel(p: Vec3) -> Vec2 {
    let ndc = camera().matrices(WIDTH, HEIGHT).view_proj.project_point3(p);
    Vec2::new((ndc.x + 1.0) * 0.5 * WIDTH as f32, (1.0 - ndc.y) * 0.5 * HEIGHT as f32)
}

/// The centre of the drawn ball: the centroid of the pixel centres
/// weighted by how much brighter than the background each pixel is.
fn centre(image: &RgbaImage) -> Vec2 {
    let background = RendererConfig::default().background;
    let (mut sum, mut weight) = (Vec2::ZERO, 0.0);
    for (x, y, p) in image.enumerate_pixels() {
        let w = f32::from(p.0[0].saturating_sub(background[0]));
        sum += w * Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
        weight += w;
    }
    assert!(weight > 0.0, "nothing drawn");
    sum / weight
}

/// Draws the ball at alpha 0.5 in lerp, Hermite, then lerp mode again
/// through one renderer, and checks where each lands.
fn hermite_lands_on_the_arc_and_lerp_on_the_chord(splat: bool) {
    let path = if splat { "splat" } else { "quads" };
    let world = launched("velocity_verlet");
    let (x0, x1, _) = columns(&world);
    // Velocity Verlet's step is exact under constant gravity.
    assert!(x0.abs_diff_eq(arc(0.0), 1e-6) && x1.abs_diff_eq(arc(DT), 1e-5));
    let (on_arc, on_chord) = (pixel(arc(0.5 * DT)), pixel(lerp(x0, x1, 0.5)));
    assert!(
        on_chord.y - on_arc.y > 12.0,
        "the chord should be 12.3 px below the arc: {on_chord} vs {on_arc}"
    );
    let mut renderer =
        Renderer::new(gpu(), OFFSCREEN_FORMAT, config(splat, Interpolation::Interpolate)).expect("renderer");
    let lerped = centre(&draw(&mut renderer, &world, 0.5));
    renderer.set_interpolation(Interpolation::Hermite { dt: DT });
    let curved = centre(&draw(&mut renderer, &world, 0.5));
    renderer.set_interpolation(Interpolation::Interpolate);
    let lerped_again = centre(&draw(&mut renderer, &world, 0.5));
    assert!(
        curved.distance(on_arc) < 0.5,
        "{path}: Hermite drew the ball at {curved}, the arc is at {on_arc}"
    );
    assert!(
        lerped.distance(on_chord) < 0.5 && lerped_again.distance(on_chord) < 0.5,
        "{path}: lerp drew the ball at {lerped} and {lerped_again}, the chord is at {on_chord}"
    );
    assert!(
        (lerped.y - on_arc.y).abs() > 11.5,
        "{path}: lerp should miss the arc's row by 12.3 px: {lerped} vs {on_arc}"
    );
}

#[test]
fn quads_drawn_by_hermite_land_on_the_projectiles_arc_and_by_lerp_on_its_chord() {
    hermite_lands_on_the_arc_and_lerp_on_the_chord(false);
}

#[test]
fn the_splat_drawn_by_hermite_lands_on_the_projectiles_arc_and_by_lerp_on_its_chord() {
    hermite_lands_on_the_arc_and_lerp_on_the_chord(true);
}

#[test]
fn the_gpu_draws_hermite_where_the_cpu_twin_places_it() {
    let world = launched("velocity_verlet");
    let (x0, x1, v1) = columns(&world);
    let mode = Interpolation::Hermite { dt: DT };
    for splat in [false, true] {
        let mut renderer = Renderer::new(gpu(), OFFSCREEN_FORMAT, config(splat, mode)).expect("renderer");
        for alpha in [0.2f32, 0.5, 0.8] {
            let cpu = mode.position(x0, x1, v1, mode.parameter(alpha));
            assert_eq!(cpu, hermite_from_end(x0, x1, v1, DT, alpha));
            let gpu = centre(&draw(&mut renderer, &world, alpha));
            assert!(
                gpu.distance(pixel(cpu)) < 0.5,
                "splat {splat}, alpha {alpha}: the GPU drew {gpu}, the CPU says {}",
                pixel(cpu)
            );
        }
    }
}

#[test]
fn the_end_velocity_recovers_the_arc_from_steps_exact_under_gravity_and_the_chord_from_semi_implicit_euler() {
    // The start velocity derived from (x0, x1, v1) is the launch velocity
    // when the step lies on the arc.
    for integrator in ["velocity_verlet", "leapfrog", "heun", "midpoint", "rk4"] {
        let (x0, x1, v1) = columns(&launched(integrator));
        for t in [0.25f32, 0.5, 0.75] {
            let drawn = hermite_from_end(x0, x1, v1, DT, t);
            assert!(
                drawn.abs_diff_eq(arc(t * DT), 1e-5),
                "{integrator}, t {t}: {drawn} is not on the arc {}",
                arc(t * DT)
            );
        }
    }
    // Semi-implicit Euler moves straight at its end velocity: Hermite has
    // nothing to bend, and the GPU draws the same frame both ways.
    let world = launched("semi_implicit_euler");
    let (x0, x1, v1) = columns(&world);
    assert!(hermite_from_end(x0, x1, v1, DT, 0.5).abs_diff_eq(lerp(x0, x1, 0.5), 1e-5));
    let frame = |interpolation| {
        let mut renderer = Renderer::new(gpu(), OFFSCREEN_FORMAT, config(false, interpolation)).expect("renderer");
        centre(&draw(&mut renderer, &world, 0.5))
    };
    let (hermite, lerped) = (
        frame(Interpolation::Hermite { dt: DT }),
        frame(Interpolation::Interpolate),
    );
    assert!(hermite.distance(lerped) < 0.05, "{hermite} vs {lerped}");
}

#[test]
fn a_ball_that_has_not_moved_yet_is_drawn_where_it_is_not_rocked_by_its_velocity() {
    // Spawned and not stepped: previous == current, at 10 m/s (the
    // tangents would draw it t (1 - t) dt v = 1.25 m, 50 px, behind).
    let mut world = World::default();
    world
        .spawn(Particle {
            position: START,
            velocity: Vec3::new(10.0, 0.0, 0.0),
            radius: 0.05,
            colour: [255, 255, 255, 255],
            ..Particle::default()
        })
        .expect("spawn");
    for splat in [false, true] {
        let drawn = drawn_by_hermite(&world, splat);
        assert!(drawn.distance(pixel(START)) < 0.5, "splat {splat}: {drawn}");
    }
}

/// Where a fresh Hermite renderer draws `world`'s ball half-way through
/// the step, by the quads or the splat.
fn drawn_by_hermite(world: &World, splat: bool) -> Vec2 {
    let mut renderer = Renderer::new(
        gpu(),
        OFFSCREEN_FORMAT,
        config(splat, Interpolation::Hermite { dt: DT }),
    )
    .expect("renderer");
    centre(&draw(&mut renderer, world, 0.5))
}

#[test]
fn a_ball_that_bounced_in_the_step_is_drawn_on_the_chord_not_below_the_floor() {
    // Falling at 6 m/s onto a floor 0.1 m below: the step ends on the floor
    // moving up, so the parabola from the end velocity would dip through it.
    let mut world = World::new(WorldConfig {
        integrator: "velocity_verlet".into(),
        ..WorldConfig::default()
    })
    .expect("world");
    world.add_force(Gravity::EARTH);
    // Found at the end of the step, which ends on the floor.
    world.add_collider(Plane {
        contact: tickwork_engine::colliders::ContactRule::EndOfStep,
        ..Plane::floor(
            -1.0,
            Material {
                restitution: 0.8,
                friction: 0.0,
            },
        )
    });
    world
        .spawn(Particle {
            position: Vec3::new(0.0, -0.85, 0.0),
            velocity: Vec3::new(0.0, -6.0, 0.0),
            radius: 0.05,
            colour: [255, 255, 255, 255],
            ..Particle::default()
        })
        .expect("spawn");
    world
        .step(tickwork_engine::FixedStep {
            tick: 0,
            time: 0.0,
            dt: f64::from(DT),
        })
        .expect("step");
    let (x0, x1, v1) = columns(&world);
    assert!(
        v1.y > 0.0 && (x1.y + 0.95).abs() < 1e-5,
        "bounced onto the floor: {x1} at {v1}"
    );
    let parabola = lerp(x0, x1, 0.5) + 0.25 * (x1 - x0 - DT * v1);
    assert!(
        pixel(parabola).y - pixel(x1).y > 10.0,
        "the parabola would be drawn below the floor"
    );
    let chord = pixel(lerp(x0, x1, 0.5));
    assert_eq!(
        Interpolation::Hermite { dt: DT }.position(x0, x1, v1, 0.5),
        lerp(x0, x1, 0.5),
        "the CPU twin draws the chord"
    );
    for splat in [false, true] {
        let drawn = drawn_by_hermite(&world, splat);
        assert!(
            drawn.distance(chord) < 0.5,
            "splat {splat}: drawn at {drawn}, the chord is at {chord}"
        );
    }
}

#[test]
fn a_hermite_step_that_is_not_finite_and_positive_is_refused() {
    for dt in [0.0, -0.1, f32::NAN, f32::INFINITY] {
        let error =
            Renderer::new(gpu(), OFFSCREEN_FORMAT, config(false, Interpolation::Hermite { dt })).expect_err("bad dt");
        assert_eq!(
            error.to_string(),
            format!(
                "renderer: Hermite interpolation needs the fixed step dt in seconds, finite and positive, got {dt}"
            )
        );
    }
    let mut renderer = Renderer::new(gpu(), OFFSCREEN_FORMAT, RendererConfig::default()).expect("renderer");
    renderer.set_interpolation(Interpolation::Hermite { dt: 0.0 });
    let target = OffscreenTarget::new(gpu(), 32, 32, 4).expect("target");
    let world = World::default();
    let error = target
        .render(gpu(), &mut renderer, &FrameView::new(&world, 0.0, camera()))
        .expect_err("bad dt");
    assert!(error.to_string().contains("got 0"), "{error}");
}

/// A game of one ball launched as in [`launched`], stepped by velocity
/// Verlet at 2 Hz, whose stage asks for Hermite drawing or not.
struct Lob {
    hermite: bool,
}

impl Game for Lob {
    fn title(&self) -> &str {
        "lob"
    }

    fn setup(&mut self, stage: &mut Stage, _: &Settings) -> Result<(), GameError> {
        let mut world = World::new(WorldConfig {
            integrator: "velocity_verlet".into(),
            ..WorldConfig::default()
        })?;
        world.add_force(Gravity::EARTH);
        world.spawn(Particle {
            position: START,
            velocity: LAUNCH,
            radius: 0.05,
            colour: [255, 255, 255, 255],
            ..Particle::default()
        })?;
        stage.add_world("lob", world);
        stage.rate = Rate::hz(RATE_HZ)?;
        stage.camera = camera();
        stage.hermite = self.hermite;
        Ok(())
    }
}

#[test]
fn a_game_whose_stage_asks_for_hermite_is_drawn_on_the_arc_by_the_runner() {
    for hermite in [true, false] {
        let mut session = GameSession::new(Lob { hermite }, SessionOptions::default()).expect("session");
        assert_eq!(
            session.interpolation(),
            hermite.then_some(Interpolation::Hermite { dt: DT }),
            "the session passes the clock's step"
        );
        // The renderer is set up for lerp; the session's choice wins.
        let mut run = OffscreenRun::new(gpu(), WIDTH, HEIGHT, config(false, Interpolation::Interpolate)).expect("run");
        // One and a half steps in frames of half a step (the clock's hitch
        // guard caps one frame at 0.25 s): one step run, drawn half-way to
        // the next.
        let mut image = None;
        for _ in 0..3 {
            image = Some(run.frame(&mut session, 0.5 * f64::from(DT), false).expect("frame"));
        }
        let drawn = centre(&image.expect("three frames"));
        assert_eq!(session.ticks(), 1);
        let expected = if hermite {
            pixel(arc(0.5 * DT))
        } else {
            pixel(lerp(arc(0.0), arc(DT), 0.5))
        };
        assert!(
            drawn.distance(expected) < 0.5,
            "hermite {hermite}: drawn at {drawn}, expected {expected}"
        );
    }
}

//! Off-screen render tests: golden images and numbers read off frames.
//!
//! These need a graphics adapter; `scripts/test` installs Mesa's software
//! Vulkan driver. Without an adapter they fail with the error that names the
//! packages; they never skip.
#![cfg(feature = "render")]

use std::path::PathBuf;
use std::sync::OnceLock;

use glam::{Quat, Vec2, Vec3};
use tickwork_engine::render::{
    Blend, Camera, FrameView, GoldenImages, Gpu, Interpolation, Line, OFFSCREEN_FORMAT, OffscreenTarget, Renderer,
    RendererConfig, RgbaImage, Trails,
};
use tickwork_engine::{FixedClock, Gravity, Particle, RigidBody, Scene, World};

fn gpu() -> &'static Gpu {
    static GPU: OnceLock<Gpu> = OnceLock::new();
    GPU.get_or_init(|| Gpu::headless().unwrap_or_else(|error| panic!("render tests need an adapter: {error}")))
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn golden() -> GoldenImages {
    GoldenImages::new(root().join("assets/golden"), root().join("target/golden"))
}

fn render(world: &World, alpha: f32, camera: Camera, width: u32, height: u32, config: RendererConfig) -> RgbaImage {
    let mut renderer = Renderer::new(gpu(), OFFSCREEN_FORMAT, config).expect("renderer");
    let target = OffscreenTarget::new(gpu(), width, height, renderer.config().samples).expect("target");
    target
        .render(gpu(), &mut renderer, &FrameView::new(world, alpha, camera))
        .expect("frame")
}

fn check(name: &str, image: &RgbaImage) {
    if let Err(error) = golden().check(name, image) {
        panic!("{error}");
    }
}

/// A 2D camera showing x in [-8, 8], y in [-4.5, 4.5] at 16:9.
fn camera_2d() -> Camera {
    Camera::TwoD {
        center: Vec2::ZERO,
        height: 9.0,
    }
}

/// Twelve particles: four sizes by three colours, one translucent.
fn layout() -> World {
    let mut world = World::default();
    let colours = [[230, 60, 50, 255], [60, 200, 90, 255], [70, 120, 240, 160]];
    for (i, radius) in [0.1_f32, 0.3, 0.6, 1.0].into_iter().enumerate() {
        for (j, colour) in colours.into_iter().enumerate() {
            world
                .spawn(Particle {
                    position: Vec3::new(-6.0 + 4.0 * i as f32, 2.5 - 2.5 * j as f32, 0.0),
                    radius,
                    colour,
                    ..Particle::default()
                })
                .expect("spawn");
        }
    }
    world
}

#[test]
fn particle_layout_matches_its_golden_image() {
    check(
        "layout",
        &render(&layout(), 0.0, camera_2d(), 320, 180, RendererConfig::default()),
    );
}

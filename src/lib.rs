//! Tickwork: a fixed-timestep game loop with pluggable, verified numerical
//! integrators. This facade re-exports the workspace's crates:
//!
//! - [`integrators`]: every time-integration method, by name, verified to its order;
//! - [`engine`]: the clock, world, forces, scenes and renderer.
//!
//! # Features
//!
//! A game takes what it uses; the default is what `tickwork new`'s game
//! needs (`window` and `cli`).
//!
//! | feature | what it adds | crates it brings |
//! |---|---|---|
//! | *(none)* | the simulation: clock, world, forces, colliders, scenes, headless runs | glam, rayon, serde, ron, rand |
//! | `render` | the wgpu renderer, shapes, sprites, off-screen frames and GIFs, golden images, the game API run off-screen | wgpu, image, lyon |
//! | `text` | `Draw::text`, `Draw::measure`, the HUD's lines (nothing draws text without it); implies `render` | glyphon |
//! | `window` (default) | a window (winit), or in a page its canvas; implies `render` | winit |
//! | `cli` (default) | `RunOptions` from the command line or a page's URL (`RunOptions::from_args`, `parse_args`) | clap |
//! | `panel` | the control panel (F1) over a window or page; implies `window` | egui, egui_plot |
//! | `netcode` | two-player rollback matches (`--host`, `--join`), `--sync-test` | ggrs, bincode |
//! | `audio` | `Sound` and `Stage::play`: decoded, deduplicated across rollbacks, silent | kira |
//! | `audio-device` | sound through the machine's audio device (a page always has Web Audio); needs `libasound2-dev` on Linux | cpal |
//! | `gamepad` | gamepads read by the window (a page always reads them); needs `libudev-dev` on Linux | gilrs |
//! | `tiled` | `TileMap`: maps made in the Tiled editor (`.tmx`), solid layers as merged boxes, `Draw::tiles`, objects and sensors; implies `render` | tiled, quick-xml |
//!
//! `tickwork = { version = "0.1", default-features = false, features =
//! ["window", "audio"] }` is a game with sound and no command line.
#![warn(missing_docs)]

#[doc(inline)]
pub use tickwork_engine as engine;
/// The math crate games use for vectors and rotations.
pub use tickwork_engine::glam;
#[doc(inline)]
pub use tickwork_integrators as integrators;
/// `sin`, `cos`, `exp`, ... with the same bits natively and in the browser:
/// call these in `fixed_update` for checksums that match across platforms.
pub use tickwork_integrators::math;

/// The README's examples, compiled and run as doctests so they never rot.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

/// The guide's examples, run as doctests too.
#[doc = include_str!("../docs/guide.md")]
#[cfg(doctest)]
pub struct GuideDoctests;

#[cfg(feature = "render")]
pub use tickwork_engine::app::{exit_code, run};

/// What a game needs, in one import: `use tickwork::prelude::*;`.
pub mod prelude {
    pub use crate::glam::{Quat, Vec2, Vec3};
    pub use crate::math;
    #[cfg(feature = "audio")]
    pub use tickwork_engine::app::Sound;
    #[cfg(feature = "cli")]
    pub use tickwork_engine::app::parse_args;
    #[cfg(feature = "render")]
    pub use tickwork_engine::app::{
        Draw, Game, GameError, OnFailure, RunOptions, RunSummary, Settings, Stage, Viewport, WorldId, exit_code, run,
    };
    pub use tickwork_engine::input::{Key, PadAxis, PadButton, TickInput};
    pub use tickwork_engine::interpolation::Interpolated;
    #[cfg(feature = "render")]
    pub use tickwork_engine::render::{Anchor, Animation, Camera, Cap, Fit, Follow, Join, Line, Stroke, Texture};
    #[cfg(feature = "tiled")]
    pub use tickwork_engine::tilemap::{MapObject, MapOptions, TileLayerId, TileMap};
    pub use tickwork_engine::{
        Attractor, BoxCollider, Character, CharacterConfig, CharacterId, ColliderId, Contact, ContactRule, Emitter,
        Entity, FixedStep, Frame, Gravity, Heading, LinearDrag, Material, Overlap, OverlapPhase, Particle, Plane,
        QuadraticDrag, Rate, Removal, RemovalCause, RigidBody, Sensor, SensorId, SphereCollisions, Spring, SpringEnd,
        Springs, StableHasher, Touched, Wind, World, WorldConfig,
    };
}

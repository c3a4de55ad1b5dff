//! The engine's integration tests, one module a subject, in one test binary
//! (one link of wgpu, not one a file). Apart: the allocation tests
//! (`tests/allocations/`, a counting global allocator) and the import
//! checker (`tests/modules.rs`, which reads the sources, not the engine).

mod character;
mod contacts;
mod game;
#[cfg(feature = "text")]
mod game_draw;
mod gpu_step;
mod headings;
mod hermite;
mod in_step;
mod layout;
#[cfg(feature = "netcode")]
mod network;
mod non_finite;
mod physics;
mod playback;
mod recordings;
mod render;
mod replay;
#[cfg(feature = "netcode")]
mod rollback;
mod scenes;
mod seams;
mod sensors;
#[cfg(all(feature = "audio", feature = "netcode"))]
mod sound;
mod spheres;
mod support;
#[cfg(feature = "tiled")]
mod tilemap;
mod world;

//! The game API, what every game is written against (the `render`
//! feature): [`Game`](crate::app::Game) and its errors, the
//! [`Stage`](crate::app::Stage) of worlds, [`Draw`](crate::app::Draw), the
//! viewer's [`Control`](crate::app::Control)s, and which backend steps a
//! world. It imports nothing else of `app/` but sounds.

pub(crate) mod backend;
pub(crate) mod control;
pub(crate) mod draw;
pub(crate) mod error;
pub(crate) mod game;
pub(crate) mod stage;
pub(crate) mod stage_world;

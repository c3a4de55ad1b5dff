//! What the runners show frame by frame ([`FrameSource`](crate::app::FrameSource)):
//! a game's [`GameSession`](crate::app::GameSession) (clock, input,
//! recording and replay, the fixed steps) and a scene's
//! [`Playback`](crate::app::Playback).

pub(crate) mod frame_rate;
pub(crate) mod game_session;
mod game_source;
pub(crate) mod options;
pub(crate) mod playback;
mod replay;
pub(crate) mod source;

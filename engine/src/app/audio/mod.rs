//! Sounds (the `audio` feature; kira lives only here): a
//! [`Sound`](crate::app::Sound) decoded once, and the mixer that starts each
//! at its tick once however often a rollback runs it, on the machine's
//! device with `audio-device`.

pub(crate) mod mixer;
pub(crate) mod sound;

//! Netcode (the `netcode` feature; GGRS and bincode live only here):
//! rollback ([`Rollback`], the sync test) and two players over the
//! network with it: a [`Lobby`] finds
//! the other player over UDP, or the two meet in a signalling server's
//! room (`--room`, WebRTC: the `webrtc` feature), a [`NetSession`] plays the match (every
//! machine runs the whole simulation, predicts the other's input, and
//! rolls back to re-run ticks when the real input differs), and an
//! [`ImpairedSocket`] makes the link as bad as asked, the same way every
//! run, for tests on one machine.
//!
//! Where it sits in the data flow: input per tick -> GGRS (sends ours,
//! predicts theirs) -> save, load and run ticks (GGRS's requests, on the
//! [`GameSession`]) -> the clock, which is given back the
//! ticks GGRS could not run yet. What a save holds is
//! [`SavedTick`](crate::app::SavedTick): the game (a clone), every world's
//! snapshot, and which worlds froze.
//!
//! [`GameSession`]: crate::app::GameSession

#[cfg(test)]
mod fuzz;
mod guard;
mod impairment;
mod link;
mod lobby;
mod match_report;
mod net_options;
pub(crate) mod rollback;
#[cfg(feature = "webrtc")]
mod room;
mod session;
mod transport;

pub use impairment::{ImpairedSocket, Impairment, ImpairmentCounts};
pub use link::PeerAddress;
pub use lobby::{Lobby, Peer};
pub use match_report::MatchReport;
pub use net_options::NetOptions;
pub use rollback::{MAX_CHECK_DISTANCE, Rollback, SavedTick, SyncTestReport, WireInput, sync_test};
pub use session::NetSession;
pub use transport::{MAX_DECODED_INPUT_BYTES, Welcome, decode_peer_message};

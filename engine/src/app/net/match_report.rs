//! [`MatchReport`]: what a networked match did, as
//! [`NetSession::report`](super::NetSession::report) gives it once the
//! match is over.

/// What a match did.
#[derive(Clone, Debug, PartialEq)]
pub struct MatchReport {
    /// The tick the match ended at (its final state is at the start of it).
    pub ticks: u64,
    /// The final state's checksum (the same on both sides).
    pub checksum: u64,
    /// States loaded to correct a misprediction.
    pub rollbacks: u64,
    /// Ticks run again after those loads.
    pub resimulated: u64,
    /// Due ticks that waited for the other player (prediction window full).
    pub waits: u64,
    /// Ticks skipped on GGRS's advice, to let the other side catch up.
    pub skipped: u64,
    /// Messages from the other peer that were neither GGRS's nor
    /// Tickwork's (malformed, or cut short past 4 KiB): dropped, never
    /// read, and counted here.
    pub dropped: u64,
    /// The game's outcome line.
    pub outcome: Option<String>,
}

//! [`NetOptions`]: how a match is played over the network (input delay,
//! prediction window, impairment, waits, checksum interval), with the
//! range of each, checked before a match starts.

use super::impairment::Impairment;
use crate::app::RunError;

/// How a match is played over the network.
#[derive(Clone, Debug, PartialEq)]
pub struct NetOptions {
    /// Ticks a player's input waits before it counts (default 2): hides
    /// that much latency without a rollback, at the price of that much lag.
    pub input_delay: usize,
    /// Ticks a side runs ahead on predicted input before it waits for the
    /// other (default 8, GGRS's default; 0 is lockstep).
    pub max_prediction: usize,
    /// Delay, jitter and loss laid on what this side sends (default none).
    pub impairment: Option<Impairment>,
    /// How long to wait for the other player to join, answer or
    /// synchronise, in seconds (default 60).
    pub wait_seconds: f64,
    /// Ticks between the peers' checksum comparisons (default 10: six a
    /// second at 60 Hz).
    pub desync_interval: u32,
    /// Seconds without word from the other player before it counts as
    /// gone (default 5: GGRS's 2 drops a peer that a busy machine stalls
    /// for a moment, and 5 still tells a player soon that the other left).
    pub disconnect_seconds: f64,
    /// In a room: the player this side plays, 1 (who hosts) or 2, whoever
    /// comes first (default `None`: the first to come hosts). Over UDP
    /// `--host` is player 1.
    pub player: Option<u8>,
}

impl Default for NetOptions {
    fn default() -> Self {
        Self {
            input_delay: 2,
            max_prediction: 8,
            impairment: None,
            wait_seconds: 60.0,
            desync_interval: 10,
            disconnect_seconds: 5.0,
            player: None,
        }
    }
}

impl NetOptions {
    /// The longest input delay: 8 ticks (past it the lag is plain to feel).
    pub const MAX_INPUT_DELAY: usize = 8;
    /// The widest prediction window: 16 ticks (a rollback then re-runs up
    /// to 16 ticks in one frame).
    pub const MAX_PREDICTION: usize = 16;
    /// The longest wait for the other player: a day.
    pub const MAX_WAIT_SECONDS: f64 = 86_400.0;

    /// Checks every field's range.
    ///
    /// # Errors
    /// [`RunError::Limit`] naming the field, its value and the range.
    pub fn check(&self) -> Result<(), RunError> {
        let limit = |field: &str, value: String, range: String| {
            Err(RunError::Limit(format!("{field} {value}: accepted {range}")))
        };
        if self.input_delay > Self::MAX_INPUT_DELAY {
            return limit(
                "--input-delay",
                self.input_delay.to_string(),
                format!("0 to {} ticks (NetOptions::MAX_INPUT_DELAY)", Self::MAX_INPUT_DELAY),
            );
        }
        if self.max_prediction > Self::MAX_PREDICTION {
            return limit(
                "--max-prediction",
                self.max_prediction.to_string(),
                format!("0 to {} ticks (NetOptions::MAX_PREDICTION)", Self::MAX_PREDICTION),
            );
        }
        if !(self.wait_seconds > 0.0 && self.wait_seconds <= Self::MAX_WAIT_SECONDS) {
            return limit(
                "--wait-seconds",
                self.wait_seconds.to_string(),
                format!(
                    "above 0, at most {} (NetOptions::MAX_WAIT_SECONDS)",
                    Self::MAX_WAIT_SECONDS
                ),
            );
        }
        if !(self.disconnect_seconds > 0.0 && self.disconnect_seconds <= Self::MAX_WAIT_SECONDS) {
            return limit(
                "disconnect_seconds",
                self.disconnect_seconds.to_string(),
                format!(
                    "above 0, at most {} (NetOptions::MAX_WAIT_SECONDS)",
                    Self::MAX_WAIT_SECONDS
                ),
            );
        }
        if let Some(player) = self.player.filter(|p| !(1..=2).contains(p)) {
            return limit(
                "--player",
                player.to_string(),
                "1 or 2 (a match is of two players)".into(),
            );
        }
        if self.desync_interval == 0 {
            return limit("desync_interval", "0".into(), "at least 1 tick".into());
        }
        if let Some(impairment) = &self.impairment {
            impairment
                .check()
                .map_err(|e| RunError::Limit(format!("--impair: {e}")))?;
        }
        Ok(())
    }
}

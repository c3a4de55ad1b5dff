//! A bad network on purpose: [`ImpairedSocket`] holds each message this
//! peer sends for `latency ± jitter` and drops a fraction `loss` of them,
//! from a seeded generator, so a match on one machine meets what a match
//! over the internet meets (late inputs, reordering, loss), the same way
//! in every run.
//!
//! The delay is drawn uniformly from `[latency - jitter, latency + jitter]`
//! (at least 0) per message, so messages overtake each other when the
//! jitter exceeds their spacing, as on a real route. Only the sending side
//! is impaired: give both peers `--impair` for a symmetric link.

use core::cmp::Ordering;
use core::fmt;
use core::str::FromStr;
use std::collections::BinaryHeap;
use std::hash::Hash;
use std::time::Duration;

use crate::platform::Instant;

use ggrs::{Message, NonBlockingSocket};
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg32;

/// Delay, jitter and loss of a link, and the seed of their draws.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Impairment {
    /// Mean one-way delay, in milliseconds (0 to 10 000).
    pub latency_ms: f64,
    /// Half the spread of the delay, in milliseconds (0 to the latency).
    pub jitter_ms: f64,
    /// Fraction of messages dropped (0 to 0.9).
    pub loss: f64,
    /// Seed of the delay and loss draws (default 0).
    pub seed: u64,
}

impl Impairment {
    /// The longest latency accepted: 10 s.
    pub const MAX_LATENCY_MS: f64 = 10_000.0;
    /// The largest loss accepted: 90% (past it GGRS's resends cannot keep a
    /// match alive).
    pub const MAX_LOSS: f64 = 0.9;

    /// Checks every field's range.
    ///
    /// # Errors
    /// The field, its value and the accepted range.
    pub fn check(&self) -> Result<(), String> {
        let fields = [
            ("latency", self.latency_ms, 0.0, Self::MAX_LATENCY_MS, "ms"),
            (
                "jitter",
                self.jitter_ms,
                0.0,
                self.latency_ms,
                "ms (at most the latency)",
            ),
            ("loss", self.loss, 0.0, Self::MAX_LOSS, "(a fraction)"),
        ];
        for (field, value, low, high, unit) in fields {
            if !(low..=high).contains(&value) {
                return Err(format!("{field} {value}: accepted {low} to {high} {unit}"));
            }
        }
        Ok(())
    }
}

impl FromStr for Impairment {
    type Err = String;

    /// `LATENCY_MS,JITTER_MS,LOSS[,SEED]`, for example `60,20,0.05`.
    fn from_str(text: &str) -> Result<Self, String> {
        let parts: Vec<&str> = text.split(',').map(str::trim).collect();
        if !(3..=4).contains(&parts.len()) {
            return Err(format!(
                "\"{text}\": expected LATENCY_MS,JITTER_MS,LOSS[,SEED], for example 60,20,0.05"
            ));
        }
        let number = |k: usize, name: &str| {
            parts[k]
                .parse::<f64>()
                .map_err(|e| format!("\"{text}\": the {name} \"{}\" is not a number ({e})", parts[k]))
        };
        let seed = match parts.get(3) {
            Some(seed) => seed
                .parse::<u64>()
                .map_err(|e| format!("\"{text}\": the seed \"{seed}\" is not a whole number ({e})"))?,
            None => 0,
        };
        let impairment = Self {
            latency_ms: number(0, "latency")?,
            jitter_ms: number(1, "jitter")?,
            loss: number(2, "loss")?,
            seed,
        };
        impairment.check().map_err(|e| format!("\"{text}\": {e}"))?;
        Ok(impairment)
    }
}

impl fmt::Display for Impairment {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} ms ± {} ms, {}% loss",
            self.latency_ms,
            self.jitter_ms,
            self.loss * 100.0
        )
    }
}

/// A message held until it is due.
#[derive(Debug)]
struct Held<A> {
    due: Duration,
    /// Order of sending, so that equal due times leave in sending order.
    order: u64,
    to: A,
    message: Message,
}

impl<A> PartialEq for Held<A> {
    fn eq(&self, other: &Self) -> bool {
        (self.due, self.order) == (other.due, other.order)
    }
}
impl<A> Eq for Held<A> {}
impl<A> PartialOrd for Held<A> {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl<A> Ord for Held<A> {
    /// Reversed, so that [`BinaryHeap`] pops the earliest due first.
    fn cmp(&self, other: &Self) -> Ordering {
        (other.due, other.order).cmp(&(self.due, self.order))
    }
}

/// What an [`ImpairedSocket`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ImpairmentCounts {
    /// Messages handed to the socket to send.
    pub sent: u64,
    /// Of them, dropped.
    pub dropped: u64,
}

/// A [`NonBlockingSocket`] that sends through `inner` late, out of order
/// and not at all, as an [`Impairment`] says. `now` is the time since the
/// socket was made (the wall clock, or a test's own).
pub struct ImpairedSocket<S, A> {
    inner: S,
    impairment: Impairment,
    random: Pcg32,
    held: BinaryHeap<Held<A>>,
    order: u64,
    counts: ImpairmentCounts,
    now: Box<dyn FnMut() -> Duration>,
}

impl<S, A> fmt::Debug for ImpairedSocket<S, A> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("ImpairedSocket")
            .field("impairment", &self.impairment)
            .field("held", &self.held.len())
            .field("counts", &self.counts)
            .finish_non_exhaustive()
    }
}

impl<S: NonBlockingSocket<A>, A: Clone + PartialEq + Eq + Hash> ImpairedSocket<S, A> {
    /// `inner` impaired, timed by the wall clock.
    pub fn new(inner: S, impairment: Impairment) -> Self {
        let start = Instant::now();
        Self::with_clock(inner, impairment, move || start.elapsed())
    }

    /// `inner` impaired, timed by `now` (for tests that step time themselves).
    pub fn with_clock(inner: S, impairment: Impairment, now: impl FnMut() -> Duration + 'static) -> Self {
        Self {
            inner,
            impairment,
            random: Pcg32::seed_from_u64(impairment.seed),
            held: BinaryHeap::new(),
            order: 0,
            counts: ImpairmentCounts::default(),
            now: Box::new(now),
        }
    }

    /// Messages sent and dropped so far.
    #[must_use]
    pub fn counts(&self) -> ImpairmentCounts {
        self.counts
    }

    /// Sends every held message that is due.
    fn release(&mut self) {
        let now = (self.now)();
        while self.held.peek().is_some_and(|held| held.due <= now) {
            if let Some(held) = self.held.pop() {
                self.inner.send_to(&held.message, &held.to);
            }
        }
    }
}

impl<S: NonBlockingSocket<A>, A: Clone + PartialEq + Eq + Hash> NonBlockingSocket<A> for ImpairedSocket<S, A> {
    fn send_to(&mut self, msg: &Message, addr: &A) {
        self.counts.sent += 1;
        // Both draws every time, so that the loss does not shift the delays.
        let lost = self.random.random::<f64>() < self.impairment.loss;
        let spread = self.random.random::<f64>() * 2.0 - 1.0;
        if lost {
            self.counts.dropped += 1;
        } else {
            let delay_ms = (self.impairment.latency_ms + spread * self.impairment.jitter_ms).max(0.0);
            let due = (self.now)() + Duration::from_secs_f64(delay_ms / 1000.0);
            self.order += 1;
            self.held.push(Held {
                due,
                order: self.order,
                to: addr.clone(),
                message: msg.clone(),
            });
        }
        self.release();
    }

    fn receive_all_messages(&mut self) -> Vec<(A, Message)> {
        self.release();
        self.inner.receive_all_messages()
    }
}

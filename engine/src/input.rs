//! Input events delivered per tick, and their recording for replays.
//!
//! A key pressed during a frame must be seen by exactly one fixed step. The
//! frame may run zero steps (the event must wait, not vanish) or several (the
//! event must not repeat). [`InputQueue`] holds events until the next step
//! begins and hands them all to that step only. Because the simulation then
//! depends on *which tick* saw an event, never on when frames happened, an
//! [`InputLog`] of `(tick, event)` pairs replays a run bit for bit.

use core::fmt;
use std::path::Path;

use serde::{Deserialize, Serialize};

/// Events waiting for the next fixed step.
#[derive(Clone, Debug)]
pub struct InputQueue<E> {
    pending: Vec<E>,
    current: Vec<E>,
}

impl<E> Default for InputQueue<E> {
    fn default() -> Self {
        Self {
            pending: Vec::new(),
            current: Vec::new(),
        }
    }
}

impl<E> InputQueue<E> {
    /// Adds an event; the next step to begin sees it.
    pub fn push(&mut self, event: E) {
        self.pending.push(event);
    }

    /// Called once at the start of every fixed step: returns the events that
    /// arrived since the previous step began (and forgets the previous ones).
    pub fn begin_step(&mut self) -> &[E] {
        self.current.clear();
        core::mem::swap(&mut self.pending, &mut self.current);
        &self.current
    }

    /// Events waiting for the next step.
    #[must_use]
    pub fn pending(&self) -> &[E] {
        &self.pending
    }
}

/// The events of a run, by tick, for recording and replaying.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(bound(serialize = "E: Serialize", deserialize = "E: Deserialize<'de>"))]
pub struct InputLog<E> {
    /// `(tick, event)` in tick order.
    pub events: Vec<(u64, E)>,
    #[serde(skip)]
    cursor: usize,
}

impl<E> Default for InputLog<E> {
    fn default() -> Self {
        Self {
            events: Vec::new(),
            cursor: 0,
        }
    }
}

/// A log file that could not be read or written.
#[derive(Debug)]
pub struct InputLogError {
    /// The file.
    pub path: String,
    /// What went wrong (with line and column for a malformed file).
    pub message: String,
}

impl fmt::Display for InputLogError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.path, self.message)
    }
}

impl std::error::Error for InputLogError {}

impl<E: Clone> InputLog<E> {
    /// Records the events a step saw.
    pub fn record(&mut self, tick: u64, events: &[E]) {
        self.events.extend(events.iter().map(|e| (tick, e.clone())));
    }

    /// The recorded events of `tick`, for replay. Ticks must be asked in
    /// increasing order (as steps run); earlier events are skipped.
    pub fn events_at(&mut self, tick: u64) -> &[(u64, E)] {
        while self.cursor < self.events.len() && self.events[self.cursor].0 < tick {
            self.cursor += 1;
        }
        let start = self.cursor;
        while self.cursor < self.events.len() && self.events[self.cursor].0 == tick {
            self.cursor += 1;
        }
        &self.events[start..self.cursor]
    }

    /// The last tick with an event, if any.
    #[must_use]
    pub fn last_tick(&self) -> Option<u64> {
        self.events.last().map(|(t, _)| *t)
    }
}

impl<E: Serialize + for<'de> Deserialize<'de> + Clone> InputLog<E> {
    /// Writes the log as RON. Refuses to overwrite an existing file unless `overwrite`.
    ///
    /// # Errors
    /// [`InputLogError`] if the file exists (and `overwrite` is false) or cannot be written.
    pub fn save(&self, path: &Path, overwrite: bool) -> Result<(), InputLogError> {
        let error = |message: String| InputLogError {
            path: path.display().to_string(),
            message,
        };
        if path.exists() && !overwrite {
            return Err(error("exists; not overwriting a recording without being asked".into()));
        }
        let text =
            ron::ser::to_string_pretty(self, ron::ser::PrettyConfig::default()).map_err(|e| error(e.to_string()))?;
        std::fs::write(path, text).map_err(|e| error(e.to_string()))
    }

    /// Reads a log written by [`save`](Self::save).
    ///
    /// # Errors
    /// [`InputLogError`] with the line and column of a malformed file.
    pub fn load(path: &Path) -> Result<Self, InputLogError> {
        let error = |message: String| InputLogError {
            path: path.display().to_string(),
            message,
        };
        let text = std::fs::read_to_string(path).map_err(|e| error(e.to_string()))?;
        ron::from_str(&text).map_err(|e| {
            error(format!(
                "line {}, column {}: {}",
                e.span.start.line, e.span.start.col, e.code
            ))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_event_is_seen_by_exactly_one_step() {
        let mut q = InputQueue::default();
        q.push('a');
        // A frame with zero steps: nothing begins, the event waits.
        assert_eq!(q.pending(), &['a']);
        q.push('b');
        // A frame with three steps: the first sees both, the others nothing.
        assert_eq!(q.begin_step(), &['a', 'b']);
        assert!(q.begin_step().is_empty());
        assert!(q.begin_step().is_empty());
        q.push('c');
        assert_eq!(q.begin_step(), &['c']);
    }

    #[test]
    fn logs_replay_by_tick() {
        let mut log = InputLog::default();
        log.record(3, &['x']);
        log.record(3, &['y']);
        log.record(7, &['z']);
        assert!(log.events_at(0).is_empty());
        assert_eq!(log.events_at(3), &[(3, 'x'), (3, 'y')]);
        assert!(log.events_at(4).is_empty());
        assert_eq!(log.events_at(7), &[(7, 'z')]);
        assert_eq!(log.last_tick(), Some(7));
    }
}

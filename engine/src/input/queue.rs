//! Window events handed to the fixed steps whose simulated time they
//! arrived in.
//!
//! An event that arrives during a frame is stamped with where in that frame
//! it arrived (`f`, 0 at the frame's start, 1 at its end). When the frame
//! advances the clock's present from `T0` to `T1` (simulated seconds, the
//! backlog included), the event's simulated time is
//!
//! ```text
//! tau = T0 + f (T1 - T0)
//! ```
//!
//! and it belongs to the tick whose window `[t_k, t_k + dt)` contains `tau`.
//! A frame that runs three steps gives an early event to its first step and
//! a late one to its last, and an event after the last step's window waits
//! for a later frame's: which tick sees a key depends on when it was
//! pressed, not on how the display's frames fell around it, so the delay
//! from a press to its tick is at most one step and does not jitter with
//! frame timing. (Handing every event to the next tick run, as game loops
//! usually do, makes that delay vary by up to a whole frame.)
//!
//! Presses and releases are latched: a tap shorter than a step is seen, as
//! pressed and released, by exactly one step (the one its press arrived
//! in), and a release by the step of its own arrival; a frame that runs no
//! step keeps its events waiting.

use std::collections::VecDeque;

use glam::Vec2;

use super::keys::{Key, KeySet};
use super::pad::{MAX_PADS, PadAxis, PadButton, PadButtons, PadInput, quantise};
use super::tick::TickInput;

/// One thing the player did, as the window saw it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum InputEvent {
    /// A key or mouse button went down (`down`) or up.
    Key {
        /// The key.
        key: Key,
        /// Down (pressed) or up (released).
        down: bool,
    },
    /// The pointer moved to this world point (on the `z = 0` plane).
    Pointer(Vec2),
    /// A gamepad's button went down (`down`) or up.
    PadButton {
        /// The pad (0 for the first connected; past [`MAX_PADS`] ignored).
        pad: u8,
        /// The button.
        button: PadButton,
        /// Down (pressed) or up (released).
        down: bool,
    },
    /// A gamepad's stick or trigger moved to `value` (in `[-1, 1]`).
    PadAxis {
        /// The pad (0 for the first connected; past [`MAX_PADS`] ignored).
        pad: u8,
        /// The axis.
        axis: PadAxis,
        /// Its new value.
        value: f32,
    },
}

/// Events waiting for the fixed step whose simulated time they arrived in,
/// and the key state they leave. Reuses its buffers: no allocation once
/// warm.
#[derive(Clone, Debug, Default)]
pub struct InputQueue {
    /// Arrived during the coming frame: the event and where in the frame.
    arrived: Vec<(InputEvent, f64)>,
    /// Stamped with simulated time, in arrival order.
    waiting: VecDeque<(InputEvent, f64)>,
    held: KeySet,
    pressed: KeySet,
    released: KeySet,
    pointer: Option<[f32; 2]>,
    pads: [PadInput; MAX_PADS],
}

impl InputQueue {
    /// Adds an event that arrived at `arrival` in the coming frame (0 at
    /// its start, 1 at its end; outside that, or NaN, it counts at the
    /// nearer end: the frame cannot place it better).
    pub fn push(&mut self, event: InputEvent, arrival: f64) {
        let arrival = if arrival.is_nan() { 0.0 } else { arrival.clamp(0.0, 1.0) };
        self.arrived.push((event, arrival));
    }

    /// Called once a frame has advanced the clock's present (simulated
    /// time plus backlog) from `from` to `to`: gives the frame's events
    /// their simulated times.
    pub fn stamp(&mut self, from: f64, to: f64) {
        for (event, arrival) in self.arrived.drain(..) {
            self.waiting.push_back((event, from + arrival * (to - from)));
        }
    }

    /// The input of the step that ends at simulated time `end`: the events
    /// stamped before `end` applied in order, presses and releases
    /// latched, the rest left waiting.
    pub fn tick(&mut self, end: f64) -> TickInput {
        while let Some(&(event, time)) = self.waiting.front() {
            if time >= end {
                break;
            }
            self.waiting.pop_front();
            match event {
                InputEvent::Key { key, down: true } => {
                    if !self.held.contains(key) {
                        self.pressed.insert(key);
                    }
                    self.held.insert(key);
                }
                InputEvent::Key { key, down: false } => {
                    if self.held.contains(key) {
                        self.released.insert(key);
                    }
                    self.held.remove(key);
                }
                InputEvent::Pointer(at) => self.pointer = Some(at.to_array()),
                InputEvent::PadButton { pad, button, down } => {
                    let Some(pad) = self.pads.get_mut(usize::from(pad)) else {
                        continue;
                    };
                    if down && !pad.held.contains(button) {
                        pad.pressed.insert(button);
                    }
                    if !down && pad.held.contains(button) {
                        pad.released.insert(button);
                    }
                    if down {
                        pad.held.insert(button);
                    } else {
                        pad.held.remove(button);
                    }
                }
                InputEvent::PadAxis { pad, axis, value } => {
                    if let Some(pad) = self.pads.get_mut(usize::from(pad)) {
                        pad.axes[axis as usize] = quantise(value);
                    }
                }
            }
        }
        let input = TickInput {
            held: self.held,
            pressed: self.pressed,
            released: self.released,
            pointer: self.pointer,
            pads: self.pads,
        };
        self.pressed = KeySet::EMPTY;
        self.released = KeySet::EMPTY;
        for pad in &mut self.pads {
            pad.pressed = PadButtons::default();
            pad.released = PadButtons::default();
        }
        input
    }

    /// Events not yet seen by a step (arrived or stamped).
    #[must_use]
    pub fn waiting(&self) -> usize {
        self.arrived.len() + self.waiting.len()
    }

    /// Forgets the waiting events, presses and releases (a restart starts
    /// a new timeline); keys still held stay held, and the pointer stays.
    pub fn restart(&mut self) {
        self.arrived.clear();
        self.waiting.clear();
        self.pressed = KeySet::EMPTY;
        self.released = KeySet::EMPTY;
        for pad in &mut self.pads {
            pad.pressed = PadButtons::default();
            pad.released = PadButtons::default();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DT: f64 = 1.0 / 60.0;

    fn key(key: Key, down: bool) -> InputEvent {
        InputEvent::Key { key, down }
    }

    #[test]
    fn gamepad_buttons_latch_per_tick_as_keys_do_and_axes_keep_their_last_value() {
        let mut queue = InputQueue::default();
        let button = |pad, button, down| InputEvent::PadButton { pad, button, down };
        // Pad 1 taps South within step 0; pad 0 holds East from step 1; the
        // left stick moves twice in step 0; pad 7 does not exist.
        queue.push(button(1, PadButton::South, true), 0.1);
        queue.push(button(1, PadButton::South, false), 0.2);
        queue.push(
            InputEvent::PadAxis {
                pad: 0,
                axis: PadAxis::LeftX,
                value: 0.3,
            },
            0.1,
        );
        queue.push(
            InputEvent::PadAxis {
                pad: 0,
                axis: PadAxis::LeftX,
                value: -0.5,
            },
            0.2,
        );
        queue.push(button(0, PadButton::East, true), 0.5);
        queue.push(button(7, PadButton::North, true), 0.5);
        queue.stamp(0.0, 3.0 * DT);
        let steps: Vec<TickInput> = (1..=3).map(|k| queue.tick(f64::from(k) * DT)).collect();
        let tap = steps[0].pad(1);
        assert!(tap.pressed(PadButton::South) && tap.released(PadButton::South) && !tap.held(PadButton::South));
        assert_eq!(steps[0].pad(0).axes[0], quantise(-0.5), "the last value in the step");
        assert!((steps[0].pad(0).axis(PadAxis::LeftX) + 0.5).abs() < 1e-4);
        assert!(steps[1].pad(0).pressed(PadButton::East) && steps[1].pad(0).held(PadButton::East));
        assert!(!steps[2].pad(0).pressed(PadButton::East) && steps[2].pad(0).held(PadButton::East));
        assert_eq!(steps[2].pad(0).axes[0], quantise(-0.5), "kept");
        assert!(steps.iter().all(|s| s.pad(7).is_idle()), "no eighth pad");
        // A recording keeps the pads and reads them back; one without pads
        // (every recording before them) still reads.
        let text = ron::to_string(&steps[1]).expect("serialises");
        assert_eq!(ron::from_str::<TickInput>(&text).expect("reads back"), steps[1]);
        let keys_only = ron::to_string(&TickInput::default()).expect("serialises");
        assert!(!keys_only.contains("pads"), "{keys_only}");
    }

    #[test]
    fn a_frame_of_three_steps_gives_each_event_to_the_step_it_arrived_in() {
        let mut queue = InputQueue::default();
        // A frame of 3 dt: a tap at its start, a press at 0.5 (step 1) and
        // its release at 0.9 (step 2).
        queue.push(key(Key::Space, true), 0.0);
        queue.push(key(Key::Space, false), 0.01);
        queue.push(key(Key::Up, true), 0.5);
        queue.push(key(Key::Up, false), 0.9);
        queue.stamp(0.0, 3.0 * DT);
        let steps: Vec<TickInput> = (1..=3).map(|k| queue.tick(f64::from(k) * DT)).collect();
        assert!(steps[0].pressed(Key::Space) && !steps[0].held(Key::Space));
        assert!(!steps[0].pressed(Key::Up));
        assert!(steps[1].pressed(Key::Up) && steps[1].held(Key::Up));
        assert!(!steps[2].held(Key::Up) && !steps[2].pressed(Key::Up));
        assert_eq!(queue.waiting(), 0);
    }

    #[test]
    fn an_event_past_the_last_step_of_its_frame_waits_for_its_own() {
        let mut queue = InputQueue::default();
        // A frame of 1.5 dt runs one step; the event at 0.9 is at 1.35 dt.
        queue.push(key(Key::Left, true), 0.9);
        queue.push(InputEvent::Pointer(Vec2::new(1.0, 2.0)), 0.9);
        queue.stamp(0.0, 1.5 * DT);
        assert_eq!(queue.tick(DT), TickInput::default());
        assert_eq!(queue.waiting(), 2);
        // The next frame (no events of its own) runs step 1.
        queue.stamp(1.5 * DT, 2.2 * DT);
        let input = queue.tick(2.0 * DT);
        assert!(input.pressed(Key::Left));
        assert_eq!(input.pointer_at(), Some(Vec2::new(1.0, 2.0)));
        assert_eq!(queue.tick(3.0 * DT).carried(), input.carried());
    }

    #[test]
    fn a_tap_within_one_step_is_pressed_and_released_in_that_tick_only() {
        let mut queue = InputQueue::default();
        // One frame of 2 dt: Space down at 0.6 dt and up at 0.8 dt, both in
        // the first step's window.
        queue.push(key(Key::Space, true), 0.3);
        queue.push(key(Key::Space, false), 0.4);
        queue.stamp(0.0, 2.0 * DT);
        let first = queue.tick(DT);
        assert!(first.pressed(Key::Space), "{first:?}");
        assert!(first.released(Key::Space), "{first:?}");
        assert!(!first.held(Key::Space), "up again by the step's end: {first:?}");
        let second = queue.tick(2.0 * DT);
        assert_eq!(second, TickInput::default(), "seen once");
        assert_eq!(queue.waiting(), 0);
    }

    #[test]
    fn a_release_spanning_ticks_lands_in_the_tick_of_its_arrival() {
        let mut queue = InputQueue::default();
        // A frame of 4 dt: Right down at 0.5 dt (step 0), up at 2.6 dt
        // (step 2).
        queue.push(key(Key::Right, true), 0.125);
        queue.push(key(Key::Right, false), 0.65);
        queue.stamp(0.0, 4.0 * DT);
        let steps: Vec<TickInput> = (1..=4).map(|k| queue.tick(f64::from(k) * DT)).collect();
        let seen = |f: fn(&TickInput, Key) -> bool| -> Vec<bool> { steps.iter().map(|s| f(s, Key::Right)).collect() };
        assert_eq!(seen(TickInput::pressed), [true, false, false, false]);
        assert_eq!(seen(TickInput::held), [true, true, false, false]);
        assert_eq!(seen(TickInput::released), [false, false, true, false]);
        // A release whose time is past the frame's last step waits for the
        // next frame's step of its time, like a press.
        queue.push(key(Key::Right, true), 0.0);
        queue.push(key(Key::Right, false), 0.9);
        queue.stamp(4.0 * DT, 5.5 * DT);
        let held = queue.tick(5.0 * DT);
        assert!(held.pressed(Key::Right) && held.held(Key::Right) && !held.released(Key::Right));
        queue.stamp(5.5 * DT, 6.5 * DT);
        let up = queue.tick(6.0 * DT);
        assert!(up.released(Key::Right) && !up.held(Key::Right) && !up.pressed(Key::Right));
        // A release of a key that was not down is no release.
        queue.push(key(Key::Left, false), 0.0);
        queue.stamp(6.5 * DT, 7.5 * DT);
        assert!(!queue.tick(7.0 * DT).released(Key::Left));
    }

    #[test]
    fn arrivals_outside_the_frame_count_at_its_ends() {
        let mut queue = InputQueue::default();
        queue.push(key(Key::A, true), f64::NAN);
        queue.push(key(Key::D, true), 7.0);
        queue.stamp(0.0, 2.0 * DT);
        assert!(queue.tick(DT).pressed(Key::A));
        // Arrived "after" the frame: at its end, 2 dt, the third step's.
        assert!(!queue.tick(2.0 * DT).pressed(Key::D));
        assert!(queue.tick(3.0 * DT).pressed(Key::D));
    }
}

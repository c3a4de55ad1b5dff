//! Gamepads for the window, through gilrs (the `gamepad` feature): each
//! button and stick event of the first [`MAX_PADS`] pads connected becomes
//! an input event of the pad's slot, stamped when it was polled (each
//! frame), so the queue latches it into a tick as it does keys. Without
//! the feature there is no pad to poll.

use crate::input::InputEvent;
#[cfg(feature = "gamepad")]
use crate::input::{MAX_PADS, PadAxis, PadButton};
use crate::platform::Instant;

/// The window's gamepads (none without the `gamepad` feature).
pub(super) struct Gamepads {
    #[cfg(feature = "gamepad")]
    gilrs: Option<gilrs::Gilrs>,
    /// The pads in their slots, by gilrs's id (the order they connected).
    #[cfg(feature = "gamepad")]
    slots: Vec<gilrs::GamepadId>,
}

impl Gamepads {
    /// Opens the gamepad library; where it cannot start, says so in one
    /// line and polls nothing.
    pub(super) fn open() -> Self {
        #[cfg(feature = "gamepad")]
        {
            let gilrs = match gilrs::Gilrs::new() {
                Ok(gilrs) => Some(gilrs),
                Err(error) => {
                    crate::platform::say(&format!("tickwork: no gamepads: {error}"));
                    None
                }
            };
            let mut pads = Self {
                gilrs,
                slots: Vec::new(),
            };
            if let Some(gilrs) = &pads.gilrs {
                pads.slots = gilrs.gamepads().map(|(id, _)| id).take(MAX_PADS).collect();
            }
            pads
        }
        #[cfg(not(feature = "gamepad"))]
        Self {}
    }

    /// The pad events since the last poll, each as the input event of its
    /// pad's slot, stamped now.
    pub(super) fn poll(&mut self, out: &mut Vec<(InputEvent, Instant)>) {
        #[cfg(feature = "gamepad")]
        {
            let Some(gilrs) = &mut self.gilrs else {
                return;
            };
            while let Some(gilrs::Event { id, event, .. }) = gilrs.next_event() {
                if matches!(event, gilrs::EventType::Connected)
                    && !self.slots.contains(&id)
                    && self.slots.len() < MAX_PADS
                {
                    self.slots.push(id);
                }
                let Some(slot) = self.slots.iter().position(|s| *s == id) else {
                    continue;
                };
                let pad = u8::try_from(slot).unwrap_or(u8::MAX);
                let input = match event {
                    gilrs::EventType::ButtonPressed(button, _) => {
                        button_of(button).map(|button| InputEvent::PadButton {
                            pad,
                            button,
                            down: true,
                        })
                    }
                    gilrs::EventType::ButtonReleased(button, _) => {
                        button_of(button).map(|button| InputEvent::PadButton {
                            pad,
                            button,
                            down: false,
                        })
                    }
                    gilrs::EventType::AxisChanged(axis, value, _) => {
                        axis_of(axis).map(|axis| InputEvent::PadAxis { pad, axis, value })
                    }
                    gilrs::EventType::ButtonChanged(gilrs::Button::LeftTrigger2, value, _) => {
                        Some(InputEvent::PadAxis {
                            pad,
                            axis: PadAxis::LeftTrigger,
                            value,
                        })
                    }
                    gilrs::EventType::ButtonChanged(gilrs::Button::RightTrigger2, value, _) => {
                        Some(InputEvent::PadAxis {
                            pad,
                            axis: PadAxis::RightTrigger,
                            value,
                        })
                    }
                    _ => None,
                };
                out.extend(input.map(|event| (event, Instant::now())));
            }
        }
        #[cfg(not(feature = "gamepad"))]
        let _ = out;
    }
}

/// The pad button of a gilrs button, if it is one.
#[cfg(feature = "gamepad")]
fn button_of(button: gilrs::Button) -> Option<PadButton> {
    use gilrs::Button as B;
    Some(match button {
        B::South => PadButton::South,
        B::East => PadButton::East,
        B::West => PadButton::West,
        B::North => PadButton::North,
        B::LeftTrigger => PadButton::LeftBumper,
        B::RightTrigger => PadButton::RightBumper,
        B::LeftTrigger2 => PadButton::LeftTrigger,
        B::RightTrigger2 => PadButton::RightTrigger,
        B::Select => PadButton::Select,
        B::Start => PadButton::Start,
        B::LeftThumb => PadButton::LeftStick,
        B::RightThumb => PadButton::RightStick,
        B::DPadUp => PadButton::DPadUp,
        B::DPadDown => PadButton::DPadDown,
        B::DPadLeft => PadButton::DPadLeft,
        B::DPadRight => PadButton::DPadRight,
        _ => return None,
    })
}

/// The pad axis of a gilrs axis, if it is one.
#[cfg(feature = "gamepad")]
fn axis_of(axis: gilrs::Axis) -> Option<PadAxis> {
    use gilrs::Axis as A;
    Some(match axis {
        A::LeftStickX => PadAxis::LeftX,
        A::LeftStickY => PadAxis::LeftY,
        A::RightStickX => PadAxis::RightX,
        A::RightStickY => PadAxis::RightY,
        A::LeftZ => PadAxis::LeftTrigger,
        A::RightZ => PadAxis::RightTrigger,
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    #[cfg(feature = "gamepad")]
    use super::*;

    #[cfg(feature = "gamepad")]
    #[test]
    fn every_pad_button_and_axis_has_a_gilrs_source() {
        use gilrs::{Axis as A, Button as B};
        let buttons = [
            B::South,
            B::East,
            B::West,
            B::North,
            B::LeftTrigger,
            B::RightTrigger,
            B::LeftTrigger2,
            B::RightTrigger2,
            B::Select,
            B::Start,
            B::LeftThumb,
            B::RightThumb,
            B::DPadUp,
            B::DPadDown,
            B::DPadLeft,
            B::DPadRight,
        ];
        let mapped: Vec<PadButton> = buttons.into_iter().filter_map(button_of).collect();
        assert_eq!(mapped, PadButton::ALL);
        let axes = [
            A::LeftStickX,
            A::LeftStickY,
            A::RightStickX,
            A::RightStickY,
            A::LeftZ,
            A::RightZ,
        ];
        assert_eq!(axes.into_iter().filter_map(axis_of).count(), 6);
        assert_eq!(button_of(B::Mode), None);
    }
}

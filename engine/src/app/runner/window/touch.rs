//! Touch as the mouse: one finger on a touch screen is the left button and
//! the pointer, as macroquad and egui treat it, so a game written for the
//! mouse (Breakout's paddle, a click to start) plays on a phone unchanged.
//! Only the first finger down counts until it lifts; others are ignored.
//! (A pure mapping, tested without a window.)

use winit::event::TouchPhase;

/// What a touch means to the mouse.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Mouse {
    /// The pointer moves to this position (physical pixels).
    Move(f64, f64),
    /// The left button goes down.
    Press,
    /// The left button comes up.
    Release,
}

/// Follows which finger stands for the mouse.
#[derive(Debug, Default)]
pub(super) struct TouchMouse {
    /// The finger that is the mouse while it is down.
    finger: Option<u64>,
}

impl TouchMouse {
    /// The mouse events (at most two, in order) that finger `id` doing
    /// `phase` at `(x, y)` stands for.
    pub(super) fn map(&mut self, id: u64, phase: TouchPhase, (x, y): (f64, f64)) -> [Option<Mouse>; 2] {
        match phase {
            TouchPhase::Started if self.finger.is_none() => {
                self.finger = Some(id);
                [Some(Mouse::Move(x, y)), Some(Mouse::Press)]
            }
            TouchPhase::Moved if self.finger == Some(id) => [Some(Mouse::Move(x, y)), None],
            TouchPhase::Ended | TouchPhase::Cancelled if self.finger == Some(id) => {
                self.finger = None;
                [Some(Mouse::Move(x, y)), Some(Mouse::Release)]
            }
            _ => [None, None],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_finger_is_the_mouse_until_it_lifts() {
        let mut touch = TouchMouse::default();
        assert_eq!(
            touch.map(7, TouchPhase::Started, (10.0, 20.0)),
            [Some(Mouse::Move(10.0, 20.0)), Some(Mouse::Press)]
        );
        // A second finger changes nothing while the first is down.
        assert_eq!(touch.map(8, TouchPhase::Started, (50.0, 50.0)), [None, None]);
        assert_eq!(touch.map(8, TouchPhase::Moved, (60.0, 50.0)), [None, None]);
        assert_eq!(touch.map(8, TouchPhase::Ended, (60.0, 50.0)), [None, None]);
        assert_eq!(
            touch.map(7, TouchPhase::Moved, (12.0, 21.0)),
            [Some(Mouse::Move(12.0, 21.0)), None]
        );
        assert_eq!(
            touch.map(7, TouchPhase::Ended, (13.0, 22.0)),
            [Some(Mouse::Move(13.0, 22.0)), Some(Mouse::Release)]
        );
        // Then the next finger down is the mouse.
        assert_eq!(
            touch.map(9, TouchPhase::Started, (1.0, 2.0)),
            [Some(Mouse::Move(1.0, 2.0)), Some(Mouse::Press)]
        );
        assert_eq!(
            touch.map(9, TouchPhase::Cancelled, (1.0, 2.0)),
            [Some(Mouse::Move(1.0, 2.0)), Some(Mouse::Release)]
        );
        // A finger that moves or lifts without having started is ignored.
        assert_eq!(touch.map(3, TouchPhase::Moved, (0.0, 0.0)), [None, None]);
        assert_eq!(touch.map(3, TouchPhase::Ended, (0.0, 0.0)), [None, None]);
    }
}

//! The window's keys: which physical keys are game keys, and what the
//! runner's own keys do (pure mappings, tested without a window).

use winit::keyboard::{Key, KeyCode, NamedKey, PhysicalKey};

use super::super::control::Control;
use crate::input::Key as GameKey;

/// What one of the runner's keys asks for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum KeyAction {
    /// Escape: close the window.
    Quit,
    /// F12: save a screenshot.
    Screenshot,
    /// F1: show or hide the control panel.
    TogglePanel,
    /// A control for the source (pause, step, time scale, integrator, restart).
    Control(Control),
}

/// Whether a held key repeats its action: single step and the time scale
/// may, the toggles (F1, pause, integrator, restart, F12) act once a press.
/// (Under load, the X server's autorepeat turned one F1 into two, and the
/// panel came back.)
pub(super) fn repeatable(key: PhysicalKey) -> bool {
    matches!(
        key,
        PhysicalKey::Code(
            KeyCode::Period | KeyCode::NumpadAdd | KeyCode::NumpadSubtract | KeyCode::Equal | KeyCode::Minus
        )
    )
}

/// The runner's action for a key (by its meaning, `logical`, or its place
/// on the keyboard, `physical`), if it has one.
pub(super) fn key_action(logical: &Key, physical: PhysicalKey) -> Option<KeyAction> {
    let control = match (logical, physical) {
        (Key::Named(NamedKey::Escape), _) => return Some(KeyAction::Quit),
        (Key::Named(NamedKey::F12), _) => return Some(KeyAction::Screenshot),
        (Key::Named(NamedKey::F1), _) => return Some(KeyAction::TogglePanel),
        (Key::Named(NamedKey::Space), _) | (_, PhysicalKey::Code(KeyCode::KeyP)) => Control::TogglePause,
        (Key::Named(NamedKey::Tab), _) => Control::NextIntegrator,
        (_, PhysicalKey::Code(KeyCode::Period)) => Control::SingleStep,
        (_, PhysicalKey::Code(KeyCode::NumpadAdd)) => Control::Faster,
        (_, PhysicalKey::Code(KeyCode::NumpadSubtract)) => Control::Slower,
        (_, PhysicalKey::Code(KeyCode::KeyR | KeyCode::F5)) => Control::Reset,
        (Key::Character(c), _) => match c.as_str() {
            "+" | "=" => Control::Faster,
            "-" | "_" => Control::Slower,
            d if d.len() == 1 && ("1"..="9").contains(&d) => Control::Integrator(usize::from(d.as_bytes()[0] - b'1')),
            _ => return None,
        },
        _ => return None,
    };
    Some(KeyAction::Control(control))
}

/// The game key of a physical key, if it is one.
pub(super) fn game_key(key: PhysicalKey) -> Option<GameKey> {
    let PhysicalKey::Code(code) = key else {
        return None;
    };
    Some(match code {
        KeyCode::ArrowLeft => GameKey::Left,
        KeyCode::ArrowRight => GameKey::Right,
        KeyCode::ArrowUp => GameKey::Up,
        KeyCode::ArrowDown => GameKey::Down,
        KeyCode::Space => GameKey::Space,
        KeyCode::Enter | KeyCode::NumpadEnter => GameKey::Enter,
        KeyCode::ShiftLeft | KeyCode::ShiftRight => GameKey::Shift,
        KeyCode::KeyW => GameKey::W,
        KeyCode::KeyA => GameKey::A,
        KeyCode::KeyS => GameKey::S,
        KeyCode::KeyD => GameKey::D,
        KeyCode::KeyQ => GameKey::Q,
        KeyCode::KeyE => GameKey::E,
        KeyCode::KeyR => GameKey::R,
        KeyCode::KeyF => GameKey::F,
        KeyCode::KeyZ => GameKey::Z,
        KeyCode::KeyX => GameKey::X,
        KeyCode::KeyC => GameKey::C,
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runner_keys_map_to_their_actions_and_digits_to_integrators() {
        let code = PhysicalKey::Code;
        let none = code(KeyCode::F24);
        assert_eq!(
            key_action(&Key::Named(NamedKey::F1), none),
            Some(KeyAction::TogglePanel)
        );
        assert_eq!(key_action(&Key::Named(NamedKey::Escape), none), Some(KeyAction::Quit));
        assert_eq!(
            key_action(&Key::Character("3".into()), code(KeyCode::Digit3)),
            Some(KeyAction::Control(Control::Integrator(2)))
        );
        assert_eq!(
            key_action(&Key::Character("r".into()), code(KeyCode::KeyR)),
            Some(KeyAction::Control(Control::Reset))
        );
        assert_eq!(key_action(&Key::Character("0".into()), code(KeyCode::Digit0)), None);
        assert!(repeatable(code(KeyCode::Period)) && !repeatable(code(KeyCode::F1)));
        assert_eq!(game_key(code(KeyCode::ArrowLeft)), Some(GameKey::Left));
        assert_eq!(game_key(code(KeyCode::F5)), None);
    }
}

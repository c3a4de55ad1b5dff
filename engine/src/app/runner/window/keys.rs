//! The window's keys: which physical keys are game keys, and what the
//! runner's own keys do (pure mappings, tested without a window).

use winit::keyboard::{Key, KeyCode, NamedKey, PhysicalKey};

use crate::app::api::control::Control;
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

/// Whether `key` has a control of the runner's when pressed without Ctrl
/// (it reaches a game only if the game claims it).
pub(super) fn runner_owned(key: GameKey) -> bool {
    matches!(
        key,
        GameKey::P
            | GameKey::Tab
            | GameKey::Escape
            | GameKey::F1
            | GameKey::F5
            | GameKey::F12
            | GameKey::Digit1
            | GameKey::Digit2
            | GameKey::Digit3
            | GameKey::Digit4
            | GameKey::Digit5
            | GameKey::Digit6
            | GameKey::Digit7
            | GameKey::Digit8
            | GameKey::Digit9
    )
}

/// The game key `physical` gives a source that takes input (`takes_input`)
/// and claimed `claimed` of the runner's keys; `None` where the key is the
/// runner's.
pub(super) fn game_key_for(physical: PhysicalKey, takes_input: bool, claimed: crate::input::KeySet) -> Option<GameKey> {
    let key = game_key(physical)?;
    let taken = !runner_owned(key) || claimed.contains(key);
    (takes_input && taken).then_some(key)
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
        KeyCode::KeyB => GameKey::B,
        KeyCode::KeyG => GameKey::G,
        KeyCode::KeyH => GameKey::H,
        KeyCode::KeyI => GameKey::I,
        KeyCode::KeyJ => GameKey::J,
        KeyCode::KeyK => GameKey::K,
        KeyCode::KeyL => GameKey::L,
        KeyCode::KeyM => GameKey::M,
        KeyCode::KeyN => GameKey::N,
        KeyCode::KeyO => GameKey::O,
        KeyCode::KeyP => GameKey::P,
        KeyCode::KeyT => GameKey::T,
        KeyCode::KeyU => GameKey::U,
        KeyCode::KeyV => GameKey::V,
        KeyCode::KeyY => GameKey::Y,
        KeyCode::Digit0 => GameKey::Digit0,
        KeyCode::Digit1 => GameKey::Digit1,
        KeyCode::Digit2 => GameKey::Digit2,
        KeyCode::Digit3 => GameKey::Digit3,
        KeyCode::Digit4 => GameKey::Digit4,
        KeyCode::Digit5 => GameKey::Digit5,
        KeyCode::Digit6 => GameKey::Digit6,
        KeyCode::Digit7 => GameKey::Digit7,
        KeyCode::Digit8 => GameKey::Digit8,
        KeyCode::Digit9 => GameKey::Digit9,
        KeyCode::Escape => GameKey::Escape,
        KeyCode::Tab => GameKey::Tab,
        KeyCode::Backspace => GameKey::Backspace,
        KeyCode::F1 => GameKey::F1,
        KeyCode::F2 => GameKey::F2,
        KeyCode::F3 => GameKey::F3,
        KeyCode::F4 => GameKey::F4,
        KeyCode::F5 => GameKey::F5,
        KeyCode::F6 => GameKey::F6,
        KeyCode::F7 => GameKey::F7,
        KeyCode::F8 => GameKey::F8,
        KeyCode::F9 => GameKey::F9,
        KeyCode::F10 => GameKey::F10,
        KeyCode::F11 => GameKey::F11,
        KeyCode::F12 => GameKey::F12,
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
        assert_eq!(game_key(code(KeyCode::F5)), Some(GameKey::F5));
        assert_eq!(game_key(code(KeyCode::KeyP)), Some(GameKey::P));
        assert_eq!(game_key(code(KeyCode::Digit7)), Some(GameKey::Digit7));
        assert_eq!(game_key(code(KeyCode::ControlLeft)), None, "Ctrl is the runner's");
        // Every game key but the mouse buttons has a physical key.
        let mut codes = vec![
            KeyCode::ArrowLeft,
            KeyCode::ArrowRight,
            KeyCode::ArrowUp,
            KeyCode::ArrowDown,
            KeyCode::Space,
            KeyCode::Enter,
            KeyCode::ShiftLeft,
            KeyCode::Escape,
            KeyCode::Tab,
            KeyCode::Backspace,
        ];
        codes.extend([
            KeyCode::KeyA,
            KeyCode::KeyB,
            KeyCode::KeyC,
            KeyCode::KeyD,
            KeyCode::KeyE,
            KeyCode::KeyF,
            KeyCode::KeyG,
            KeyCode::KeyH,
            KeyCode::KeyI,
            KeyCode::KeyJ,
            KeyCode::KeyK,
            KeyCode::KeyL,
            KeyCode::KeyM,
            KeyCode::KeyN,
            KeyCode::KeyO,
            KeyCode::KeyP,
            KeyCode::KeyQ,
            KeyCode::KeyR,
            KeyCode::KeyS,
            KeyCode::KeyT,
            KeyCode::KeyU,
            KeyCode::KeyV,
            KeyCode::KeyW,
            KeyCode::KeyX,
            KeyCode::KeyY,
            KeyCode::KeyZ,
        ]);
        codes.extend([
            KeyCode::Digit0,
            KeyCode::Digit1,
            KeyCode::Digit2,
            KeyCode::Digit3,
            KeyCode::Digit4,
            KeyCode::Digit5,
            KeyCode::Digit6,
            KeyCode::Digit7,
            KeyCode::Digit8,
            KeyCode::Digit9,
        ]);
        codes.extend([
            KeyCode::F1,
            KeyCode::F2,
            KeyCode::F3,
            KeyCode::F4,
            KeyCode::F5,
            KeyCode::F6,
            KeyCode::F7,
            KeyCode::F8,
            KeyCode::F9,
            KeyCode::F10,
            KeyCode::F11,
            KeyCode::F12,
        ]);
        let mut given: Vec<GameKey> = codes.into_iter().filter_map(|c| game_key(code(c))).collect();
        given.sort();
        given.dedup();
        let wanted: Vec<GameKey> = GameKey::ALL
            .into_iter()
            .filter(|k| !matches!(k, GameKey::MouseLeft | GameKey::MouseRight | GameKey::MouseMiddle))
            .collect();
        assert_eq!(given, wanted);
        // The runner's keys reach a game only when claimed; the others
        // always; none reaches a source that takes no input.
        let mut claimed = crate::input::KeySet::EMPTY;
        assert_eq!(game_key_for(code(KeyCode::KeyP), true, claimed), None, "P pauses");
        assert_eq!(game_key_for(code(KeyCode::Digit3), true, claimed), None, "3 switches");
        assert_eq!(game_key_for(code(KeyCode::KeyB), true, claimed), Some(GameKey::B));
        assert_eq!(
            game_key_for(code(KeyCode::Digit0), true, claimed),
            Some(GameKey::Digit0)
        );
        claimed.insert(GameKey::P);
        claimed.insert(GameKey::Escape);
        assert_eq!(game_key_for(code(KeyCode::KeyP), true, claimed), Some(GameKey::P));
        assert_eq!(
            game_key_for(code(KeyCode::Escape), true, claimed),
            Some(GameKey::Escape)
        );
        assert_eq!(game_key_for(code(KeyCode::KeyP), false, claimed), None);
    }
}

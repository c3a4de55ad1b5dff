//! Recordings are range-checked when loaded: every bad field is an error
//! naming the file, the line, the column and the field, never a panic or a
//! replay that silently draws nothing.

use std::path::PathBuf;

use tickwork_engine::app::Recording;

/// Writes `text` to a fresh file under the target directory.
fn file(name: &str, text: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("recordings");
    std::fs::create_dir_all(&dir).expect("a scratch directory");
    let path = dir.join(name);
    std::fs::write(&path, text).expect("written");
    path
}

fn recording(hz: &str, ticks: &str, inputs: &str) -> String {
    format!(
        "Recording(\n    game: \"Lander\",\n    hz: {hz},\n    seed: 0,\n    integrator: None,\n    ticks: {ticks},\n    inputs: [{inputs}],\n)\n"
    )
}

fn error(name: &str, text: &str) -> String {
    let path = file(name, text);
    let message = Recording::load(&path).expect_err("refused").to_string();
    assert!(message.starts_with(&path.display().to_string()), "{message}");
    message
}

#[test]
fn a_good_recording_loads() {
    let path = file("good.ron", &recording("60.0", "120", ""));
    let r = Recording::load(&path).expect("valid");
    assert_eq!((r.hz, r.ticks), (60.0, 120));
}

#[test]
fn every_bad_field_is_an_error_with_file_line_column_and_field() {
    let message = error("huge_ticks.ron", &recording("60.0", "18446744073709551615", ""));
    assert!(
        message.ends_with(
            "line 6, column 5: ticks: 18446744073709551615 is past the limit of 1000000000 recorded ticks \
             (Recording::MAX_TICKS); record a shorter run"
        ),
        "{message}"
    );
    let message = error("tiny_hz.ron", &recording("1e-300", "120", ""));
    assert!(
        message.ends_with(
            "line 3, column 5: hz: 1e-300 steps per second (accepted: from 1/3600 (a step of an hour) to 1e6 \
             (a step of a microsecond) steps per second)"
        ),
        "{message}"
    );
    for hz in ["NaN", "inf", "0.0", "-60.0"] {
        let message = error("bad_hz.ron", &recording(hz, "120", ""));
        assert!(message.contains("line 3, column 5: hz: "), "{hz}: {message}");
    }
    let message = error(
        "late_input.ron",
        &recording("60.0", "10", "(12, (held: [], pressed: []))"),
    );
    assert!(
        message.contains("line 7, column 5: inputs: entry 0 is at tick 12"),
        "{message}"
    );
}

#[test]
fn a_malformed_recording_names_its_line_and_column() {
    let message = error("malformed.ron", "Recording(\n    game: \"Lander\",\n    hz: sixty,\n)");
    assert!(message.contains("line 3, column"), "{message}");
}

#[test]
fn a_misspelt_field_is_an_error_not_a_replay_on_other_settings() {
    // `integrater: Some("rk4")` was ignored: the replay ran the default
    // integrator, and diverged from the recorded run in silence.
    let text = recording("60.0", "120", "").replace("integrator: None", "integrater: Some(\"rk4\")");
    let message = error("misspelt.ron", &text);
    assert!(message.contains("line 5, column"), "{message}");
    assert!(message.contains("integrater"), "{message}");
    let text = recording("60.0", "120", "(3, TickInput(held: [Up], presed: [Up]))");
    let message = error("misspelt-input.ron", &text);
    assert!(
        message.contains("line 7, column") && message.contains("presed"),
        "{message}"
    );
}

#[test]
fn a_match_recording_holds_every_players_inputs_and_checks_each() {
    let two = recording("60.0", "10", "(2, (held: [Up], pressed: [Up]))").replace(
        "\n)\n",
        "\n    other_players: [[(3, (held: [W], pressed: [W])), (5, (held: [], pressed: []))]],\n)\n",
    );
    let r = Recording::load(&file("match.ron", &two)).expect("valid");
    assert_eq!(r.players(), 2);
    let (mut cursor, mut input) = (0, tickwork_engine::TickInput::default());
    let held: Vec<bool> = (0..7)
        .map(|tick| {
            input = r.input_of(1, &mut cursor, tick, input.carried());
            input.held(tickwork_engine::Key::W)
        })
        .collect();
    assert_eq!(held, [false, false, false, true, true, false, false]);
    // Player 1's ticks must rise too, and the message says whose entry.
    let bad = two.replace("(5, (held: [], pressed: []))", "(3, (held: [], pressed: []))");
    let message = error("bad_match.ron", &bad);
    assert!(
        message.contains("other_players: player 1: entry 1 is at tick 3: ticks must rise"),
        "{message}"
    );
    let nine = recording("60.0", "10", "").replace(
        "\n)\n",
        &format!("\n    other_players: [{}],\n)\n", ["[]"; 8].join(", ")),
    );
    let message = error("nine_players.ron", &nine);
    assert!(
        message.contains("other_players: 9 players, past the limit of 8 (Recording::MAX_PLAYERS)"),
        "{message}"
    );
}

#[test]
fn releases_are_recorded_only_where_there_are_some_so_older_recordings_load_and_save_unchanged() {
    use tickwork_engine::app::Key;
    // Every shipped recording (written before releases were latched) loads
    // and saves back to the same text: no `released` field appears.
    let shipped = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../assets/recordings");
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("recordings");
    std::fs::create_dir_all(&dir).expect("a scratch directory");
    let mut seen = 0;
    for entry in std::fs::read_dir(&shipped).expect("assets/recordings") {
        let path = entry.expect("an entry").path();
        let recording = Recording::load(&path).expect("a shipped recording loads");
        assert!(
            recording.inputs.iter().all(|(_, input)| input.released.is_empty()),
            "{}",
            path.display()
        );
        let again = dir.join(path.file_name().expect("a file name"));
        recording.save(&again, true).expect("saved");
        // (A file's last newline aside: some were written by hand.)
        assert_eq!(
            std::fs::read_to_string(&again).expect("read").trim_end(),
            std::fs::read_to_string(&path).expect("read").trim_end(),
            "{} saves back unchanged",
            path.display()
        );
        seen += 1;
    }
    assert!(seen >= 3, "{seen} recordings in {}", shipped.display());
    // A tap within one tick: pressed and released there, kept by a save.
    let path = file(
        "tap.ron",
        &recording(
            "60.0",
            "10",
            "(3, TickInput(held: [], pressed: [Space], released: [Space]))",
        ),
    );
    let tap = Recording::load(&path).expect("valid");
    let (tick, input) = tap.inputs[0];
    assert_eq!(tick, 3);
    assert!(input.pressed(Key::Space) && input.released(Key::Space) && !input.held(Key::Space));
    tap.save(&path, true).expect("saved");
    let text = std::fs::read_to_string(&path).expect("read");
    assert!(text.contains("released: [Space]"), "{text}");
    assert_eq!(Recording::load(&path).expect("valid"), tap);
}

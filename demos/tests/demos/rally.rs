//! Rally, alone and over the network: two headless processes play a match
//! on the loopback interface from scripted input, with and without a bad
//! link, and must end in the same state; the match's recording replays to
//! it; the game's rules hold when played alone.

use crate::support;

use std::io::Read;
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};

use support::{Host, start_host};
use tickwork::engine::app::{FrameSource, GameSession, SessionOptions};
use tickwork_demos::rally::{Play, Rally};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn script(side: &str) -> String {
    root()
        .join(format!("assets/recordings/rally_{side}.ron"))
        .to_string_lossy()
        .into_owned()
}

fn scratch(name: &str) -> PathBuf {
    let dir = root().join("target/test-rally").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch directory");
    dir
}

/// What one side of a match printed.
#[derive(Debug)]
struct Side {
    stdout: String,
    checksum: String,
    rollbacks: u64,
    outcome: String,
}

impl Side {
    fn of(mut child: Child, first: String, mut rest: impl Read) -> Self {
        // Standard error on a thread of its own, so that neither pipe fills.
        let mut errors = child.stderr.take().expect("piped");
        let stderr = std::thread::spawn(move || {
            let mut text = String::new();
            let _ = errors.read_to_string(&mut text);
            text
        });
        let mut stdout = first;
        rest.read_to_string(&mut stdout).expect("reads the output");
        let status = child.wait().expect("the side ends");
        let stderr = stderr.join().expect("the standard error reader");
        assert!(status.success(), "{stdout}\n{stderr}");
        let ended = stdout
            .lines()
            .find(|l| l.starts_with("tickwork: rally: the match ended at tick 300: checksum "))
            .unwrap_or_else(|| panic!("no end of match in:\n{stdout}"));
        let checksum = ended
            .split("checksum ")
            .nth(1)
            .and_then(|s| s.split(';').next())
            .expect("a checksum")
            .to_owned();
        let rollbacks = ended
            .split("; ")
            .nth(1)
            .and_then(|s| s.split(' ').next())
            .and_then(|n| n.parse().ok())
            .expect("a rollback count");
        let outcome = stdout
            .lines()
            .find(|l| l.starts_with("rally: "))
            .expect("an outcome line")
            .to_owned();
        Self {
            stdout,
            checksum,
            rollbacks,
            outcome,
        }
    }
}

/// Plays a 300-tick match between a host and a joiner on this machine,
/// each side from its script, with `extra` options on both sides and
/// `host_extra` on the host's; returns what both printed.
fn play_match(extra: &[&[&str]; 2], host_extra: &[&str]) -> [Side; 2] {
    let rally = env!("CARGO_BIN_EXE_rally");
    let common = ["--headless", "--frames", "300"];
    let Host {
        child: host,
        output: host_out,
        first,
        port,
    } = start_host(
        Command::new(rally)
            .args(common)
            .args(["--host", "0", "--script", &script("left")])
            .args(extra[0])
            .args(host_extra)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped()),
    );
    let mut joiner = Command::new(rally)
        .args(common)
        .args(["--join", &format!("127.0.0.1:{port}"), "--script", &script("right")])
        .args(extra[1])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the joiner starts");
    let joiner_out = joiner.stdout.take().expect("piped");
    let joined = std::thread::spawn(move || Side::of(joiner, String::new(), joiner_out));
    let hosted = Side::of(host, first, host_out);
    [hosted, joined.join().expect("the joiner's reader")]
}

#[test]
fn a_match_over_loopback_and_one_over_a_bad_link_end_in_the_same_state_and_replay_to_it() {
    let dir = scratch("match");
    let clean = play_match(&[&[], &[]], &[]);
    assert_eq!(clean[0].checksum, clean[1].checksum, "{clean:#?}");
    assert_eq!(clean[0].outcome, clean[1].outcome, "{clean:#?}");

    // 60 ms ± 20 ms each way and 5% of the messages lost: inputs arrive
    // late, so both sides predict, mispredict and roll back; the match must
    // still end where the clean one did (the same inputs, tick for tick).
    let recording = dir.join("match.ron");
    let record = recording.to_string_lossy().into_owned();
    let bad = play_match(
        &[&["--impair", "60,20,0.05,1"], &["--impair", "60,20,0.05,2"]],
        &["--record", &record],
    );
    for side in &bad {
        assert_eq!(side.checksum, clean[0].checksum, "{bad:#?}");
        assert_eq!(side.outcome, clean[0].outcome, "{bad:#?}");
    }
    assert!(
        bad[0].rollbacks + bad[1].rollbacks > 0,
        "no rollback over a 60 ms link: {bad:#?}"
    );
    assert!(
        bad[0].stdout.contains("recorded both players' inputs of 300 ticks"),
        "{}",
        bad[0].stdout
    );

    // The confirmed inputs, replayed alone, reach the same state: under a
    // sync test (every tick rolled back 7 and run again) and off-screen.
    let output = Command::new(env!("CARGO_BIN_EXE_rally"))
        .args(["--sync-test", "7", "--replay", &record])
        .output()
        .expect("runs");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{stdout}");
    assert!(
        stdout.contains(&format!(
            "sync test passed: 300 ticks, each rolled back 7 ticks and re-simulated to the same state (checksum {})",
            clean[0].checksum
        )),
        "{stdout}"
    );
    let out = dir.join("replay");
    let output = Command::new(env!("CARGO_BIN_EXE_rally"))
        .args(["--headless", "--size", "64x36", "--replay", &record])
        .args(["--out", &out.to_string_lossy()])
        .output()
        .expect("runs");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(
        stdout.contains(&format!(
            "the replay ended at tick 300 with checksum {}",
            clean[0].checksum
        )),
        "{stdout}"
    );
    assert!(stdout.contains(&clean[0].outcome), "{stdout}");
}

#[test]
fn a_match_that_cannot_start_says_why() {
    // No host: the joiner gives up after its wait, naming the limit.
    let output = Command::new(env!("CARGO_BIN_EXE_rally"))
        .args(["--headless", "--join", "127.0.0.1:9", "--wait-seconds", "0.3"])
        .output()
        .expect("runs");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(
        stderr.contains("error: network: the host at 127.0.0.1:9 did not answer within 0.3 s (NetOptions::wait_seconds; raise it with --wait-seconds)"),
        "{stderr}"
    );
    // A game of one player cannot host a match.
    let output = Command::new(env!("CARGO_BIN_EXE_breakout"))
        .args(["--headless", "--host", "0", "--wait-seconds", "0.3"])
        .output()
        .expect("runs");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("\"breakout\" has 1 player(s); a networked match (--host, --join, --room) needs a game of 2"),
        "{stderr}"
    );
    // Options out of range name the range.
    let output = Command::new(env!("CARGO_BIN_EXE_rally"))
        .args(["--headless", "--host", "0", "--input-delay", "9"])
        .output()
        .expect("runs");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("--input-delay 9: accepted 0 to 8 ticks (NetOptions::MAX_INPUT_DELAY)"),
        "{stderr}"
    );
    let output = Command::new(env!("CARGO_BIN_EXE_rally"))
        .args(["--headless", "--host", "0", "--impair", "60,80,0.05"])
        .output()
        .expect("runs");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("\"60,80,0.05\": jitter 80: accepted 0 to 60 ms (at most the latency)"),
        "{stderr}"
    );
    let output = Command::new(env!("CARGO_BIN_EXE_rally"))
        .args(["--headless", "--script", &script("left")])
        .output()
        .expect("runs");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("--script plays one side of a networked match: pass --host PORT, --join ADDR or --room URL"),
        "{stderr}"
    );
}

#[test]
fn alone_the_right_paddle_plays_itself_and_the_first_to_five_wins() {
    let mut session = GameSession::new(Rally::default(), SessionOptions::default()).expect("sets up");
    assert!(
        session.game().computer,
        "a run alone gives the right paddle to the computer"
    );
    // Nobody moves the left paddle: it returns only what comes straight at
    // it, and the computer wins the match.
    for _ in 0..60 * 120 {
        session.advance(1.0 / 60.0).expect("steps");
        if session.game().play == Play::Over {
            break;
        }
    }
    let [left, right] = session.game().score;
    assert_eq!(session.game().play, Play::Over, "{left} : {right}");
    assert!(right == 5 && left < 5, "{left} : {right}");
    assert_eq!(session.outcome(), Some(format!("left {left} : 5 right (right wins)")));
}

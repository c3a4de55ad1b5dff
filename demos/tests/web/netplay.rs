//! Matches over WebRTC through `tickwork signal` on loopback: the same two
//! scripted Rally players (`rally_left.ron` hosting, `rally_right.ron`
//! joining) end with the checksum of their UDP match whichever way they
//! meet: two native builds in a room, two pages in headless Chromium, a
//! page and a native build. Each match's left side plays player 1 because
//! a side asks for its player (`--player`, `player=`): the host in one
//! pairing, the joiner in another, both in the third. Where neither asks
//! (the full room) the first to come hosts, which a busy machine can get
//! the other way round, and a checksum compared across matches needs the
//! players in the same seats. A room already full refuses a third player;
//! a player killed mid-match ends the other's match with a message saying
//! so, within the disconnect timeout. A page's `record=` replays natively
//! to the match's end; `--impair` lays a bad link on WebRTC too.
//!
//! Nothing here waits on time: each side is waited on for the line it
//! prints, within a deadline that only bounds one that never prints it.

use crate::browser::{self, Browser, Server};

use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdout, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// How long a side may take to print a line it is waited on for.
const LINE_TIMEOUT: Duration = Duration::from_secs(120);

/// The ticks each match plays.
const TICKS: &str = "300";

/// The disconnect timeout (`NetOptions::disconnect_seconds`): a player
/// whose other side is gone hears so within it; the tests allow three
/// times it on a busy machine.
const DISCONNECT: Duration = Duration::from_secs(5);

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn script(side: &str) -> String {
    root()
        .join(format!("assets/recordings/rally_{side}.ron"))
        .to_string_lossy()
        .into_owned()
}

/// A process whose standard output is read line by line on a thread of
/// its own (so a test can wait for a line with a deadline); killed when
/// dropped.
struct Running {
    child: Child,
    lines: mpsc::Receiver<String>,
    seen: Vec<String>,
    /// The thread reading standard error, until its text is taken.
    errors: Option<std::thread::JoinHandle<String>>,
}

impl Running {
    fn start(command: &mut Command) -> Self {
        let mut child = command
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("the process starts");
        let stdout: ChildStdout = child.stdout.take().expect("piped");
        let mut stderr = child.stderr.take().expect("piped");
        let (send, lines) = mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines().map_while(Result::ok) {
                if send.send(line).is_err() {
                    break;
                }
            }
        });
        let errors = std::thread::spawn(move || {
            let mut text = String::new();
            let _ = stderr.read_to_string(&mut text);
            text
        });
        Self {
            child,
            lines,
            seen: Vec::new(),
            errors: Some(errors),
        }
    }

    /// Everything it wrote on standard error (once it has ended).
    fn stderr(&mut self) -> String {
        self.errors
            .take()
            .and_then(|errors| errors.join().ok())
            .unwrap_or_default()
    }

    /// The first line (printed before this call too) that contains `text`.
    fn wait_line(&mut self, text: &str) -> String {
        if let Some(line) = self.seen.iter().find(|l| l.contains(text)) {
            return line.clone();
        }
        let deadline = Instant::now() + LINE_TIMEOUT;
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match self.lines.recv_timeout(left) {
                Ok(line) => {
                    self.seen.push(line.clone());
                    if line.contains(text) {
                        return line;
                    }
                }
                Err(mpsc::RecvTimeoutError::Timeout) => panic!(
                    "no line with {text:?} within {LINE_TIMEOUT:?}; it printed:\n{}",
                    self.seen.join("\n")
                ),
                Err(mpsc::RecvTimeoutError::Disconnected) => panic!(
                    "it ended without a line with {text:?}; it printed:\n{}\n{}",
                    self.seen.join("\n"),
                    self.stderr()
                ),
            }
        }
    }

    /// Waits for the process to end: whether it succeeded, what it printed
    /// (both streams).
    fn finish(mut self) -> (bool, String) {
        let status = self.child.wait().expect("the process ends");
        self.seen.extend(self.lines.try_iter());
        let stderr = self.stderr();
        (status.success(), format!("{}\n{stderr}", self.seen.join("\n")))
    }
}

impl Drop for Running {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// `tickwork signal` on a port of loopback the system picks: the process,
/// and the URL of room `name` on it.
fn signal_server() -> (Running, String) {
    let mut server = Running::start(Command::new(env!("CARGO_BIN_EXE_tickwork")).args([
        "signal",
        "--port",
        "0",
        "--bind",
        "127.0.0.1",
    ]));
    let line = server.wait_line("tickwork signal: listening on ");
    let address = line
        .split("listening on ")
        .nth(1)
        .map(|s| s.split(':').take(2).collect::<Vec<_>>().join(":"))
        .unwrap_or_else(|| panic!("no address in {line:?}"));
    (server, format!("ws://{address}"))
}

/// A native Rally side of a match of `TICKS` ticks: `how` is `--room
/// URL`, `--host 0` or `--join ADDR`.
fn native_side(how: &[&str], side: &str) -> Running {
    native_side_of(how, side, TICKS)
}

/// A native Rally side of a match of `ticks` ticks.
fn native_side_of(how: &[&str], side: &str, ticks: &str) -> Running {
    Running::start(
        Command::new(env!("CARGO_BIN_EXE_rally"))
            .args(["--headless", "--frames", ticks])
            .args(how)
            .args(["--script", &script(side)]),
    )
}

/// The checksum in a side's `the match ended at tick 300: checksum X` line.
fn match_checksum(line: &str) -> String {
    line.split("checksum ")
        .nth(1)
        .and_then(|s| s.split(';').next())
        .unwrap_or_else(|| panic!("no checksum in {line:?}"))
        .to_owned()
}

const ENDED: &str = "tickwork: rally: the match ended at tick 300: checksum ";

/// The checksum of the scripted match over UDP, native against native.
fn udp_checksum() -> String {
    let mut host = native_side(&["--host", "0"], "left");
    let line = host.wait_line("hosting on port ");
    let port = line
        .split("hosting on port ")
        .nth(1)
        .and_then(|s| s.split(';').next())
        .unwrap_or_else(|| panic!("no port in {line:?}"))
        .to_owned();
    let mut joiner = native_side(&["--join", &format!("127.0.0.1:{port}")], "right");
    let ours = match_checksum(&host.wait_line(ENDED));
    assert_eq!(
        ours,
        match_checksum(&joiner.wait_line(ENDED)),
        "the UDP match's two sides"
    );
    ours
}

/// Two native builds meet in a room and end where their UDP match does;
/// a third player is refused by the full room; the host killed mid-match
/// ends the other's match with a message within the disconnect timeout.
#[test]
fn two_native_builds_in_a_room_end_as_over_udp_a_third_is_refused_and_a_killed_player_ends_the_match() {
    let (mut server, url) = signal_server();
    let room = format!("{url}/natives");
    // The host's link is a bad one: the same end, with rollbacks. It asks
    // to host; the joiner takes player 2.
    let mut host = native_side(&["--room", &room, "--player", "1", "--impair", "40,10,0.05"], "left");
    host.wait_line("waiting for the other player");
    let mut joiner = native_side(&["--room", &room], "right");
    let checksum = match_checksum(&host.wait_line(ENDED));
    assert_eq!(checksum, match_checksum(&joiner.wait_line(ENDED)));
    assert_eq!(
        checksum,
        udp_checksum(),
        "a match over WebRTC ends where one over UDP does"
    );
    let (host_ok, host_out) = host.finish();
    let (joiner_ok, _) = joiner.finish();
    assert!(host_ok && joiner_ok, "{host_out}");
    assert!(host_out.contains("tickwork: connected to peer "), "{host_out}");
    server.wait_line("left room \"natives\" (0 of 2)");

    // Two who ask for the same player are refused: each says so, or (if
    // the other, refused first, left before its word arrived) that the
    // other left before the match began.
    let room = format!("{url}/same");
    let mut one = native_side(&["--room", &room, "--player", "2"], "left");
    one.wait_line("waiting for the other player");
    let other = native_side(&["--room", &room, "--player", "2"], "right");
    let ends = [other.finish(), one.finish()];
    let refused = |out: &str| out.contains(&format!("both players in the room {room} asked to play player 2"));
    for (ok, out) in &ends {
        assert!(!ok, "{out}");
        assert!(refused(out) || out.contains("left the room"), "{out}");
    }
    assert!(ends.iter().any(|(_, out)| refused(out)), "{ends:?}");

    // A match that does not end by itself: two in the room, a third refused.
    let endless = "100000";
    let room = format!("{url}/full");
    let mut first = native_side_of(&["--room", &room], "left", endless);
    first.wait_line("waiting for the other player");
    let mut second = native_side_of(&["--room", &room], "right", endless);
    first.wait_line("tickwork: connected to peer ");
    second.wait_line("tickwork: connected to peer ");
    let third = native_side(&["--room", &room], "left");
    let (third_ok, third_out) = third.finish();
    assert!(!third_ok, "{third_out}");
    assert!(
        third_out.contains(&format!("the signalling server at {room} failed or refused this side")),
        "{third_out}"
    );
    server.wait_line("in room \"full\": the room is full (2 of 2 players; --room-size)");

    // The first player goes; the second hears so.
    let killed = Instant::now();
    drop(first);
    let (second_ok, second_out) = second.finish();
    let heard = killed.elapsed();
    assert!(!second_ok, "{second_out}");
    // Said by the room at once, or by GGRS after its disconnect timeout
    // of silence, whichever comes first on a busy machine.
    assert!(
        second_out.contains("error: network: the other player (peer ")
            && (second_out.contains(" left at tick ") || second_out.contains(" disconnected at tick ")),
        "{second_out}"
    );
    assert!(
        heard < 3 * DISCONNECT,
        "the other side heard after {heard:?}: {second_out}"
    );
}

/// The web build's folder, with Rally's page (`scripts/web build`).
fn site() -> PathBuf {
    let site = root().join("target/web");
    let page = site.join("rally/index.html");
    assert!(
        page.is_file(),
        "{} is missing: build the pages with `scripts/web build` (scripts/test does it before the tests)",
        page.display()
    );
    site
}

/// Chromium as the browser tests start it, with loopback candidates
/// announced as addresses (not mDNS names, which nothing here resolves).
fn browser() -> Browser {
    Browser::launch_with(&["--disable-features=WebRtcHideLocalIpsWithMdns"]).expect("chromium starts")
}

/// Rally's page in a room, playing `side`'s script (WebGL2: enough here,
/// and faster than WebGPU on the CPU), with `more` options (`&player=1`).
fn page_url(server: &Server, room: &str, side: &str, more: &str) -> String {
    server.url(&format!(
        "rally/index.html?room={room}&script=../recordings/rally_{side}.ron&frames={TICKS}&backend=webgl2{more}"
    ))
}

/// The checksum `page` ends its match with; a failure shows what the
/// `other` side's page printed too.
fn page_checksum(page: &mut browser::Page<'_>, other: Option<&browser::Page<'_>>) -> String {
    let line = page.wait_console(|l| l.starts_with(ENDED) || l.starts_with("error"), LINE_TIMEOUT);
    let others = || {
        other.map_or_else(String::new, |o| {
            let lines: Vec<_> = o.console().iter().map(|l| l.text.clone()).collect();
            format!("\nthe other page printed:\n{}", lines.join("\n"))
        })
    };
    let line = line.unwrap_or_else(|e| panic!("{e}{}", others()));
    assert!(line.starts_with(ENDED), "{line}{}", others());
    match_checksum(&line)
}

/// Two pages in a room, and a page against a native build, end where the
/// UDP match of the same scripts does.
#[test]
fn pages_in_a_room_end_as_the_udp_match_against_a_page_or_a_native_build() {
    let site = site();
    let expected = udp_checksum();
    let (_signal, url) = signal_server();
    let files = Server::start(&site).expect("the file server starts");
    let chromium = browser();

    // The page hosts, the native build joins and asks to be player 2.
    let room = format!("{url}/mixed");
    let mut page = chromium.open(&page_url(&files, &room, "left", "")).expect("a tab");
    page.wait_console(|l| l.contains("waiting for the other player"), LINE_TIMEOUT)
        .unwrap_or_else(|e| panic!("{e}"));
    let mut native = native_side(&["--room", &room, "--player", "2"], "right");
    assert_eq!(
        match_checksum(&native.wait_line(ENDED)),
        expected,
        "page against native: the native build"
    );
    assert_eq!(
        page_checksum(&mut page, None),
        expected,
        "page against native: the page"
    );
    drop(page);

    // Two browsers, as two players have: a tab behind another gets no
    // animation frames in headless Chromium, and the match runs on them.
    let room = format!("{url}/pages");
    let mut host = chromium
        .open(&page_url(&files, &room, "left", "&player=1"))
        .expect("a tab");
    host.wait_console(|l| l.contains("waiting for the other player"), LINE_TIMEOUT)
        .unwrap_or_else(|e| panic!("{e}"));
    let other_chromium = browser();
    // The joiner keeps both players' inputs: they replay natively to the end.
    // (A folder whose path has no "..": Chromium cancels a download there.)
    let downloads = std::env::temp_dir().join(format!("tickwork-netplay-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&downloads);
    std::fs::create_dir_all(&downloads).expect("a folder for the download");
    other_chromium
        .allow_downloads(&downloads)
        .unwrap_or_else(|e| panic!("{e}"));
    let recorded = page_url(&files, &room, "right", "&player=2&record=match.ron");
    let mut joiner = other_chromium.open(&recorded).expect("a tab");
    assert_eq!(
        page_checksum(&mut host, Some(&joiner)),
        expected,
        "page against page: the host"
    );
    assert_eq!(
        page_checksum(&mut joiner, Some(&host)),
        expected,
        "page against page: the joiner"
    );
    let offered = joiner
        .wait_console(
            |l| l.contains("offered as a download") || l.starts_with("error"),
            LINE_TIMEOUT,
        )
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(offered.contains("inputs of 300 ticks to match.ron"), "{offered}");
    let saved = other_chromium
        .wait_download(LINE_TIMEOUT)
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(saved, "match.ron");
    let replay = Running::start(Command::new(env!("CARGO_BIN_EXE_rally")).args([
        "--headless",
        "--no-frames",
        "--replay",
        &downloads.join(&saved).to_string_lossy(),
    ]));
    let (replayed, out) = replay.finish();
    let _ = std::fs::remove_dir_all(&downloads);
    assert!(
        replayed && out.contains(&format!("the replay ended at tick 300 with checksum {expected}")),
        "{out}"
    );
    drop((host, joiner));
}

/// The server's rules, seen from a plain websocket client: a room's name
/// is checked (400), a room tells its player of the next one, a room of
/// two refuses a third (409), a message past `--max-message-bytes` is
/// dropped and said.
#[test]
fn the_signalling_server_checks_names_introduces_players_refuses_a_third_and_drops_long_messages() {
    use tungstenite::{Error, Message};
    let (mut server, url) = signal_server();
    let status = |url: &str| match tungstenite::connect(url) {
        Err(Error::Http(response)) => response.status().as_u16(),
        Ok(_) => 101,
        Err(other) => panic!("{url}: {other}"),
    };
    assert_eq!(status(&format!("{url}/bad!name")), 400);
    server.wait_line("refused 127.0.0.1:");
    let (mut first, _) = tungstenite::connect(format!("{url}/rules")).expect("the first player");
    let text = |socket: &mut tungstenite::WebSocket<_>| match socket.read() {
        Ok(Message::Text(text)) => text.to_string(),
        other => panic!("not a text message: {other:?}"),
    };
    assert!(text(&mut first).contains("IdAssigned"));
    let (mut second, _) = tungstenite::connect(format!("{url}/rules")).expect("the second player");
    assert!(text(&mut second).contains("IdAssigned"));
    assert!(text(&mut first).contains("NewPeer"), "the first hears of the second");
    assert_eq!(status(&format!("{url}/rules")), 409, "a third is refused");
    server.wait_line("in room \"rules\": the room is full (2 of 2 players; --room-size)");
    first.send(Message::Text("x".repeat(20_000).into())).expect("sent");
    server.wait_line("dropped a message of 20000 bytes from peer ");
    drop(first);
    server.wait_line("left room \"rules\" (1 of 2)");
    drop(second);
}

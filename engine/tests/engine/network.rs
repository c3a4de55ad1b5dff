//! Networked play: the impaired socket delays, reorders and drops as its
//! seed says; two peers in one process play a match over loopback and
//! agree; a peer whose simulation is deliberately corrupted is caught by
//! the checksum comparison, with the tick and both checksums.

use std::cell::Cell;
use std::net::SocketAddr;
use std::rc::Rc;
use std::time::Duration;

use ggrs::{Message, NonBlockingSocket};
use glam::Vec3;
use tickwork_engine::app::{
    Game, GameError, ImpairedSocket, Impairment, Lobby, MatchReport, NetOptions, NetSession, Peer, RunError,
    SessionOptions, Settings, Stage, TickInput,
};
use tickwork_engine::{Entity, FixedStep, Gravity, Key, Particle, World, WorldConfig};

/// A ggrs message told apart by `k` (a sync request carrying it).
fn message(k: u32) -> Message {
    let mut bytes = vec![0u8, 0];
    bytes.extend_from_slice(&0u32.to_le_bytes());
    bytes.extend_from_slice(&k.to_le_bytes());
    bincode::deserialize(&bytes).expect("a sync request")
}

/// Records what it is asked to send, and when.
struct Wire {
    sent: Rc<std::cell::RefCell<Vec<(Duration, Message)>>>,
    now: Rc<Cell<Duration>>,
}

impl NonBlockingSocket<u8> for Wire {
    fn send_to(&mut self, msg: &Message, _addr: &u8) {
        self.sent.borrow_mut().push((self.now.get(), msg.clone()));
    }

    fn receive_all_messages(&mut self) -> Vec<(u8, Message)> {
        Vec::new()
    }
}

/// Sends 5 000 messages a millisecond apart through an impaired socket
/// with `seed`, then lets 200 ms pass; returns what reached the wire
/// (when, and which message).
fn through_impaired(seed: u64) -> Vec<(Duration, u32)> {
    let sent = Rc::default();
    let now = Rc::new(Cell::new(Duration::ZERO));
    let wire = Wire {
        sent: Rc::clone(&sent),
        now: Rc::clone(&now),
    };
    let clock = Rc::clone(&now);
    let impairment = Impairment {
        latency_ms: 60.0,
        jitter_ms: 20.0,
        loss: 0.05,
        seed,
    };
    let mut socket = ImpairedSocket::with_clock(wire, impairment, move || clock.get());
    let ids: Vec<Message> = (0..5000).map(message).collect();
    for (k, msg) in ids.iter().enumerate() {
        now.set(Duration::from_millis(k as u64));
        socket.send_to(msg, &0);
    }
    for t in 5000..5200 {
        now.set(Duration::from_millis(t));
        let _ = socket.receive_all_messages();
    }
    assert_eq!(socket.counts().sent, 5000);
    let delivered = sent.borrow();
    assert_eq!(delivered.len() as u64, 5000 - socket.counts().dropped);
    delivered
        .iter()
        .map(|(at, msg)| (*at, ids.iter().position(|m| m == msg).expect("a sent message") as u32))
        .collect()
}

#[test]
fn the_impaired_socket_delays_by_latency_and_jitter_drops_its_share_and_repeats_with_its_seed() {
    let delivered = through_impaired(7);
    // 5% of 5000 is 250; the binomial spread is about 15.
    let dropped = 5000 - delivered.len();
    assert!((190..=310).contains(&dropped), "{dropped} dropped");
    // Each message left 40 to 80 ms after it was sent (sent at k ms; the
    // socket is polled every millisecond, so up to 1 ms later).
    for (at, k) in &delivered {
        let delay = at.as_millis() as i64 - i64::from(*k);
        assert!((40..=81).contains(&delay), "message {k} took {delay} ms");
    }
    // Jitter wider than the spacing reorders.
    let overtaken = delivered.windows(2).filter(|w| w[1].1 < w[0].1).count();
    assert!(overtaken > 100, "only {overtaken} messages overtaken");
    // The same seed, the same link; another seed, another.
    assert_eq!(through_impaired(7), delivered);
    assert_ne!(through_impaired(8), delivered);
}

#[test]
fn impairment_specs_are_parsed_and_range_checked() {
    let parsed: Impairment = "60,20,0.05".parse().expect("parses");
    assert_eq!(
        parsed,
        Impairment {
            latency_ms: 60.0,
            jitter_ms: 20.0,
            loss: 0.05,
            seed: 0
        }
    );
    assert_eq!("60, 20, 0.05, 9".parse::<Impairment>().map(|i| i.seed), Ok(9));
    for (spec, message) in [
        ("60,20", "expected LATENCY_MS,JITTER_MS,LOSS[,SEED]"),
        ("sixty,20,0.05", "the latency \"sixty\" is not a number"),
        ("60,20,0.95", "loss 0.95: accepted 0 to 0.9 (a fraction)"),
        ("NaN,0,0", "latency NaN: accepted 0 to 10000 ms"),
        ("60,20,0.05,-1", "the seed \"-1\" is not a whole number"),
    ] {
        let error = spec.parse::<Impairment>().expect_err(spec);
        assert!(error.contains(message), "{spec}: {error}");
    }
}

/// A ball drifting under gravity, pushed by each player's Space; `corrupt`
/// pushes it at tick 100 on this side only (a deliberate desync).
#[derive(Clone, Default)]
struct Drift {
    ball: Entity,
    corrupt: bool,
}

impl Game for Drift {
    fn title(&self) -> &str {
        "drift"
    }

    fn players(&self) -> usize {
        2
    }

    fn setup(&mut self, stage: &mut Stage, settings: &Settings) -> Result<(), GameError> {
        let mut world = World::new(WorldConfig {
            seed: settings.seed,
            ..WorldConfig::default()
        })?;
        world.add_force(Gravity::EARTH);
        self.ball = world.spawn(Particle {
            position: Vec3::new(0.0, 100.0, 0.0),
            ..Particle::default()
        })?;
        stage.add_world("drift", world);
        Ok(())
    }

    fn fixed_update_players(
        &mut self,
        stage: &mut Stage,
        step: &FixedStep,
        inputs: &[TickInput],
    ) -> Result<(), GameError> {
        let world = &mut stage.worlds[0].world;
        let mut push = Vec3::ZERO;
        for (player, input) in inputs.iter().enumerate() {
            if input.held(Key::Space) {
                push.x += if player == 0 { 0.1 } else { -0.05 };
            }
        }
        if self.corrupt && step.tick == 100 {
            push.y += 1.0;
        }
        let velocity = world.velocity(self.ball)? + push;
        world.set_velocity(self.ball, velocity)?;
        Ok(())
    }
}

/// Space held on ticks `[from, to)` of every `period`.
fn script(period: u64, from: u64, to: u64, ticks: u64) -> tickwork_engine::Recording {
    let mut recording = tickwork_engine::Recording::new("drift", 60.0, 0, None);
    recording.ticks = ticks;
    let mut held = tickwork_engine::KeySet::EMPTY;
    held.insert(Key::Space);
    for start in (0..ticks).step_by(period as usize) {
        let down = TickInput {
            held,
            pressed: held,
            pointer: None,
            ..TickInput::default()
        };
        recording.inputs.push((start + from, down));
        recording.inputs.push((start + to, TickInput::default()));
    }
    recording.inputs.retain(|(tick, _)| *tick < ticks);
    recording
}

/// Plays `ticks` ticks between two peers in this process; the joiner's
/// game is `joiner`.
fn play(joiner: Drift, net: &NetOptions, ticks: u64) -> [Result<MatchReport, RunError>; 2] {
    let lobby = Lobby::bind(Peer::Host { port: 0 }).expect("binds");
    let port = lobby.local_addr().expect("an address").port();
    let host_net = net.clone();
    let host = std::thread::spawn(move || {
        let mut session = NetSession::start(
            Drift::default(),
            lobby,
            SessionOptions::default(),
            &host_net,
            Some(script(30, 5, 17, ticks)),
        )?;
        session.play_headless(ticks)
    });
    let net = net.clone();
    let joined = std::thread::spawn(move || {
        let host = SocketAddr::from(([127, 0, 0, 1], port));
        let lobby = Lobby::bind(Peer::Join { host })?;
        let mut session = NetSession::start(
            joiner,
            lobby,
            SessionOptions::default(),
            &net,
            Some(script(23, 0, 9, ticks)),
        )?;
        session.play_headless(ticks)
    });
    [
        host.join().expect("the host's thread"),
        joined.join().expect("the joiner's thread"),
    ]
}

#[test]
fn two_peers_agree_and_a_corrupted_peer_is_caught_with_the_tick_and_both_checksums() {
    let net = NetOptions {
        impairment: Some(Impairment {
            latency_ms: 60.0,
            jitter_ms: 20.0,
            loss: 0.05,
            seed: 3,
        }),
        ..NetOptions::default()
    };
    let [host, joiner] = play(Drift::default(), &net, 240);
    let (host, joiner) = (host.expect("the host's match"), joiner.expect("the joiner's match"));
    assert_eq!(host.checksum, joiner.checksum);
    assert_eq!((host.ticks, joiner.ticks), (240, 240));
    assert!(host.rollbacks + joiner.rollbacks > 0, "{host:?} {joiner:?}");
    // Lockstep (no prediction: every tick waits for both inputs) runs the
    // same inputs to the same state, without a rollback.
    let lockstep = NetOptions {
        max_prediction: 0,
        ..NetOptions::default()
    };
    let [a, b] = play(Drift::default(), &lockstep, 240);
    let (a, b) = (a.expect("the host's lockstep match"), b.expect("the joiner's"));
    assert_eq!((a.checksum, b.checksum), (host.checksum, host.checksum));
    assert_eq!(a.rollbacks + b.rollbacks, 0);

    let corrupted = Drift {
        corrupt: true,
        ..Drift::default()
    };
    let sides = play(corrupted, &net, 240);
    assert!(
        sides.iter().all(Result::is_err),
        "a corrupted match ended well: {sides:?}"
    );
    let messages: Vec<String> = sides
        .iter()
        .map(|s| s.as_ref().expect_err("failed").to_string())
        .collect();
    // Checksums of confirmed ticks are compared every 10 ticks: the first
    // compared after the push at tick 100 differs (the state at tick 100,
    // before the push, is the same on both sides).
    let caught = messages.iter().find(|m| m.contains("desync at tick "));
    let caught = caught.unwrap_or_else(|| panic!("no desync reported: {messages:?}"));
    let tick: u64 = caught
        .split("desync at tick ")
        .nth(1)
        .and_then(|s| s.split([':', ',']).next())
        .and_then(|n| n.parse().ok())
        .expect("a tick");
    assert!((101..=240).contains(&tick), "{caught}");
    assert!(caught.contains("this side's checksum is "), "{caught}");
    let hex = |s: &str| s.len() == 16 && s.chars().all(|c| c.is_ascii_hexdigit());
    let words: Vec<&str> = caught.split([' ', ';', ',']).collect();
    assert_eq!(words.iter().filter(|w| hex(w)).count(), 2, "{caught}");
    assert!(caught.contains("run it with --sync-test to find it"), "{caught}");
}

/// A match's HUD ends with its own line: this side's player, the other's
/// address, the round trip GGRS measured and the rollbacks so far.
#[test]
fn a_matchs_hud_names_the_other_player_the_ping_and_the_rollbacks() {
    use tickwork_engine::app::FrameSource;
    let lobby = Lobby::bind(Peer::Host { port: 0 }).expect("binds");
    let port = lobby.local_addr().expect("an address").port();
    let ticks = 120;
    let host = std::thread::spawn(move || {
        let mut session = NetSession::start(
            Drift::default(),
            lobby,
            SessionOptions::default(),
            &NetOptions::default(),
            Some(script(30, 5, 17, ticks)),
        )?;
        let report = session.play_headless(ticks)?;
        let mut hud = String::new();
        session.with_view(true, (320, 180), &mut |view| {
            hud = view.hud.to_owned();
            Ok(())
        })?;
        Ok::<_, RunError>((report, hud))
    });
    let joiner = std::thread::spawn(move || {
        let host = SocketAddr::from(([127, 0, 0, 1], port));
        let mut session = NetSession::start(
            Drift::default(),
            Lobby::bind(Peer::Join { host })?,
            SessionOptions::default(),
            &NetOptions::default(),
            Some(script(23, 0, 9, ticks)),
        )?;
        session.play_headless(ticks)
    });
    let (report, hud) = host.join().expect("the host's thread").expect("the host's match");
    joiner.join().expect("the joiner's thread").expect("the joiner's match");
    let line = hud.lines().last().unwrap_or_default();
    let (start, rest) = line.split_once(", ping ").unwrap_or_else(|| panic!("{hud:?}"));
    assert!(start.starts_with("player 1 vs 127.0.0.1:"), "{line}");
    let (ms, rollbacks) = rest.split_once(" ms, ").unwrap_or_else(|| panic!("{line}"));
    assert!(ms.parse::<u64>().is_ok_and(|ms| ms < 5_000), "{line}");
    assert_eq!(rollbacks, format!("{} rollbacks", report.rollbacks), "{line}");
}

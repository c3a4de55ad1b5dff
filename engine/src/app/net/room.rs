//! Meeting the other player in a signalling server's room, and the WebRTC
//! [`Link`] to it (the `webrtc` feature; matchbox's socket).
//!
//! A player opens `ws://HOST:PORT/ROOM` ([`Room::open`]): the server
//! (`tickwork signal`, or any matchbox server) introduces the two players
//! of a room, and their browsers or native builds open WebRTC data
//! channels to each other: an unreliable one for GGRS's messages, a
//! reliable one for Tickwork's control messages. Each then tells the
//! other its game, its settings, the player it asked to play (`--player`,
//! if any) and how long it waited in the room ([`ControlMessage::Meet`]).
//! A side that asked for a player plays it (two that asked for the same
//! one are refused); else the one that waited longer (the first to come)
//! hosts. The host plays player 1, and its seed, rate and integrator are
//! the match's. Both decide from the same two messages, so they agree.
//!
//! The waits are measured on two clocks up to the moment each side sees
//! the connection: a side stalled there for longer than the other took
//! to arrive (a machine busy for a few hundred milliseconds) can come out
//! as the later one. The first to come is a convenience for people; a
//! side that must be one player (a script, a test) asks for it.

use std::time::Duration;

use matchbox_socket::{ChannelConfig, PeerId, PeerState, WebRtcSocket};

use super::link::{Link, MESSAGE_BYTES, PeerAddress};
use super::transport::{ControlMessage, Welcome};
use crate::app::RunError;
use crate::platform::Instant;

/// The data channel GGRS's messages take (unreliable, unordered).
const GGRS_CHANNEL: usize = 0;
/// The data channel Tickwork's control messages take (reliable, ordered).
const CONTROL_CHANNEL: usize = 1;
/// How often a meeting looks for news (the room, the other's message).
const POLL: Duration = Duration::from_millis(5);

/// Why the socket's loop (signalling, then the peer connections) ended,
/// once it has: shared with the task that runs it (a thread natively, the
/// page's event loop in a browser, where the lock is never contended).
type Ended = std::sync::Arc<std::sync::Mutex<Option<String>>>;

fn ended_now(ended: &Ended) -> Option<String> {
    ended.lock().map_or_else(|e| e.into_inner().clone(), |why| why.clone())
}

/// A room of a signalling server, joined: this side's WebRTC socket,
/// waiting for the other player.
#[derive(Debug)]
pub(super) struct Room {
    url: String,
    socket: WebRtcSocket,
    ended: Ended,
    joined: Instant,
}

/// The other player met: the link to it, and who hosts.
#[derive(Debug)]
pub(super) struct Met {
    /// The WebRTC link to the other player.
    pub link: WebRtcLink,
    /// The other player, as GGRS names it.
    pub remote: PeerAddress,
    /// The host's settings: the match's.
    pub welcome: Welcome,
    /// Whether this side hosts (plays player 1).
    pub host: bool,
}

impl Room {
    /// Joins the room at `url` (`ws://HOST:PORT/ROOM` or `wss://`): the
    /// socket connects in the background (a thread natively, the page's
    /// event loop in a browser).
    ///
    /// # Errors
    /// [`RunError::Limit`] for a URL that is not a `ws://` or `wss://` URL
    /// with a host and a room.
    pub(super) fn open(url: &str) -> Result<Self, RunError> {
        check_room_url(url)?;
        let (socket, message_loop) = WebRtcSocket::builder(url)
            // A refused or unreachable server is said at once.
            .reconnect_attempts(Some(1))
            .add_channel(ChannelConfig::unreliable())
            .add_channel(ChannelConfig::reliable())
            .build();
        let ended = Ended::default();
        let (task_ended, what) = (ended.clone(), url.to_owned());
        crate::platform::spawn_background(async move {
            let why = match message_loop.await {
                Ok(()) => "the connection to the room closed".to_owned(),
                Err(error) => format!("the signalling server at {what} failed or refused this side: {error}"),
            };
            *task_ended.lock().unwrap_or_else(std::sync::PoisonError::into_inner) = Some(why);
        });
        Ok(Self {
            url: url.to_owned(),
            socket,
            ended,
            joined: Instant::now(),
        })
    }

    /// Waits (within `wait`) for the other player to connect and meet:
    /// `own` is this side's game and settings, `player` the player it
    /// asked to play, if any. Polls every few milliseconds: natively it
    /// blocks, in a page it yields to the browser between polls.
    pub(super) async fn meet(mut self, own: &Welcome, player: Option<u8>, wait: Duration) -> Result<Met, RunError> {
        let started = Instant::now();
        let mut other: Option<(PeerId, u64)> = None;
        let mut theirs: Vec<(PeerId, Welcome, Seat)> = Vec::new();
        loop {
            if let Some(why) = ended_now(&self.ended) {
                return Err(RunError::Network(why));
            }
            // (A closed socket is said by `ended` on the next poll.) The other
            // gone is said after its last message is read: a Meet sent just
            // before it left still decides (a refusal says why).
            let mut left = None;
            for (peer, state) in self.socket.try_update_peers().unwrap_or_default() {
                match state {
                    PeerState::Connected if other.is_none() => {
                        let waited = u64::try_from(self.joined.elapsed().as_millis()).unwrap_or(u64::MAX);
                        other = Some((peer, waited));
                        let meet = ControlMessage::Meet {
                            welcome: own.clone(),
                            waited_ms: waited,
                            player,
                        };
                        let _ = self
                            .socket
                            .channel_mut(CONTROL_CHANNEL)
                            .try_send(meet.encode().into(), peer);
                    }
                    PeerState::Disconnected if other.is_some_and(|(o, _)| o == peer) => left = Some(peer),
                    _ => {}
                }
            }
            for (peer, packet) in self.socket.channel_mut(CONTROL_CHANNEL).receive() {
                if packet.len() < MESSAGE_BYTES
                    && let Some(ControlMessage::Meet {
                        welcome,
                        waited_ms,
                        player,
                    }) = ControlMessage::decode(&packet)
                {
                    // A peer's latest word only: one entry a peer of the room.
                    theirs.retain(|t| t.0 != peer);
                    let seat = Seat {
                        waited_ms,
                        id: peer.to_string(),
                        player,
                    };
                    theirs.push((peer, welcome, seat));
                }
            }
            if let Some((peer, waited)) = other
                && let Some((_, welcome, their_seat)) = theirs.iter().find(|t| t.0 == peer)
            {
                if welcome.game != own.game {
                    return Err(RunError::Network(format!(
                        "the other player in the room {} plays \"{}\", not \"{}\"",
                        self.url, welcome.game, own.game
                    )));
                }
                let mine = Seat {
                    waited_ms: waited,
                    id: self.socket.id().map(|id| id.to_string()).unwrap_or_default(),
                    player,
                };
                let host = hosts(&mine, their_seat).map_err(|player| {
                    RunError::Network(format!(
                        "both players in the room {} asked to play player {player} (--player, a page's player=); \
                         one must ask for the other, or neither (the first to come then hosts)",
                        self.url
                    ))
                })?;
                return Ok(Met {
                    welcome: if host { own.clone() } else { welcome.clone() },
                    remote: PeerAddress::Room(peer.to_string()),
                    host,
                    link: WebRtcLink {
                        socket: self.socket,
                        peer,
                        ended: self.ended,
                        left: None,
                    },
                });
            }
            if let Some(peer) = left {
                return Err(RunError::Network(format!(
                    "the other player (peer {peer}) left the room {} before the match began",
                    self.url
                )));
            }
            if started.elapsed() > wait {
                return Err(RunError::Network(format!(
                    "no other player came to the room {} within {} s (NetOptions::wait_seconds; raise it with \
                     --wait-seconds)",
                    self.url,
                    wait.as_secs_f64()
                )));
            }
            crate::platform::pause(POLL).await;
        }
    }
}

/// What a side said of itself when it met the other: its wait in the room,
/// its id and the player it asked for.
#[derive(Clone, Debug)]
struct Seat {
    /// Milliseconds from its joining the room to the other's arrival.
    waited_ms: u64,
    /// Its id in the room.
    id: String,
    /// The player it asked to play (1 hosts), if any.
    player: Option<u8>,
}

/// Whether this side hosts, from both sides' seats: a side that asked for
/// a player plays it (and the other the other); else the one that waited
/// longer came first and hosts, and equal waits go to the smaller id. Both
/// sides decide alike from the same two seats.
///
/// # Errors
/// The player both asked for.
fn hosts(mine: &Seat, theirs: &Seat) -> Result<bool, u8> {
    match (mine.player, theirs.player) {
        (Some(a), Some(b)) if a == b => Err(a),
        (Some(a), _) => Ok(a == 1),
        (None, Some(b)) => Ok(b != 1),
        (None, None) => {
            Ok(mine.waited_ms > theirs.waited_ms || (mine.waited_ms == theirs.waited_ms && mine.id < theirs.id))
        }
    }
}

/// Checks that `url` names a room of a signalling server.
fn check_room_url(url: &str) -> Result<(), RunError> {
    let refuse = |why: &str| {
        Err(RunError::Limit(format!(
            "--room {url:?}: {why}; a room is ws://HOST:PORT/ROOM (or wss://), as `tickwork signal` prints"
        )))
    };
    let Some(rest) = url.strip_prefix("ws://").or_else(|| url.strip_prefix("wss://")) else {
        return refuse("not a ws:// or wss:// URL");
    };
    let Some((host, room)) = rest.split_once('/') else {
        return refuse("no room named after the host");
    };
    if host.is_empty() {
        return refuse("no host");
    }
    if room.is_empty() || room.contains(['/', '?', '#']) {
        return refuse("the room's name is empty or has '/', '?' or '#' in it");
    }
    Ok(())
}

/// A [`Link`] over WebRTC data channels to the other player of a room.
#[derive(Debug)]
pub(super) struct WebRtcLink {
    socket: WebRtcSocket,
    peer: PeerId,
    ended: Ended,
    left: Option<String>,
}

impl WebRtcLink {
    fn send_on(&mut self, channel: usize, bytes: &[u8]) {
        // After the socket's loop ended there is no one to send to: `gone` says so.
        let _ = self
            .socket
            .channel_mut(channel)
            .try_send(bytes.to_vec().into(), self.peer);
    }
}

impl Link for WebRtcLink {
    fn send(&mut self, bytes: &[u8]) {
        self.send_on(GGRS_CHANNEL, bytes);
    }

    fn send_control(&mut self, bytes: &[u8]) {
        self.send_on(CONTROL_CHANNEL, bytes);
    }

    fn receive(&mut self, each: &mut dyn FnMut(&[u8])) {
        for channel in [GGRS_CHANNEL, CONTROL_CHANNEL] {
            for (peer, packet) in self.socket.channel_mut(channel).receive() {
                if peer == self.peer {
                    each(&packet);
                }
            }
        }
    }

    fn gone(&mut self) -> Option<String> {
        if self.left.is_none() {
            match self.socket.try_update_peers() {
                Ok(changes) => {
                    if changes.contains(&(self.peer, PeerState::Disconnected)) {
                        self.left = Some("its connection closed".into());
                    }
                }
                Err(_) => {
                    self.left = Some(ended_now(&self.ended).unwrap_or_else(|| "the connection closed".into()));
                }
            }
        }
        self.left.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn seat(waited_ms: u64, id: &str, player: Option<u8>) -> Seat {
        Seat {
            waited_ms,
            id: id.to_owned(),
            player,
        }
    }

    /// The first to come hosts, whichever side decides; a tie goes to the
    /// smaller id, on both sides.
    #[test]
    fn both_sides_agree_on_the_host() {
        let agree = |a: &Seat, b: &Seat| {
            let (ours, theirs) = (hosts(a, b), hosts(b, a));
            assert_eq!(ours.map(|host| !host), theirs, "{a:?} against {b:?}");
            ours
        };
        assert_eq!(agree(&seat(900, "b", None), &seat(40, "a", None)), Ok(true));
        assert_eq!(agree(&seat(40, "a", None), &seat(900, "b", None)), Ok(false));
        assert_eq!(agree(&seat(40, "a", None), &seat(40, "b", None)), Ok(true));
        assert_eq!(agree(&seat(40, "b", None), &seat(40, "a", None)), Ok(false));
    }

    /// A player asked for is played whoever came first (the other side
    /// takes the other); the same player asked for by both is refused.
    #[test]
    fn a_player_asked_for_wins_over_the_wait() {
        for (ours, theirs, host) in [
            (Some(1), None, true),
            (Some(2), None, false),
            (None, Some(1), false),
            (None, Some(2), true),
            (Some(1), Some(2), true),
            (Some(2), Some(1), false),
        ] {
            // Whoever waited longer.
            for (a, b) in [(5, 900), (900, 5)] {
                assert_eq!(hosts(&seat(a, "a", ours), &seat(b, "b", theirs)), Ok(host));
                assert_eq!(hosts(&seat(b, "b", theirs), &seat(a, "a", ours)), Ok(!host));
            }
        }
        assert_eq!(hosts(&seat(5, "a", Some(2)), &seat(900, "b", Some(2))), Err(2));
        assert_eq!(hosts(&seat(900, "b", Some(1)), &seat(5, "a", Some(1))), Err(1));
    }

    /// A room URL is ws:// or wss://, a host, and one room name.
    #[test]
    fn room_urls_are_checked() {
        assert!(check_room_url("ws://127.0.0.1:3536/rally").is_ok());
        assert!(check_room_url("wss://example.org/a-room").is_ok());
        for (url, why) in [
            ("http://127.0.0.1:3536/rally", "not a ws:// or wss:// URL"),
            ("ws://127.0.0.1:3536", "no room named after the host"),
            ("ws:///rally", "no host"),
            ("ws://127.0.0.1:3536/", "the room's name is empty"),
            ("ws://127.0.0.1:3536/a/b", "has '/', '?' or '#'"),
        ] {
            let error = check_room_url(url).expect_err(url).to_string();
            assert!(error.contains(why) && error.contains(url), "{url}: {error}");
        }
    }
}

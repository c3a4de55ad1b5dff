//! Meeting the other player in a signalling server's room, and the WebRTC
//! [`Link`] to it (the `webrtc` feature; matchbox's socket).
//!
//! A player opens `ws://HOST:PORT/ROOM` ([`Room::open`]): the server
//! (`tickwork signal`, or any matchbox server) introduces the two players
//! of a room, and their browsers or native builds open WebRTC data
//! channels to each other: an unreliable one for GGRS's messages, a
//! reliable one for Tickwork's control messages. Each then tells the
//! other its game, its settings and how long it waited in the room
//! ([`ControlMessage::Meet`]); the one that waited longer (the first to
//! come) hosts: it plays player 1, and its seed, rate and integrator are
//! the match's. Both decide from the same two messages, so they agree.

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
    /// `own` is this side's game and settings. Polls every few
    /// milliseconds: natively it blocks, in a page it yields to the
    /// browser between polls.
    pub(super) async fn meet(mut self, own: &Welcome, wait: Duration) -> Result<Met, RunError> {
        let started = Instant::now();
        let mut other: Option<(PeerId, u64)> = None;
        let mut theirs: Vec<(PeerId, Welcome, u64)> = Vec::new();
        loop {
            if let Some(why) = ended_now(&self.ended) {
                return Err(RunError::Network(why));
            }
            // (A closed socket is said by `ended` on the next poll.)
            for (peer, state) in self.socket.try_update_peers().unwrap_or_default() {
                match state {
                    PeerState::Connected if other.is_none() => {
                        let waited = u64::try_from(self.joined.elapsed().as_millis()).unwrap_or(u64::MAX);
                        other = Some((peer, waited));
                        let meet = ControlMessage::Meet {
                            welcome: own.clone(),
                            waited_ms: waited,
                        };
                        let _ = self
                            .socket
                            .channel_mut(CONTROL_CHANNEL)
                            .try_send(meet.encode().into(), peer);
                    }
                    PeerState::Disconnected if other.is_some_and(|(o, _)| o == peer) => {
                        return Err(RunError::Network(format!(
                            "the other player (peer {peer}) left the room {} before the match began",
                            self.url
                        )));
                    }
                    _ => {}
                }
            }
            for (peer, packet) in self.socket.channel_mut(CONTROL_CHANNEL).receive() {
                if packet.len() < MESSAGE_BYTES
                    && let Some(ControlMessage::Meet { welcome, waited_ms }) = ControlMessage::decode(&packet)
                {
                    // A peer's latest word only: one entry a peer of the room.
                    theirs.retain(|t| t.0 != peer);
                    theirs.push((peer, welcome, waited_ms));
                }
            }
            if let Some((peer, waited)) = other
                && let Some((_, welcome, their_wait)) = theirs.iter().find(|t| t.0 == peer)
            {
                if welcome.game != own.game {
                    return Err(RunError::Network(format!(
                        "the other player in the room {} plays \"{}\", not \"{}\"",
                        self.url, welcome.game, own.game
                    )));
                }
                let me = self.socket.id().map(|id| id.to_string()).unwrap_or_default();
                let host = hosts((waited, &me), (*their_wait, &peer.to_string()));
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

/// Whether this side hosts, from both sides' (wait in the room, id): the
/// one that waited longer came first and hosts; equal waits go to the
/// smaller id. Both sides decide alike from the same two pairs.
fn hosts(mine: (u64, &str), theirs: (u64, &str)) -> bool {
    mine.0 > theirs.0 || (mine.0 == theirs.0 && mine.1 < theirs.1)
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

    /// The first to come hosts, whichever side decides; a tie goes to the
    /// smaller id, on both sides.
    #[test]
    fn both_sides_agree_on_the_host() {
        assert!(hosts((900, "b"), (40, "a")));
        assert!(!hosts((40, "a"), (900, "b")));
        assert!(hosts((40, "a"), (40, "b")));
        assert!(!hosts((40, "b"), (40, "a")));
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

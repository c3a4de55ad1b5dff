//! `tickwork signal`: the signalling server two players meet through
//! before a match over WebRTC (`--room ws://HOST:PORT/ROOM`, a page's
//! `?room=`).
//!
//! It is matchbox's server library (`matchbox_signaling`) with a topology
//! of Tickwork's own: rooms named by the URL's path, as matchbox's full
//! mesh names them, but with limits. A room takes `--room-size` players
//! (2: a match is of two) and refuses the next with HTTP 409; the server
//! holds at most `--max-rooms` rooms; a signalling message (an offer, an
//! answer, an ICE candidate: a few kilobytes) longer than
//! `--max-message-bytes` is dropped, as is one addressed to a peer of
//! another room. Once the players' browsers or builds are connected to
//! each other, the match's traffic goes between them, not through here.
//! It prints a line for each player that joins or leaves, and for each
//! refusal.

use std::collections::HashMap;
use std::net::{IpAddr, Ipv4Addr, SocketAddr};
use std::sync::{Arc, Mutex, MutexGuard};

use axum::extract::ws::Message;
use axum::http::StatusCode;
use axum::response::Response;
use futures::StreamExt;
use matchbox_protocol::{JsonPeerEvent, PeerId, PeerRequest};
use matchbox_signaling::common_logic::{SignalingChannel, parse_request, try_send};
use matchbox_signaling::{
    ClientRequestError, NoCallbacks, SignalingServerBuilder, SignalingState, SignalingTopology, WsStateMeta,
};

use super::CliError;

/// `tickwork signal`'s options.
#[derive(Debug, Clone, clap::Args)]
pub struct SignalArgs {
    /// The port to listen on (0: any free port; the line it prints says
    /// which).
    #[arg(long, default_value_t = 3536)]
    pub port: u16,
    /// The address to listen on (default all of this machine's; 127.0.0.1
    /// for this machine alone).
    #[arg(long, default_value_t = IpAddr::V4(Ipv4Addr::UNSPECIFIED))]
    pub bind: IpAddr,
    /// Players a room takes: the next is refused (2-16; a match is of 2).
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u16).range(2..=16))]
    pub room_size: u16,
    /// Rooms open at once: a player who would open another is refused
    /// (1-100000).
    #[arg(long, default_value_t = 1000, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub max_rooms: u32,
    /// The longest signalling message passed on, in bytes (an offer is a
    /// few kilobytes; 1024-1048576).
    #[arg(long, default_value_t = 16_384, value_parser = clap::value_parser!(u32).range(1024..=1_048_576))]
    pub max_message_bytes: u32,
}

/// The longest room name: the URL's path after its `/`.
pub const MAX_ROOM_NAME: usize = 64;

/// The server's limits and its rooms, shared by every peer's handler.
#[derive(Clone, Debug)]
pub struct Rooms {
    limits: SignalArgs,
    rooms: Arc<Mutex<HashMap<String, HashMap<PeerId, SignalingChannel>>>>,
}

impl SignalingState for Rooms {}

impl Rooms {
    /// No room yet, under `limits`.
    #[must_use]
    pub fn new(limits: SignalArgs) -> Self {
        Self {
            limits,
            rooms: Arc::default(),
        }
    }

    fn lock(&self) -> MutexGuard<'_, HashMap<String, HashMap<PeerId, SignalingChannel>>> {
        // A handler that panicked left the map whole: each change is one call.
        self.rooms.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    /// Why a player may not enter `room` now, if it may not: the room is
    /// full, or it would be a room past the limit.
    fn refusal(&self, room: &str) -> Option<String> {
        let rooms = self.lock();
        match rooms.get(room) {
            Some(players) if players.len() >= usize::from(self.limits.room_size) => Some(format!(
                "the room is full ({} of {} players; --room-size)",
                players.len(),
                self.limits.room_size
            )),
            None if rooms.len() >= self.limits.max_rooms as usize => Some(format!(
                "{} rooms are open, the most this server holds (--max-rooms)",
                rooms.len()
            )),
            _ => None,
        }
    }

    /// Adds `peer` to `room`, telling the players already there (who then
    /// offer it a connection); the room's count after, or why not.
    fn enter(&self, room: &str, peer: PeerId, channel: SignalingChannel) -> Result<usize, String> {
        if let Some(why) = self.refusal(room) {
            return Err(why);
        }
        let mut rooms = self.lock();
        let players = rooms.entry(room.to_owned()).or_default();
        let news = Message::Text(JsonPeerEvent::NewPeer(peer).to_string().into());
        for other in players.values() {
            let _ = try_send(other, news.clone());
        }
        players.insert(peer, channel);
        Ok(players.len())
    }

    /// Takes `peer` out of `room`, telling those left; the room closes
    /// when it is empty. The room's count after.
    fn leave(&self, room: &str, peer: PeerId) -> usize {
        let mut rooms = self.lock();
        let Some(players) = rooms.get_mut(room) else {
            return 0;
        };
        players.remove(&peer);
        let news = Message::Text(JsonPeerEvent::PeerLeft(peer).to_string().into());
        for other in players.values() {
            let _ = try_send(other, news.clone());
        }
        let left = players.len();
        if left == 0 {
            rooms.remove(room);
        }
        left
    }

    /// The channel of `peer` if it is in `room`.
    fn channel(&self, room: &str, peer: PeerId) -> Option<SignalingChannel> {
        self.lock().get(room)?.get(&peer).cloned()
    }
}

/// Whether `room` is a name a room may have: 1 to [`MAX_ROOM_NAME`]
/// letters, digits, `-`, `_` or `.`.
fn room_name_ok(room: &str) -> bool {
    (1..=MAX_ROOM_NAME).contains(&room.len()) && room.bytes().all(|b| b.is_ascii_alphanumeric() || b"-_.".contains(&b))
}

/// Tickwork's topology: matchbox's full mesh within a room, with limits.
#[derive(Debug, Default)]
pub struct RoomTopology;

#[async_trait::async_trait]
impl SignalingTopology<NoCallbacks, Rooms> for RoomTopology {
    async fn state_machine(upgrade: WsStateMeta<NoCallbacks, Rooms>) {
        let WsStateMeta {
            room,
            peer_id,
            sender,
            mut receiver,
            state,
            ..
        } = upgrade;
        // Admitted before the upgrade; another may have come in between.
        let count = match state.enter(&room, peer_id, sender.clone()) {
            Ok(count) => count,
            Err(why) => {
                println!("tickwork signal: refused peer {peer_id} in room \"{room}\": {why}");
                let _ = try_send(&sender, Message::Close(None));
                return;
            }
        };
        let size = state.limits.room_size;
        println!("tickwork signal: peer {peer_id} joined room \"{room}\" ({count} of {size})");
        let limit = state.limits.max_message_bytes as usize;
        while let Some(request) = receiver.next().await {
            if let Ok(Message::Text(text)) = &request
                && text.len() > limit
            {
                println!(
                    "tickwork signal: dropped a message of {} bytes from peer {peer_id} (--max-message-bytes {limit})",
                    text.len()
                );
                continue;
            }
            match parse_request(request) {
                Ok(PeerRequest::Signal { receiver, data }) => {
                    // Only to a player of the same room.
                    if let Some(channel) = state.channel(&room, receiver) {
                        let event = JsonPeerEvent::Signal { sender: peer_id, data };
                        let _ = try_send(&channel, Message::Text(event.to_string().into()));
                    }
                }
                Ok(PeerRequest::KeepAlive) => {}
                // Not a request: dropped; the peer may go on.
                Err(ClientRequestError::Json(_) | ClientRequestError::UnsupportedType(_)) => {}
                Err(ClientRequestError::Close | ClientRequestError::Axum(_)) => break,
            }
        }
        let count = state.leave(&room, peer_id);
        println!("tickwork signal: peer {peer_id} left room \"{room}\" ({count} of {size})");
    }
}

/// The answer to a player refused before its connection opens.
fn refuse(status: StatusCode, why: String) -> Response {
    Response::builder()
        .status(status)
        .body(why.into())
        .unwrap_or_else(|_| Response::new(axum::body::Body::empty()))
}

/// Runs the server until the process is stopped.
///
/// # Errors
/// [`CliError::Signal`] if the port cannot be bound or the server fails.
#[allow(
    clippy::result_large_err,
    reason = "matchbox's connection callback answers a refusal with axum's Response"
)]
pub fn run(args: &SignalArgs) -> Result<(), CliError> {
    let rooms = Rooms::new(args.clone());
    let admit = rooms.clone();
    let mut server = SignalingServerBuilder::new(SocketAddr::new(args.bind, args.port), RoomTopology, rooms)
        .on_connection_request(move |meta| {
            let room = meta.path.clone().unwrap_or_default();
            if !room_name_ok(&room) {
                let why = format!(
                    "a room's name is 1 to {MAX_ROOM_NAME} letters, digits, '-', '_' or '.' (ws://HOST:PORT/ROOM), \
                     not {room:?}"
                );
                println!("tickwork signal: refused {}: {why}", meta.origin);
                return Err(refuse(StatusCode::BAD_REQUEST, why));
            }
            match admit.refusal(&room) {
                Some(why) => {
                    println!("tickwork signal: refused {} in room \"{room}\": {why}", meta.origin);
                    Err(refuse(StatusCode::CONFLICT, why))
                }
                None => Ok(true),
            }
        })
        .build();
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .map_err(|e| CliError::Signal(format!("cannot start the server's runtime: {e}")))?;
    runtime.block_on(async move {
        let address = server
            .bind()
            .map_err(|e| CliError::Signal(format!("cannot listen on {}:{}: {e}", args.bind, args.port)))?;
        let shown = match address.ip() {
            ip if ip.is_unspecified() => SocketAddr::new(IpAddr::V4(Ipv4Addr::LOCALHOST), address.port()),
            _ => address,
        };
        println!(
            "tickwork signal: listening on {address}: players meet with --room ws://{shown}/ROOM (or a page's \
             ?room=ws://{shown}/ROOM), {} to a room, at most {} rooms",
            args.room_size, args.max_rooms
        );
        server
            .serve()
            .await
            .map_err(|e| CliError::Signal(format!("the server failed: {e}")))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Room names: what a URL's path segment may safely be, within the
    /// limit.
    #[test]
    fn room_names_are_checked() {
        for ok in ["rally", "a", "match-1_b.2", &"r".repeat(MAX_ROOM_NAME)] {
            assert!(room_name_ok(ok), "{ok}");
        }
        for bad in ["", "a/b", "a b", "ä", &"r".repeat(MAX_ROOM_NAME + 1)] {
            assert!(!room_name_ok(bad), "{bad}");
        }
    }
}

//! A [`Link`]: the way to the one other player of a match, whatever
//! carries it (a UDP socket, WebRTC data channels), and [`PeerAddress`],
//! how GGRS and the match's messages name that player.
//!
//! The transport above it (`transport.rs`) reads GGRS's messages and
//! Tickwork's control messages out of what a link receives; a link only
//! moves bytes, and says when the other player is known to be gone.

use std::fmt;
use std::io::ErrorKind;
use std::net::{SocketAddr, UdpSocket};

/// The other player of a match, as GGRS's messages and the match's lines
/// name it: a UDP address (`--host`, `--join`) or a peer of a signalling
/// server's room (WebRTC, `--room`).
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum PeerAddress {
    /// The other player's UDP address.
    Udp(SocketAddr),
    /// The id the signalling server gave the other player in a room.
    Room(String),
}

impl fmt::Display for PeerAddress {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Udp(address) => write!(f, "{address}"),
            Self::Room(id) => write!(f, "peer {id}"),
        }
    }
}

/// The largest message a link passes on: GGRS's messages stay far below
/// it (an input message of a full prediction window is about 1.5 KB); a
/// longer one (or a UDP datagram cut short at this size) is dropped and
/// counted.
pub(super) const MESSAGE_BYTES: usize = 4096;

/// Moves a match's bytes to and from the one other player.
pub(super) trait Link {
    /// Sends one of GGRS's messages: unreliable and unordered is what GGRS
    /// expects (it sends again what is not acknowledged).
    fn send(&mut self, bytes: &[u8]);
    /// Sends one of Tickwork's control messages: reliably where the link
    /// can (WebRTC's reliable channel), else as a datagram that the
    /// sender repeats.
    fn send_control(&mut self, bytes: &[u8]);
    /// Calls `each` with every message from the other player received
    /// since the last call (nothing from anyone else).
    fn receive(&mut self, each: &mut dyn FnMut(&[u8]));
    /// Why the other player is known to have gone (its channels closed),
    /// if it has; a link that cannot tell (UDP) leaves it to GGRS's
    /// timeout.
    fn gone(&mut self) -> Option<String> {
        None
    }
}

/// A [`Link`] over a non-blocking UDP socket bound by the lobby.
#[derive(Debug)]
pub(super) struct UdpLink {
    socket: UdpSocket,
    peer: SocketAddr,
    buffer: Box<[u8; MESSAGE_BYTES]>,
}

impl UdpLink {
    /// The link of `socket` to `peer`.
    ///
    /// # Errors
    /// The socket cannot be made non-blocking.
    pub(super) fn new(socket: UdpSocket, peer: SocketAddr) -> std::io::Result<Self> {
        socket.set_nonblocking(true)?;
        Ok(Self {
            socket,
            peer,
            buffer: Box::new([0; MESSAGE_BYTES]),
        })
    }
}

impl Link for UdpLink {
    fn send(&mut self, bytes: &[u8]) {
        // A lost datagram is what UDP does: GGRS, or the next poll, sends again.
        let _ = self.socket.send_to(bytes, self.peer);
    }

    fn send_control(&mut self, bytes: &[u8]) {
        self.send(bytes);
    }

    fn receive(&mut self, each: &mut dyn FnMut(&[u8])) {
        loop {
            match self.socket.recv_from(&mut self.buffer[..]) {
                // A stranger's datagrams are not the match's.
                Ok((length, from)) if from == self.peer => each(&self.buffer[..length]),
                Ok(_) => {}
                Err(error) if error.kind() == ErrorKind::WouldBlock => break,
                // A datagram socket may report an earlier send's failure
                // (the peer's port closed) here; there may be more to read.
                Err(error) if error.kind() == ErrorKind::ConnectionReset => {}
                Err(_) => break,
            }
        }
    }
}

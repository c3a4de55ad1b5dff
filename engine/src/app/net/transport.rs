//! The UDP transport of a match: GGRS's messages (bincode, as GGRS's own
//! socket sends them) and Tickwork's few control datagrams on one socket.
//!
//! Control datagrams start with [`MAGIC`] and carry RON: the joiner's
//! hello, the host's welcome (the settings both peers must share), and
//! "done" (this peer knows the match's final state and needs nothing more).
//! GGRS ignores datagrams from addresses it does not know; the transport
//! drops anything that is neither a control datagram nor a GGRS message.

use std::cell::RefCell;
use std::io::ErrorKind;
use std::net::{SocketAddr, UdpSocket};
use std::rc::Rc;

use ggrs::{Message, NonBlockingSocket};
use serde::{Deserialize, Serialize};

/// The first bytes of a Tickwork control datagram: the protocol's version,
/// so a peer of another version is not a peer (version 2: inputs carry the
/// keys released in their tick, a fixed-size input four bytes longer).
pub(super) const MAGIC: &[u8] = b"tickwork-net/2 ";

/// The largest datagram read: GGRS's messages stay far below it.
const DATAGRAM_BYTES: usize = 4096;

/// What the peers tell each other outside GGRS.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub(super) enum ControlMessage {
    /// A player asks to join the host's match of `game`.
    Hello {
        /// The joiner's game title.
        game: String,
    },
    /// The host's answer: the settings both simulations must share.
    Welcome(Welcome),
    /// This peer has the match's final state: the tick and its checksum.
    Done {
        /// The match's last tick.
        tick: u64,
        /// The checksum of the state at it.
        checksum: u64,
    },
}

/// The settings of a match, chosen by the host and taken by the joiner.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Welcome {
    /// The game's title.
    pub game: String,
    /// The worlds' seed.
    pub seed: u64,
    /// Fixed steps per second, if the host gave `--hz`.
    pub hz: Option<f64>,
    /// `--integrator`, if the host gave it.
    pub integrator: Option<String>,
}

impl ControlMessage {
    /// The datagram: [`MAGIC`] and the message as RON.
    pub(super) fn encode(&self) -> Vec<u8> {
        let mut bytes = MAGIC.to_vec();
        // A plain enum of strings and numbers always serialises.
        bytes.extend_from_slice(ron::to_string(self).unwrap_or_default().as_bytes());
        bytes
    }

    /// The message in a datagram, if it is a well-formed control datagram.
    pub(super) fn decode(bytes: &[u8]) -> Option<Self> {
        let text = std::str::from_utf8(bytes.strip_prefix(MAGIC)?).ok()?;
        ron::from_str(text).ok()
    }
}

/// What the transport and the session share: the "done" flags of the two
/// ends, and the welcome the host repeats to a joiner that missed it.
#[derive(Debug, Default)]
pub(super) struct Shared {
    /// This peer's final tick and checksum, once known: the transport says
    /// so with every poll.
    pub local_done: Option<(u64, u64)>,
    /// The other peer's final tick and checksum, once it said them.
    pub remote_done: Option<(u64, u64)>,
    /// The host's welcome, answered to every late hello.
    pub welcome: Option<Vec<u8>>,
}

/// GGRS's [`NonBlockingSocket`] over a non-blocking [`UdpSocket`] bound by
/// the lobby, talking to one peer.
#[derive(Debug)]
pub(super) struct UdpTransport {
    socket: UdpSocket,
    peer: SocketAddr,
    buffer: Box<[u8; DATAGRAM_BYTES]>,
    shared: Rc<RefCell<Shared>>,
}

impl UdpTransport {
    /// The transport of `socket`, whose peer is `peer`.
    ///
    /// # Errors
    /// The socket cannot be made non-blocking.
    pub(super) fn new(socket: UdpSocket, peer: SocketAddr, shared: Rc<RefCell<Shared>>) -> std::io::Result<Self> {
        socket.set_nonblocking(true)?;
        Ok(Self {
            socket,
            peer,
            buffer: Box::new([0; DATAGRAM_BYTES]),
            shared,
        })
    }

    fn send_control(&self, message: &ControlMessage) {
        // A lost datagram is what UDP does: the next poll sends again.
        let _ = self.socket.send_to(&message.encode(), self.peer);
    }
}

impl NonBlockingSocket<SocketAddr> for UdpTransport {
    fn send_to(&mut self, msg: &Message, addr: &SocketAddr) {
        if let Ok(bytes) = bincode::serialize(msg) {
            // Unreliable by design: GGRS sends again what is not acknowledged.
            let _ = self.socket.send_to(&bytes, addr);
        }
    }

    fn receive_all_messages(&mut self) -> Vec<(SocketAddr, Message)> {
        let mut messages = Vec::new();
        loop {
            match self.socket.recv_from(&mut self.buffer[..]) {
                Ok((length, from)) => {
                    let bytes = &self.buffer[..length];
                    if bytes.starts_with(MAGIC) {
                        let mut shared = self.shared.borrow_mut();
                        match ControlMessage::decode(bytes) {
                            Some(ControlMessage::Done { tick, checksum }) if from == self.peer => {
                                shared.remote_done = Some((tick, checksum));
                            }
                            Some(ControlMessage::Hello { .. }) if from == self.peer => {
                                if let Some(welcome) = &shared.welcome {
                                    let _ = self.socket.send_to(welcome, from);
                                }
                            }
                            _ => {}
                        }
                    } else if let Ok(message) = bincode::deserialize(bytes) {
                        messages.push((from, message));
                    }
                }
                Err(error) if error.kind() == ErrorKind::WouldBlock => break,
                // A datagram socket may report an earlier send's failure
                // (the peer's port closed) here; there may be more to read.
                Err(error) if error.kind() == ErrorKind::ConnectionReset => {}
                Err(_) => break,
            }
        }
        let done = self.shared.borrow().local_done;
        if let Some((tick, checksum)) = done {
            self.send_control(&ControlMessage::Done { tick, checksum });
        }
        messages
    }
}

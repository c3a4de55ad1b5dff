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
    /// Datagrams from the other peer that were neither a control message
    /// nor a GGRS message (malformed, or cut short at [`DATAGRAM_BYTES`]):
    /// dropped, and counted here for the match's report.
    pub dropped: u64,
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
                    let mut shared = self.shared.borrow_mut();
                    if bytes.starts_with(MAGIC) {
                        match ControlMessage::decode(bytes) {
                            Some(ControlMessage::Done { tick, checksum }) if from == self.peer => {
                                shared.remote_done = Some((tick, checksum));
                            }
                            Some(ControlMessage::Hello { .. }) if from == self.peer => {
                                if let Some(welcome) = &shared.welcome {
                                    let _ = self.socket.send_to(welcome, from);
                                }
                            }
                            None if from == self.peer => shared.dropped = shared.dropped.saturating_add(1),
                            _ => {}
                        }
                    } else if let Ok(message) = bincode::deserialize(bytes) {
                        messages.push((from, message));
                    } else if from == self.peer {
                        shared.dropped = shared.dropped.saturating_add(1);
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Datagrams from the peer that are neither GGRS's nor Tickwork's
    /// (garbage, a control message that does not parse, one cut short past
    /// the read buffer) are dropped and counted, a stranger's are dropped
    /// without counting, and a GGRS message between them still arrives.
    #[test]
    fn malformed_datagrams_from_the_peer_are_dropped_and_counted() {
        let local = UdpSocket::bind("127.0.0.1:0").expect("a local socket");
        let peer = UdpSocket::bind("127.0.0.1:0").expect("the peer's socket");
        let stranger = UdpSocket::bind("127.0.0.1:0").expect("a stranger's socket");
        let (to, peer_address) = (local.local_addr().expect("bound"), peer.local_addr().expect("bound"));
        let shared = Rc::new(RefCell::new(Shared::default()));
        let mut transport = UdpTransport::new(local, peer_address, Rc::clone(&shared)).expect("non-blocking");
        // GGRS's keep-alive (magic 0x1234, the body's eighth variant), as
        // bincode encodes it.
        let keep_alive = [0x34, 0x12, 7, 0, 0, 0];
        assert!(bincode::deserialize::<Message>(&keep_alive).is_ok(), "a GGRS message");
        let mut control = MAGIC.to_vec();
        control.extend_from_slice(b"Done(tick: \"not a number\")");
        let oversized = vec![0xff; DATAGRAM_BYTES + 100];
        for datagram in [&[0xff, 0xfe, 0x00][..], &control, &keep_alive[..], &oversized] {
            peer.send_to(datagram, to).expect("sent");
        }
        stranger.send_to(&[0xff; 8], to).expect("sent");
        // Loopback delivers at once, but not within the sends' calls:
        // read until all five have arrived, bounded by their count.
        let mut received = Vec::new();
        let mut polls = 0;
        while received.is_empty() || shared.borrow().dropped < 3 {
            received.extend(transport.receive_all_messages());
            polls += 1;
            assert!(
                polls < 1_000_000,
                "the datagrams did not arrive: {received:?}, {:?}",
                shared.borrow()
            );
            std::thread::yield_now();
        }
        assert_eq!(received.len(), 1, "the GGRS message arrives: {received:?}");
        assert_eq!(received[0].0, peer_address);
        assert_eq!(
            shared.borrow().dropped,
            3,
            "garbage, a bad control message, an oversized one"
        );
    }
}

//! The transport of a match over a [`Link`]: GGRS's messages (bincode, as
//! GGRS's own socket sends them) and Tickwork's few control messages.
//!
//! Control messages start with [`MAGIC`] and carry RON: the joiner's
//! hello, the host's welcome (the settings both peers must share), the
//! meeting of two players in a room, and "done" (this peer knows the
//! match's final state and needs nothing more). The transport drops (and
//! counts) anything from the other player that is neither a control
//! message nor a GGRS message GGRS can take.

use std::cell::RefCell;
use std::rc::Rc;

use ggrs::{Message, NonBlockingSocket};
use serde::{Deserialize, Serialize};

use super::link::{Link, MESSAGE_BYTES, PeerAddress};

/// The first bytes of a Tickwork control datagram: the protocol's version,
/// so a peer of another version is not a peer (version 2: inputs carry the
/// keys released in their tick, a fixed-size input four bytes longer).
pub(super) const MAGIC: &[u8] = b"tickwork-net/2 ";

/// The most bytes a GGRS input message's run-length-encoded inputs may
/// decode to: far above what a prediction window of inputs takes (GGRS
/// sends at most 128 frames of about a hundred bytes: 14 KB), far below
/// what would strain memory.
pub const MAX_DECODED_INPUT_BYTES: usize = 1 << 16;

/// A datagram from a peer as the GGRS message it holds, where it is one
/// GGRS can take: `None` for bytes that are not a GGRS message, and for an
/// input message whose run-length-encoded inputs are malformed (a varint
/// cut short or past 64 bits; a run past the end, which GGRS would
/// discard itself) or decode to more than [`MAX_DECODED_INPUT_BYTES`].
/// GGRS 0.13 reads those varints without checking them and panics (or
/// tries to allocate what the lengths say) on such bytes, which a damaged
/// datagram or a hostile peer can send; they are refused here, before
/// GGRS reads them.
///
/// The layout read is bincode's (fixed-width little-endian integers, as
/// GGRS's own socket and this transport encode), of GGRS 0.13's
/// `Message`: a `u16` magic, the body's variant as a `u32` (input: 2),
/// and an input's connection statuses (a `u64` count of a `bool` and an
/// `i32` each), `bool`, two `i32` frames, then its bytes (a `u64` length).
#[must_use]
pub fn decode_peer_message(bytes: &[u8]) -> Option<Message> {
    const INPUT: u32 = 2;
    let word = |at: usize, n: usize| -> Option<u64> {
        let field = bytes.get(at..at.checked_add(n)?)?;
        Some(field.iter().rev().fold(0u64, |v, &b| v << 8 | u64::from(b)))
    };
    if word(2, 4)? == u64::from(INPUT) {
        // The statuses (5 bytes each), the flag and the two frames.
        let statuses = usize::try_from(word(6, 8)?).ok()?;
        let at = statuses.checked_mul(5)?.checked_add(6 + 8 + 1 + 4 + 4)?;
        let length = usize::try_from(word(at, 8)?).ok()?;
        let start = at.checked_add(8)?;
        let inputs = bytes.get(start..start.checked_add(length)?)?;
        if rle_decoded_len(inputs)? > MAX_DECODED_INPUT_BYTES {
            return None;
        }
    }
    bincode::deserialize(bytes).ok()
}

/// The length `bitfield-rle` decodes `data` to, if it is well formed: a
/// sequence of varints (seven bits a byte, least significant first, at
/// most ten bytes), each a run of `value >> 2` bytes of 0 or 255 where bit
/// 0 is set, else `value >> 1` literal bytes that follow it.
fn rle_decoded_len(data: &[u8]) -> Option<usize> {
    let (mut at, mut total) = (0usize, 0usize);
    while at < data.len() {
        let mut value = 0u64;
        let mut shift = 0;
        loop {
            let byte = *data.get(at)?;
            at += 1;
            let bits = u64::from(byte & 127);
            if shift > 63 || (shift == 63 && bits > 1) {
                return None;
            }
            value |= bits << shift;
            shift += 7;
            if byte & 128 == 0 {
                break;
            }
        }
        let run = usize::try_from(if value & 1 == 1 { value >> 2 } else { value >> 1 }).ok()?;
        if value & 1 == 0 {
            at = at.checked_add(run).filter(|&end| end <= data.len())?;
        }
        total = total.checked_add(run)?;
    }
    Some(total)
}

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
    /// A player met in a room: its game and settings, the player it asked
    /// to play, and how long it waited there for the other (without a
    /// player asked for, the one that waited longer hosts).
    Meet {
        /// The settings it would host with.
        welcome: Welcome,
        /// Milliseconds from its joining the room to the other's arrival.
        waited_ms: u64,
        /// The player it asked to play (`--player`, 1 hosts), if any.
        #[serde(default)]
        player: Option<u8>,
    },
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
    /// nor a GGRS message GGRS can take (malformed, or what is left of one
    /// cut short at [`MESSAGE_BYTES`] no message): dropped, and counted
    /// here for the match's report.
    pub dropped: u64,
    /// Why the other player is known to have left (its link says so).
    pub remote_left: Option<String>,
}

/// GGRS's [`NonBlockingSocket`] over a [`Link`] to the other player: GGRS's
/// messages go out as they are; what arrives is sorted into GGRS's
/// messages, Tickwork's control messages and what is neither (dropped and
/// counted).
#[derive(Debug)]
pub(super) struct Transport<L> {
    link: L,
    peer: PeerAddress,
    shared: Rc<RefCell<Shared>>,
}

impl<L: Link> Transport<L> {
    /// The transport over `link`, whose other end GGRS knows as `peer`.
    pub(super) fn new(link: L, peer: PeerAddress, shared: Rc<RefCell<Shared>>) -> Self {
        Self { link, peer, shared }
    }
}

impl<L: Link> NonBlockingSocket<PeerAddress> for Transport<L> {
    fn send_to(&mut self, msg: &Message, _addr: &PeerAddress) {
        if let Ok(bytes) = bincode::serialize(msg) {
            self.link.send(&bytes);
        }
    }

    fn receive_all_messages(&mut self) -> Vec<(PeerAddress, Message)> {
        let mut messages = Vec::new();
        let mut answer_hello = false;
        let (peer, shared) = (&self.peer, &self.shared);
        self.link.receive(&mut |bytes| {
            let mut shared = shared.borrow_mut();
            if bytes.len() >= MESSAGE_BYTES {
                shared.dropped = shared.dropped.saturating_add(1);
            } else if bytes.starts_with(MAGIC) {
                match ControlMessage::decode(bytes) {
                    Some(ControlMessage::Done { tick, checksum }) => shared.remote_done = Some((tick, checksum)),
                    Some(ControlMessage::Hello { .. }) => answer_hello = true,
                    Some(_) => {}
                    None => shared.dropped = shared.dropped.saturating_add(1),
                }
            } else if let Some(message) = decode_peer_message(bytes) {
                messages.push((peer.clone(), message));
            } else {
                shared.dropped = shared.dropped.saturating_add(1);
            }
        });
        let gone = self.link.gone();
        let mut shared = self.shared.borrow_mut();
        if let Some(why) = gone {
            shared.remote_left.get_or_insert(why);
        }
        // A joiner that missed the welcome says hello again.
        if let (true, Some(welcome)) = (answer_hello, &shared.welcome) {
            self.link.send_control(welcome);
        }
        if let Some((tick, checksum)) = shared.local_done {
            self.link
                .send_control(&ControlMessage::Done { tick, checksum }.encode());
        }
        messages
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::net::link::UdpLink;
    use std::net::UdpSocket;

    /// GGRS's input message (magic 0x1234, no connection statuses, frames
    /// 0 and -1) carrying `inputs` as its run-length-encoded bytes.
    fn input_message(inputs: &[u8]) -> Vec<u8> {
        let mut bytes = vec![0x34, 0x12];
        bytes.extend_from_slice(&2u32.to_le_bytes());
        bytes.extend_from_slice(&0u64.to_le_bytes());
        bytes.push(0);
        bytes.extend_from_slice(&0i32.to_le_bytes());
        bytes.extend_from_slice(&(-1i32).to_le_bytes());
        bytes.extend_from_slice(&(inputs.len() as u64).to_le_bytes());
        bytes.extend_from_slice(inputs);
        bytes
    }

    /// An input message whose encoded inputs GGRS would decode is taken;
    /// one whose encoding is cut short, runs past its end or decodes to
    /// more than the limit (which GGRS would try to allocate) is refused.
    #[test]
    fn input_messages_ggrs_cannot_decode_are_refused() {
        // Two literal bytes, then a run of 8 bytes of 255 (8 << 2 | 3).
        assert!(decode_peer_message(&input_message(&[4, 7, 9, 35])).is_some());
        assert_eq!(rle_decoded_len(&[4, 7, 9, 35]), Some(10));
        // A varint of ten bytes, the most 64 bits take, is read (here an
        // empty literal run); an eleventh byte is refused.
        let ten = [0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x00];
        assert_eq!(rle_decoded_len(&ten), Some(0));
        assert_eq!(
            rle_decoded_len(&[0x80; 10].iter().copied().chain([0]).collect::<Vec<_>>()),
            None
        );
        let huge_run = {
            let mut varint = Vec::new();
            let mut value = (1u64 << 40) << 2 | 1;
            while value >= 128 {
                varint.push(value as u8 | 128);
                value >>= 7;
            }
            varint.push(value as u8);
            varint
        };
        for (inputs, why) in [
            (&[0x80][..], "a varint cut short"),
            (&[4, 7][..], "a literal run past the end"),
            (&[0xff; 11][..], "a varint past 64 bits"),
            (&huge_run[..], "a run of 2^40 bytes"),
        ] {
            assert_eq!(decode_peer_message(&input_message(inputs)).map(|_| ()), None, "{why}");
        }
        // The input's declared length past the datagram.
        let mut short = input_message(&[4, 7, 9]);
        short.truncate(short.len() - 1);
        assert!(decode_peer_message(&short).is_none());
    }

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
        let link = UdpLink::new(local, peer_address).expect("non-blocking");
        let mut transport = Transport::new(link, PeerAddress::Udp(peer_address), Rc::clone(&shared));
        // GGRS's keep-alive (magic 0x1234, the body's eighth variant), as
        // bincode encodes it.
        let keep_alive = [0x34, 0x12, 7, 0, 0, 0];
        assert!(bincode::deserialize::<Message>(&keep_alive).is_ok(), "a GGRS message");
        let mut control = MAGIC.to_vec();
        control.extend_from_slice(b"Done(tick: \"not a number\")");
        let oversized = vec![0xff; MESSAGE_BYTES + 100];
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
        assert_eq!(received[0].0, PeerAddress::Udp(peer_address));
        assert_eq!(
            shared.borrow().dropped,
            3,
            "garbage, a bad control message, an oversized one"
        );
    }
}

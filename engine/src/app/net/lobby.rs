//! Finding the other player: the host listens on a UDP port, the joiner
//! says hello to it until the host welcomes it with the match's settings.
//! GGRS needs both addresses before it starts; this is how each side
//! learns the other's.

use std::net::{Ipv4Addr, Ipv6Addr, SocketAddr, UdpSocket};
use std::time::Duration;

use crate::platform::Instant;

use super::transport::{ControlMessage, Welcome};
use crate::app::RunError;

/// Which side of a match this machine is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Peer {
    /// Hosts on a UDP port (0: one the system picks) and plays player 0.
    Host {
        /// The port.
        port: u16,
    },
    /// Joins the host at an address and plays player 1.
    Join {
        /// The host's address.
        host: SocketAddr,
    },
}

impl Peer {
    /// The player this side plays: the host 0, the joiner 1.
    #[must_use]
    pub fn player(self) -> usize {
        match self {
            Self::Host { .. } => 0,
            Self::Join { .. } => 1,
        }
    }
}

/// A bound socket, before the other player is found.
#[derive(Debug)]
pub struct Lobby {
    socket: UdpSocket,
    peer: Peer,
}

/// The other player found: the socket, their address and the match's
/// settings.
#[derive(Debug)]
pub(super) struct Connection {
    pub socket: UdpSocket,
    pub remote: SocketAddr,
    pub welcome: Welcome,
}

fn network_error(what: impl core::fmt::Display) -> RunError {
    RunError::Network(what.to_string())
}

impl Lobby {
    /// Binds the socket of `peer`: the host's port, or any port for a joiner.
    ///
    /// # Errors
    /// [`RunError::Network`] if the port cannot be bound (in use, or
    /// reserved).
    pub fn bind(peer: Peer) -> Result<Self, RunError> {
        let local = match peer {
            Peer::Host { port } => SocketAddr::from((Ipv4Addr::UNSPECIFIED, port)),
            Peer::Join { host } if host.is_ipv6() => SocketAddr::from((Ipv6Addr::UNSPECIFIED, 0)),
            Peer::Join { .. } => SocketAddr::from((Ipv4Addr::UNSPECIFIED, 0)),
        };
        let socket = UdpSocket::bind(local).map_err(|e| network_error(format!("cannot bind UDP {local}: {e}")))?;
        Ok(Self { socket, peer })
    }

    /// The local address (the port a host listens on, once bound).
    ///
    /// # Errors
    /// [`RunError::Network`] if the system cannot say.
    pub fn local_addr(&self) -> Result<SocketAddr, RunError> {
        self.socket.local_addr().map_err(network_error)
    }

    /// Which side this is.
    #[must_use]
    pub fn peer(&self) -> Peer {
        self.peer
    }

    /// Finds the other player within `wait`: a host waits for a hello of
    /// its game and answers with `welcome`; a joiner says hello every
    /// 100 ms until welcomed (and takes the welcome's settings).
    pub(super) fn connect(self, welcome: Welcome, wait: Duration) -> Result<Connection, RunError> {
        let started = Instant::now();
        let mut buffer = [0u8; 2048];
        let left = |what: &str| {
            wait.checked_sub(started.elapsed())
                .filter(|left| !left.is_zero())
                .ok_or_else(|| {
                    network_error(format!(
                        "{what} within {} s (NetOptions::wait_seconds; raise it with --wait-seconds)",
                        wait.as_secs_f64()
                    ))
                })
        };
        match self.peer {
            Peer::Host { .. } => loop {
                let left = left("no player joined")?;
                self.socket.set_read_timeout(Some(left)).map_err(network_error)?;
                let (length, from) = match self.socket.recv_from(&mut buffer) {
                    Ok(got) => got,
                    Err(e) if matches!(e.kind(), std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut) => {
                        continue;
                    }
                    Err(e) => return Err(network_error(e)),
                };
                let Some(ControlMessage::Hello { game }) = ControlMessage::decode(&buffer[..length]) else {
                    continue;
                };
                // The answer tells a joiner of another game what is played here.
                let _ = self
                    .socket
                    .send_to(&ControlMessage::Welcome(welcome.clone()).encode(), from);
                if game == welcome.game {
                    return Ok(Connection {
                        socket: self.socket,
                        remote: from,
                        welcome,
                    });
                }
                crate::say!(
                    "tickwork: {from} wants to play \"{game}\", not \"{}\"; still waiting",
                    welcome.game
                );
            },
            Peer::Join { host } => {
                let hello = ControlMessage::Hello { game: welcome.game }.encode();
                loop {
                    let left = left(&format!("the host at {host} did not answer"))?;
                    self.socket.send_to(&hello, host).map_err(network_error)?;
                    let resend = Duration::from_millis(100).min(left);
                    self.socket.set_read_timeout(Some(resend)).map_err(network_error)?;
                    match self.socket.recv_from(&mut buffer) {
                        Ok((length, from)) if from == host => {
                            if let Some(ControlMessage::Welcome(welcome)) = ControlMessage::decode(&buffer[..length]) {
                                return Ok(Connection {
                                    socket: self.socket,
                                    remote: host,
                                    welcome,
                                });
                            }
                        }
                        Ok(_) => {}
                        Err(e) if matches!(e.kind(), std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut) => {
                        }
                        // The host's port is not open yet (Windows says
                        // "reset"): say hello again.
                        Err(e)
                            if matches!(
                                e.kind(),
                                std::io::ErrorKind::ConnectionRefused | std::io::ErrorKind::ConnectionReset
                            ) =>
                        {
                            std::thread::sleep(resend);
                        }
                        Err(e) => return Err(network_error(e)),
                    }
                }
            }
        }
    }
}

//! How a [`NetSession`] starts: the other player found over UDP
//! ([`NetSession::start`]) or met in a signalling server's room
//! ([`NetSession::start_in_room`]), then one way on for both: the
//! settings checked, the game session made, GGRS's session built over the
//! link.

use std::cell::RefCell;
use std::rc::Rc;
use std::time::Duration;

use ggrs::{DesyncDetection, PlayerType, SessionBuilder};

use super::net_session::{NetSession, Script, ggrs_error};
use crate::app::api::stage::Settings;
use crate::app::net::impairment::ImpairedSocket;
use crate::app::net::link::{Link, PeerAddress, UdpLink};
use crate::app::net::lobby::{Lobby, Peer};
use crate::app::net::net_options::NetOptions;
use crate::app::net::rollback::{Rollback, RollbackCursor};
use crate::app::net::transport::{ControlMessage, Shared, Transport, Welcome};
use crate::app::{Game, GameError, GameSession, RunError, SessionOptions};
use crate::input::{Recording, TickInput};
use crate::platform::Instant;

/// The other player found, however: what the match starts from.
struct Found<L> {
    link: L,
    remote: PeerAddress,
    /// The host's settings, the match's.
    welcome: Welcome,
    /// Whether this side hosts (player 1; its settings are the match's).
    host: bool,
    /// The welcome to answer a late hello with (a UDP host's).
    repeat: Option<Vec<u8>>,
}

impl<G: Game + Clone + 'static> NetSession<G> {
    /// Finds the other player from `lobby` and starts the match: the host's
    /// seed, rate and integrator (from `options`) are the joiner's too.
    /// `script` plays this side's input from a recording (tests, bots).
    ///
    /// # Errors
    /// [`RunError::Network`] if the other player is not found in time or
    /// plays another game, [`RunError::Limit`] for options out of range,
    /// [`RunError::Game`] for a game that does not have two players or
    /// whose set-up fails.
    pub fn start(
        game: G,
        lobby: Lobby,
        options: SessionOptions,
        net: &NetOptions,
        script: Option<Recording>,
    ) -> Result<Self, RunError> {
        let own = check_match(&game, &options, net, script.as_ref())?;
        let wait = Duration::from_secs_f64(net.wait_seconds);
        let peer = lobby.peer();
        let connection = lobby.connect(own.clone(), wait)?;
        let welcome = connection.welcome;
        if let Peer::Join { host } = peer {
            check_welcome(&own, &welcome, &format!("the host at {host}"))?;
        }
        let host = matches!(peer, Peer::Host { .. });
        let found = Found {
            link: UdpLink::new(connection.socket, connection.remote).map_err(|e| RunError::Network(e.to_string()))?,
            remote: PeerAddress::Udp(connection.remote),
            repeat: host.then(|| ControlMessage::Welcome(welcome.clone()).encode()),
            welcome,
            host,
        };
        Self::begin(game, found, options, net, script)
    }

    /// Meets the other player in the signalling server's room at `url`
    /// (`ws://HOST:PORT/ROOM`) and starts the match over WebRTC: a side
    /// that asked for a player ([`NetOptions::player`]) plays it, else the
    /// first to come hosts (player 1, its settings the match's). Natively
    /// the future blocks while it waits; in a page it yields to the
    /// browser.
    ///
    /// # Errors
    /// As [`start`](Self::start); [`RunError::Limit`] for a URL that is
    /// not a room's; [`RunError::Network`] if the server refuses this side
    /// (the room is full) or cannot be reached, the other player leaves
    /// before the match begins, or both asked to play the same player.
    #[cfg(feature = "webrtc")]
    pub async fn start_in_room(
        game: G,
        url: &str,
        options: SessionOptions,
        net: &NetOptions,
        script: Option<Recording>,
    ) -> Result<Self, RunError> {
        let own = check_match(&game, &options, net, script.as_ref())?;
        let room = crate::app::net::room::Room::open(url)?;
        crate::say!(
            "tickwork: {}: in the room {url}, waiting for the other player",
            own.game
        );
        let met = room
            .meet(&own, net.player, Duration::from_secs_f64(net.wait_seconds))
            .await?;
        if !met.host {
            check_welcome(&own, &met.welcome, &format!("the host ({})", met.remote))?;
        }
        let found = Found {
            link: met.link,
            remote: met.remote,
            welcome: met.welcome,
            host: met.host,
            repeat: None,
        };
        Self::begin(game, found, options, net, script)
    }

    /// The match with the other player found: the game session with the
    /// host's settings, GGRS's session over the link.
    fn begin<L: Link + 'static>(
        game: G,
        found: Found<L>,
        options: SessionOptions,
        net: &NetOptions,
        script: Option<Recording>,
    ) -> Result<Self, RunError> {
        // Synchronising gets a wait of its own.
        let started = Instant::now();
        let welcome = &found.welcome;
        let session = GameSession::new(
            game,
            SessionOptions {
                settings: Settings {
                    integrator: welcome.integrator.clone(),
                    seed: welcome.seed,
                    networked: true,
                    gpu: false,
                },
                hz: welcome.hz,
                record: None,
                replay: None,
                ..options
            },
        )?;
        let shared = Rc::new(RefCell::new(Shared {
            welcome: found.repeat,
            ..Shared::default()
        }));
        let transport = Transport::new(found.link, found.remote.clone(), Rc::clone(&shared));
        let fps = session.clock().timeline().rate().hz_value().round().max(1.0) as usize;
        let local = usize::from(!found.host);
        let builder = SessionBuilder::<Rollback<G>>::new()
            .with_num_players(2)
            .map_err(ggrs_error)?
            .with_input_delay(net.input_delay)
            .with_max_prediction_window(net.max_prediction)
            .with_desync_detection_mode(DesyncDetection::On {
                interval: net.desync_interval,
            })
            .with_fps(fps)
            .map_err(ggrs_error)?
            .with_disconnect_timeout(Duration::from_secs_f64(net.disconnect_seconds))
            .add_player(PlayerType::Local, local)
            .map_err(ggrs_error)?
            .add_player(PlayerType::Remote(found.remote.clone()), 1 - local)
            .map_err(ggrs_error)?;
        let p2p = match net.impairment {
            Some(impairment) => builder.start_p2p_session(ImpairedSocket::new(transport, impairment)),
            None => builder.start_p2p_session(transport),
        }
        .map_err(ggrs_error)?;
        Ok(Self {
            session,
            p2p,
            broken: None,
            local,
            remote: found.remote,
            shared,
            cursor: RollbackCursor::new(0),
            pending: None,
            script: script.map(|recording| Script {
                recording,
                cursor: 0,
                input: TickInput::default(),
            }),
            played: Vec::new(),
            certain_ticks: 0,
            skip: 0,
            end: None,
            final_state: None,
            settled: false,
            remote_gone: false,
            lockstep: net.max_prediction == 0,
            waits: 0,
            skipped: 0,
            started,
            wait: Duration::from_secs_f64(net.wait_seconds),
        })
    }
}

/// Checks that `game` can play a match with `script`, and gives this
/// side's settings: what it hosts with.
fn check_match<G: Game>(
    game: &G,
    options: &SessionOptions,
    net: &NetOptions,
    script: Option<&Recording>,
) -> Result<Welcome, RunError> {
    net.check()?;
    let title = game.title().to_owned();
    if game.players() != 2 {
        return Err(RunError::Game(GameError::Message(format!(
            "\"{title}\" has {} player(s); a networked match (--host, --join, --room) needs a game of 2",
            game.players()
        ))));
    }
    if let Some(script) = script
        && (script.game != title || script.players() != 1)
    {
        return Err(RunError::Game(GameError::Message(format!(
            "the recording is of {} player(s) of \"{}\"; a networked match plays one player's recording of \
             \"{title}\" for this side",
            script.players(),
            script.game
        ))));
    }
    Ok(Welcome {
        game: title,
        seed: options.settings.seed,
        hz: options.hz,
        integrator: options.settings.integrator.clone(),
    })
}

/// Checks the host's `welcome` against this joiner's own settings: the
/// same game, and no setting given here that differs from the host's.
fn check_welcome(own: &Welcome, welcome: &Welcome, host: &str) -> Result<(), RunError> {
    if welcome.game != own.game {
        return Err(RunError::Network(format!(
            "{host} plays \"{}\", not \"{}\"",
            welcome.game, own.game
        )));
    }
    let differs = [
        ("--seed", own.seed != 0 && own.seed != welcome.seed),
        ("--hz", own.hz.is_some() && own.hz != welcome.hz),
        (
            "--integrator",
            own.integrator.is_some() && own.integrator != welcome.integrator,
        ),
    ];
    if let Some((flag, _)) = differs.iter().find(|d| d.1) {
        return Err(RunError::Network(format!(
            "{flag} differs from the host's (seed {}, hz {}, integrator {}): a joiner plays with the host's \
             settings; leave {flag} out",
            welcome.seed,
            welcome.hz.map_or_else(|| "the game's".to_owned(), |hz| hz.to_string()),
            welcome.integrator.as_deref().unwrap_or("the game's"),
        )));
    }
    Ok(())
}

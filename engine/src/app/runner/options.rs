//! The command-line options every game shares ([`RunOptions`], a clap
//! `Args` to flatten into a game's own parser) and their value parsers.

use std::path::PathBuf;

/// The options every game shares on the command line (with the `cli`
/// feature: a clap `Args`), or filled in code (`RunOptions::default()`).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
pub struct RunOptions {
    /// Integrator by registry name (see `tickwork integrators`); a game that
    /// races integrators takes a comma-separated list. An error in a game
    /// that fixes every world's integrator to others (the tops).
    #[cfg_attr(feature = "cli", arg(long))]
    pub integrator: Option<String>,
    /// Fixed steps per second (default: the game's, usually 60).
    #[cfg_attr(feature = "cli", arg(long, value_parser = positive_f64, allow_hyphen_values = true))]
    pub hz: Option<f64>,
    /// Simulated seconds per real second.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = 1.0, value_parser = positive_f64, allow_hyphen_values = true))]
    pub time_scale: f64,
    /// Draw off-screen even when a display is available.
    #[cfg_attr(feature = "cli", arg(long))]
    pub headless: bool,
    /// Frames to run (default: until the window is closed; 300 off-screen,
    /// or as many as a replayed recording needs).
    #[cfg_attr(feature = "cli", arg(long, allow_negative_numbers = true))]
    pub frames: Option<u64>,
    /// Off-screen: directory for the PNG frames (default: a new
    /// `tickwork-out/<game>` directory).
    #[cfg_attr(feature = "cli", arg(long))]
    pub out: Option<PathBuf>,
    /// Off-screen: the animated GIF (default: `<game>.gif` in the frames'
    /// directory).
    #[cfg_attr(feature = "cli", arg(long))]
    pub gif: Option<PathBuf>,
    /// Off-screen: draw every frame but write none, and say how long a
    /// frame took (a timing run).
    #[cfg_attr(feature = "cli", arg(long, conflicts_with_all = ["out", "gif"]))]
    pub no_frames: bool,
    /// Window or frame size, WIDTHxHEIGHT (default: 1280x720 in a window,
    /// 640x360 off-screen).
    #[cfg_attr(feature = "cli", arg(long, value_parser = parse_size, allow_hyphen_values = true))]
    pub size: Option<(u32, u32)>,
    /// Seed of the worlds' random generators.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = 0, allow_negative_numbers = true))]
    pub seed: u64,
    /// Record the keys of every tick to this file (RON) when the run ends.
    #[cfg_attr(feature = "cli", arg(long, conflicts_with = "replay"))]
    pub record: Option<PathBuf>,
    /// Replay a recording instead of the keyboard, with its rate and seed.
    #[cfg_attr(feature = "cli", arg(long))]
    pub replay: Option<PathBuf>,
    /// Frame durations from a simulated display at this rate (default: the
    /// real clock in a window, 60 Hz off-screen).
    #[cfg_attr(feature = "cli", arg(long, value_parser = display_hz, allow_hyphen_values = true))]
    pub display_hz: Option<f64>,
    /// Window: after `--frames`, keep showing the last frame this many
    /// seconds before closing (for a screenshot from outside).
    #[cfg_attr(feature = "cli", arg(long, default_value_t = 0.0, value_parser = non_negative_seconds, allow_hyphen_values = true))]
    pub hold: f64,
    /// Overwrite existing frames, GIF or recording.
    #[cfg_attr(feature = "cli", arg(long))]
    pub force: bool,
    /// Start with the control panel shown (F1 toggles it; default: as the
    /// game says, hidden for games, shown for the lab's demos).
    #[cfg_attr(feature = "cli", arg(long, conflicts_with = "no_panel"))]
    pub panel: bool,
    /// Start with the control panel hidden (F1 toggles it).
    #[cfg_attr(feature = "cli", arg(long))]
    pub no_panel: bool,
    /// Run headless under a rollback sync test instead: every tick, roll
    /// back this many ticks (1-7) and re-simulate, failing at the first tick
    /// whose state differs (with `--replay`, its inputs; `--frames` ticks,
    /// default 300 or the recording's).
    #[cfg(feature = "netcode")]
    #[cfg_attr(
        feature = "cli",
        arg(long, value_name = "TICKS", conflicts_with = "record", allow_negative_numbers = true)
    )]
    pub sync_test: Option<usize>,
    /// Host a two-player match on this UDP port (0: any free port, printed)
    /// and play player 1 (the other player runs `--join`).
    #[cfg(feature = "netcode")]
    #[cfg_attr(feature = "cli", arg(long, value_name = "PORT", conflicts_with_all = ["join", "sync_test"]))]
    pub host: Option<u16>,
    /// Join the match hosted at this address (`192.168.1.20:7000`) and play
    /// player 2, with the host's seed, rate and integrator.
    #[cfg(feature = "netcode")]
    #[cfg_attr(feature = "cli", arg(long, value_name = "ADDR", conflicts_with = "sync_test"))]
    pub join: Option<std::net::SocketAddr>,
    /// Meet the other player in this room of a signalling server
    /// (`ws://HOST:PORT/ROOM`, as `tickwork signal` prints) and play over
    /// WebRTC: the first in the room hosts and plays player 1, unless a
    /// side asks for a player (`--player`). A page takes it as `?room=`.
    #[cfg(feature = "webrtc")]
    #[cfg_attr(
        feature = "cli",
        arg(long, value_name = "URL", conflicts_with_all = ["host", "join", "sync_test"])
    )]
    pub room: Option<String>,
    /// With `--room`: play this player, 1 (who hosts) or 2, whichever side
    /// comes first (the other takes the other; two who ask for the same
    /// one are refused). Without it the first in the room hosts, which a
    /// busy machine can mistake. A page takes it as `?player=`.
    #[cfg(feature = "webrtc")]
    #[cfg_attr(
        feature = "cli",
        arg(long, value_name = "1|2", requires = "room", value_parser = clap::value_parser!(u8).range(1..=2))
    )]
    pub player: Option<u8>,
    /// In a match: play this side from a recording of one player's input
    /// (`--record` of a run alone) instead of the keyboard (tests, bots).
    #[cfg(feature = "netcode")]
    #[cfg_attr(feature = "cli", arg(long, value_name = "FILE", conflicts_with = "replay"))]
    pub script: Option<PathBuf>,
    /// In a match: ticks a player's input waits before it counts; hides
    /// that much latency without a rollback (0-8).
    #[cfg(feature = "netcode")]
    #[cfg_attr(feature = "cli", arg(long, default_value_t = 2, value_name = "TICKS"))]
    pub input_delay: usize,
    /// In a match: ticks this side runs ahead on predicted input before it
    /// waits for the other player (0-16; 0 is lockstep).
    #[cfg(feature = "netcode")]
    #[cfg_attr(feature = "cli", arg(long, default_value_t = 8, value_name = "TICKS"))]
    pub max_prediction: usize,
    /// In a match: delay, jitter and loss laid on what this side sends,
    /// `LATENCY_MS,JITTER_MS,LOSS[,SEED]` (for example `60,20,0.05`), to
    /// try a bad network on one machine.
    #[cfg(feature = "netcode")]
    #[cfg_attr(feature = "cli", arg(long, value_name = "SPEC"))]
    pub impair: Option<crate::app::Impairment>,
    /// In a match: seconds to wait for the other player to join or answer.
    #[cfg(feature = "netcode")]
    #[cfg_attr(feature = "cli", arg(long, default_value_t = 60.0, value_parser = positive_f64))]
    pub wait_seconds: f64,
    /// In a page: the graphics backend, `webgpu` or `webgl2` (default:
    /// WebGPU where the browser has it, else WebGL2). Natively
    /// `WGPU_BACKEND` chooses.
    #[cfg_attr(feature = "cli", arg(long, value_parser = ["webgpu", "webgl2"]))]
    pub backend: Option<String>,
    /// Step every world's particles on the GPU (compute shaders, drawn
    /// from the GPU's buffers); what the GPU step does not do is an error
    /// naming it.
    #[cfg_attr(feature = "cli", arg(long))]
    pub gpu: bool,
}

impl Default for RunOptions {
    fn default() -> Self {
        Self {
            integrator: None,
            hz: None,
            time_scale: 1.0,
            headless: false,
            frames: None,
            out: None,
            gif: None,
            no_frames: false,
            size: None,
            seed: 0,
            record: None,
            replay: None,
            display_hz: None,
            hold: 0.0,
            force: false,
            panel: false,
            no_panel: false,
            #[cfg(feature = "netcode")]
            sync_test: None,
            #[cfg(feature = "netcode")]
            host: None,
            #[cfg(feature = "netcode")]
            join: None,
            #[cfg(feature = "webrtc")]
            room: None,
            #[cfg(feature = "webrtc")]
            player: None,
            #[cfg(feature = "netcode")]
            script: None,
            #[cfg(feature = "netcode")]
            input_delay: 2,
            #[cfg(feature = "netcode")]
            max_prediction: 8,
            #[cfg(feature = "netcode")]
            impair: None,
            #[cfg(feature = "netcode")]
            wait_seconds: 60.0,
            backend: None,
            gpu: false,
        }
    }
}

#[cfg(feature = "netcode")]
impl RunOptions {
    /// The networked side of these options: the peer (`--host`, `--join`)
    /// and how the match is played, if a match was asked for.
    #[must_use]
    pub fn network(&self) -> Option<(crate::app::Peer, crate::app::NetOptions)> {
        let peer = match (self.host, self.join) {
            (Some(port), _) => crate::app::Peer::Host { port },
            (None, Some(host)) => crate::app::Peer::Join { host },
            (None, None) => return None,
        };
        Some((peer, self.net_options()))
    }

    /// How a match is played (`--input-delay`, `--max-prediction`,
    /// `--impair`, `--wait-seconds`), over UDP or in a room.
    #[must_use]
    pub fn net_options(&self) -> crate::app::NetOptions {
        crate::app::NetOptions {
            input_delay: self.input_delay,
            max_prediction: self.max_prediction,
            impairment: self.impair,
            wait_seconds: self.wait_seconds,
            #[cfg(feature = "webrtc")]
            player: self.player,
            ..crate::app::NetOptions::default()
        }
    }
}

/// A command line of only the shared options.
#[cfg(feature = "cli")]
#[derive(clap::Parser)]
#[command(
    about = "Runs a Tickwork game: in a window when a display is available, else off-screen into PNG frames and \
             a GIF.",
    after_help = "Window keys: F1 control panel, P pause, . single step, +/- time scale, Tab or 1-9 integrator, \
                  F5 restart, F12 screenshot, Escape quit; the arrows, Space, Enter and letters go to the game."
)]
struct SharedCommandLine {
    #[command(flatten)]
    options: RunOptions,
}

#[cfg(feature = "cli")]
impl RunOptions {
    /// Parses the program's command line (exits with clap's message and
    /// usage for bad options, `--help` lists them). Games with options of
    /// their own flatten [`RunOptions`] into their parser instead.
    #[must_use]
    pub fn from_args() -> Self {
        parse_args::<SharedCommandLine>().options
    }
}

/// Parses the program's command line into `P`: the process's arguments,
/// or in a page its URL query (`?hz=120&seed=3`, see
/// [`platform::args`](crate::platform::args)), by the same parser. A bad
/// option exits with clap's message and usage, which a page shows on the
/// console and on the page; `--help` prints the options. Games with
/// options of their own call it with their parser.
#[cfg(feature = "cli")]
#[must_use]
pub fn parse_args<P: clap::Parser>() -> P {
    match P::try_parse_from(crate::platform::args()) {
        Ok(parsed) => parsed,
        // Natively clap prints (with colour on a terminal) and exits.
        Err(error) if !crate::platform::IS_WEB => error.exit(),
        Err(error) => {
            let text = error.render().to_string();
            if error.use_stderr() {
                crate::platform::complain(text.trim_end());
            } else {
                crate::platform::say(text.trim_end());
            }
            crate::platform::exit(error.exit_code())
        }
    }
}

/// Parses `WIDTHxHEIGHT` (`1280x720`) into positive pixel counts.
///
/// # Errors
/// A message quoting the text for anything else.
pub fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let (w, h) = text
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("expected WIDTHxHEIGHT, e.g. 1280x720, got {text:?}"))?;
    let side = |s: &str| {
        s.trim()
            .parse::<u32>()
            .ok()
            .filter(|&v| v > 0)
            .ok_or_else(|| format!("{s:?} in {text:?} is not a positive whole number of pixels"))
    };
    Ok((side(w)?, side(h)?))
}

/// Parses a finite number of seconds, 0 or more (a command-line value
/// parser: the error names the value; clap adds the option).
///
/// # Errors
/// A message naming the value.
pub fn non_negative_seconds(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v >= 0.0 => Ok(v),
        _ => Err(format!("{text:?} is not a finite number of seconds, 0 or more")),
    }
}

/// The slowest simulated display: a frame an hour (the clock's longest frame).
pub const MIN_DISPLAY_HZ: f64 = 1.0 / crate::clock::FixedClock::MAX_FRAME_TIME;
/// The fastest simulated display: a million frames a second (a microsecond,
/// the shortest fixed step; `1e300` once made every frame last no time).
pub const MAX_DISPLAY_HZ: f64 = crate::clock::Rate::MAX_HZ;

/// Parses a simulated display's rate (`--display-hz`), within
/// [`MIN_DISPLAY_HZ`] and [`MAX_DISPLAY_HZ`].
///
/// # Errors
/// A message naming the value and the accepted range.
pub fn display_hz(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(v) if (MIN_DISPLAY_HZ..=MAX_DISPLAY_HZ).contains(&v) => Ok(v),
        Ok(_) => Err(format!(
            "{text:?} is outside the accepted range, from 1/3600 (MIN_DISPLAY_HZ) to 1e6 (MAX_DISPLAY_HZ) \
             frames per second"
        )),
        Err(_) => Err(format!("{text:?} is not a number of frames per second")),
    }
}

#[cfg_attr(not(feature = "cli"), allow(dead_code))]
fn positive_f64(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("{text:?} is not a positive, finite number")),
    }
}

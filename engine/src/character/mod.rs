//! A kinematic character: an upright box in the z = 0 plane that a game
//! drives (run, jump) and the world moves in its fixed step, sliding
//! against the world's planes and boxes, as Rapier's
//! `KinematicCharacterController` and a Celeste-style `Actor` do.
//!
//! Each step, after the kinematic colliders have moved
//! (`World::step`), every character in the order added:
//!
//! 1. rides the ground it stood on: a moving platform carries it by the
//!    platform's own move this step (blocked by anything else in the way);
//! 2. is pushed out of anything that moved into it;
//! 3. jumps if a jump is buffered and it stands, or left the ground at
//!    most [`CharacterConfig::coyote_ticks`] steps ago ("coyote time"); a
//!    jump asked for in the air is kept
//!    [`CharacterConfig::jump_buffer_ticks`] steps ("jump buffering");
//! 4. falls: its velocity gains [`CharacterConfig::gravity`] times the step;
//! 5. moves across (x), then up or down (y), each move stopping
//!    [`CharacterConfig::skin`] short of the first surface in its way.
//!    Across, an edge at most [`CharacterConfig::step_height`] above its
//!    feet is stepped onto; up or down, what stops a fall is its ground
//!    (collider, normal, velocity), what stops a rise its ceiling;
//! 6. snaps down onto ground at most [`CharacterConfig::snap_distance`]
//!    below, if it stood on ground before the step and did not jump
//!    (walking down a step or off a platform's lip keeps it grounded).
//!
//! **No seams.** A character keeps its skin of space to every surface, so
//! it slides along a floor of many boxes, or a wall of stacked ones,
//! without meeting their shared edges: moving across, it is never level
//! with a box top it stands on.
//!
//! **What it meets.** The world's colliders by their declared form
//! ([`Collider::gpu_form`](crate::Collider::gpu_form)): solid boxes and
//! containers whose z range holds 0, and planes (a floor, a wall; a slope
//! stops a move across as a wall does, and is ground to land on where its
//! normal points up by at least [`CharacterConfig::min_ground_normal`]; it
//! is not walked up). Particles and other characters pass
//! through it; sensors see it through
//! [`World::sensors_touching`](crate::World::sensors_touching).
//!
//! A character is part of the world's state: a snapshot, a rollback and
//! the state hash cover it, and the same inputs move it the same on every
//! machine (f32 arithmetic in a fixed order).

mod moves;

use core::fmt;

use glam::Vec2;

use crate::colliders::ColliderId;

/// The most characters a world holds (a platformer has one to a few; the
/// sweep of each meets every collider).
pub const MAX_CHARACTERS: usize = 256;

/// How a character is shaped and how it moves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CharacterConfig {
    /// Half its width and height, metres (default 0.3 x 0.45: a body 0.6 m
    /// by 0.9 m).
    pub half_extents: Vec2,
    /// Its fall's acceleration, m/s² (default (0, -30): a platformer's,
    /// about three times Earth's, for snappy jumps).
    pub gravity: Vec2,
    /// The space kept to every surface, metres (default 0.005): what lets
    /// it slide past the edges of flush boxes; below a tenth of its size.
    pub skin: f32,
    /// The highest edge it walks up onto, metres above its feet (default
    /// 0.25; 0: none).
    pub step_height: f32,
    /// How far down it snaps onto ground it walks off, metres (default
    /// 0.25; 0: it falls).
    pub snap_distance: f32,
    /// Steps after leaving the ground that a jump is still taken (default
    /// 6: 0.1 s at 60 Hz).
    pub coyote_ticks: u32,
    /// Steps a jump asked for in the air is kept, to be taken on landing
    /// (default 6).
    pub jump_buffer_ticks: u32,
    /// The least upward component of a surface's normal for it to count as
    /// ground (default 0.7, slopes up to about 45 degrees).
    pub min_ground_normal: f32,
}

impl Default for CharacterConfig {
    fn default() -> Self {
        Self {
            half_extents: Vec2::new(0.3, 0.45),
            gravity: Vec2::new(0.0, -30.0),
            skin: 0.005,
            step_height: 0.25,
            snap_distance: 0.25,
            coyote_ticks: 6,
            jump_buffer_ticks: 6,
            min_ground_normal: 0.7,
        }
    }
}

/// What a character stands on after a step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ground {
    /// The collider.
    pub collider: ColliderId,
    /// Its surface's normal, up from the ground.
    pub normal: Vec2,
    /// The ground's velocity (a moving platform's), which carries it.
    pub velocity: Vec2,
}

/// A surface a character's move was stopped by after a step (a wall, a
/// ceiling).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Touch {
    /// The collider.
    pub collider: ColliderId,
    /// Its surface's normal, towards the character.
    pub normal: Vec2,
}

/// A handle on a character of a world.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct CharacterId(pub(crate) u64);

impl CharacterId {
    /// A handle to no character, for a game's fields before set-up (every
    /// lookup with it is an error naming it): also
    /// [`CharacterId::default`], as for sensors and colliders.
    pub const PLACEHOLDER: Self = Self(u64::MAX);
}

impl Default for CharacterId {
    fn default() -> Self {
        Self::PLACEHOLDER
    }
}

impl fmt::Display for CharacterId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if *self == Self::PLACEHOLDER {
            return f.write_str("CharacterId::PLACEHOLDER (a handle set before any character was added)");
        }
        write!(f, "character #{}", self.0)
    }
}

/// A character: where it is, how it moves, and what it touched in the
/// last step ([the module](self) says how a step moves it).
#[derive(Clone, Debug, PartialEq)]
pub struct Character {
    /// Its centre, metres (z = 0). Set it to teleport (a respawn).
    pub position: Vec2,
    /// Its velocity, m/s: a game sets `x` from its input each step
    /// ([`run`](Self::run)); a step adds gravity to it and zeroes what a
    /// surface stops.
    pub velocity: Vec2,
    /// Its shape and movement.
    pub config: CharacterConfig,
    /// Where the last step started it (what a frame draws from).
    previous: Vec2,
    ground: Option<Ground>,
    wall: Option<Touch>,
    ceiling: Option<Touch>,
    /// Steps of coyote time left.
    coyote: u32,
    /// A buffered jump: its speed and the steps it has left.
    jump: Option<(f32, u32)>,
    /// Whether the last step took a jump.
    jumped: bool,
}

impl Character {
    /// A character centred at `position`, at rest, shaped by `config`.
    #[must_use]
    pub fn new(position: Vec2, config: CharacterConfig) -> Self {
        Self {
            position,
            velocity: Vec2::ZERO,
            config,
            previous: position,
            ground: None,
            wall: None,
            ceiling: None,
            coyote: 0,
            jump: None,
            jumped: false,
        }
    }

    /// Where to draw it `alpha` of the way from the last step's start to
    /// its end (the frame's interpolation factor), as a particle's
    /// [`World::drawn_position`](crate::World::drawn_position) is.
    #[must_use]
    pub fn drawn_position(&self, alpha: f32) -> Vec2 {
        self.previous.lerp(self.position, alpha)
    }

    /// Puts it at `position` at once, drawn there with no sweep from where
    /// it was (a respawn): off any ground and out of coyote time; its
    /// velocity and a buffered jump stay.
    pub fn teleport(&mut self, position: Vec2) {
        self.position = position;
        self.previous = position;
        self.ground = None;
        self.coyote = 0;
    }

    /// Sets its horizontal speed, m/s (negative: left).
    pub fn run(&mut self, speed: f32) {
        self.velocity.x = speed;
    }

    /// Asks for a jump at `speed` m/s up: taken by the next step if it
    /// stands (or may still jump: coyote time), else kept for
    /// [`CharacterConfig::jump_buffer_ticks`] steps and taken on landing.
    pub fn jump(&mut self, speed: f32) {
        self.jump = Some((speed, self.config.jump_buffer_ticks.max(1)));
    }

    /// Cuts a rising jump short (a released button: variable jump
    /// height): its upward speed is capped at `speed`.
    pub fn cut_jump(&mut self, speed: f32) {
        self.velocity.y = self.velocity.y.min(speed.max(0.0));
    }

    /// Stops it dead: no velocity, no buffered jump (a death, a cut scene).
    pub fn stop(&mut self) {
        self.velocity = Vec2::ZERO;
        self.jump = None;
    }

    /// What it stands on after the last step; `None` in the air.
    #[must_use]
    pub fn ground(&self) -> Option<&Ground> {
        self.ground.as_ref()
    }

    /// Whether it stands on ground after the last step.
    #[must_use]
    pub fn grounded(&self) -> bool {
        self.ground.is_some()
    }

    /// The wall its last step's move across was stopped by, if any.
    #[must_use]
    pub fn wall(&self) -> Option<&Touch> {
        self.wall.as_ref()
    }

    /// The ceiling its last step's rise was stopped by, if any.
    #[must_use]
    pub fn ceiling(&self) -> Option<&Touch> {
        self.ceiling.as_ref()
    }

    /// Whether the last step took a jump (to start a sound or an
    /// animation).
    #[must_use]
    pub fn jumped(&self) -> bool {
        self.jumped
    }

    /// Whether a jump asked for now would be taken (it stands, or its
    /// coyote time runs).
    #[must_use]
    pub fn can_jump(&self) -> bool {
        self.ground.is_some() || self.coyote > 0
    }

    /// Its box's corners (bottom-left, top-right).
    #[must_use]
    pub fn bounds(&self) -> (Vec2, Vec2) {
        (
            self.position - self.config.half_extents,
            self.position + self.config.half_extents,
        )
    }

    /// Checks its numbers: finite, sizes above 0, the skin below a tenth of
    /// its smaller half size, steps and snaps at least 0.
    ///
    /// # Errors
    /// [`CharacterError::Invalid`] naming the field, its value and range.
    pub fn validate(&self) -> Result<(), CharacterError> {
        let c = &self.config;
        let invalid =
            |field: &'static str, value: f32, range: &'static str| Err(CharacterError::Invalid { field, value, range });
        for (field, v) in [
            ("position", self.position),
            ("velocity", self.velocity),
            ("gravity", c.gravity),
        ] {
            if let Some(bad) = v.to_array().into_iter().find(|x| !x.is_finite()) {
                return invalid(field, bad, "finite");
            }
        }
        if let Some((speed, _)) = self.jump
            && !speed.is_finite()
        {
            return invalid("jump speed", speed, "finite");
        }
        if let Some(bad) = c
            .half_extents
            .to_array()
            .into_iter()
            .find(|h| !(h.is_finite() && *h > 0.0))
        {
            return invalid("half_extents", bad, "finite, above 0");
        }
        if !(c.skin.is_finite() && c.skin > 0.0 && c.skin <= c.half_extents.min_element() / 10.0) {
            return invalid("skin", c.skin, "above 0, at most a tenth of the smaller half extent");
        }
        for (field, v) in [("step_height", c.step_height), ("snap_distance", c.snap_distance)] {
            if !(v.is_finite() && v >= 0.0) {
                return invalid(field, v, "finite, at least 0");
            }
        }
        if !(c.min_ground_normal.is_finite() && c.min_ground_normal > 0.0 && c.min_ground_normal <= 1.0) {
            return invalid("min_ground_normal", c.min_ground_normal, "above 0, at most 1");
        }
        Ok(())
    }
}

/// What went wrong with a character.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CharacterError {
    /// A number out of its range.
    Invalid {
        /// The field (`half_extents`, `skin`, ...).
        field: &'static str,
        /// Its value.
        value: f32,
        /// What it must be.
        range: &'static str,
    },
    /// The handle names no character of this world (removed, or
    /// another world's).
    Unknown {
        /// The handle.
        id: CharacterId,
    },
    /// The world has [`MAX_CHARACTERS`] already.
    TooMany {
        /// The limit.
        limit: usize,
    },
}

impl fmt::Display for CharacterError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Invalid { field, value, range } => {
                write!(f, "character {field} is {value}: it must be {range}")
            }
            Self::Unknown { id } => write!(f, "{id} is not in this world (removed, or another world's)"),
            Self::TooMany { limit } => write!(
                f,
                "a world holds at most {limit} characters (tickwork::engine::character::MAX_CHARACTERS)"
            ),
        }
    }
}

impl std::error::Error for CharacterError {}

pub(crate) use moves::{Solids, step_character};

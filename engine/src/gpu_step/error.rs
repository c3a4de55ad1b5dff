//! What a GPU world refuses, and why.

use core::fmt;

/// A world the GPU step cannot take, or a GPU it cannot run on.
#[derive(Clone, Debug, PartialEq)]
pub enum GpuStepError {
    /// The world's method has no GPU form (yet, or ever: implicit and
    /// adaptive methods stay on the CPU).
    Method {
        /// The method's name.
        method: String,
        /// Why.
        reason: &'static str,
    },
    /// A force the GPU step does not evaluate.
    Force {
        /// The force's name.
        force: &'static str,
    },
    /// A collider the GPU step does not resolve.
    Collider {
        /// The collider's name.
        collider: &'static str,
        /// What of it.
        reason: &'static str,
    },
    /// Something else of the world the GPU step does not do.
    Unsupported(&'static str),
    /// The adapter cannot run compute shaders (WebGL2).
    NoCompute,
    /// No adapter was found for a world whose backend is the GPU.
    NoAdapter(String),
    /// The particles' buffers are past one of the device's limits.
    Limit {
        /// The limit's name in `wgpu::Limits`.
        limit: &'static str,
        /// Its value, bytes or workgroups.
        value: u64,
        /// What the world needs of it.
        needed: u64,
        /// How many particles fit.
        fits: u64,
    },
    /// A force's pairs are past the world's `max_pairs`, as the CPU's step
    /// refuses them.
    Pairs {
        /// The force's name.
        force: &'static str,
        /// Its pairs.
        pairs: u64,
        /// `WorldConfig::max_pairs`.
        limit: u64,
    },
    /// A step's length that is not finite and positive.
    Step(f32),
    /// A particle whose state became infinite or NaN on the GPU.
    NonFinite {
        /// Its row.
        row: usize,
        /// Its position.
        position: glam::Vec3,
        /// Its velocity.
        velocity: glam::Vec3,
    },
    /// Reading the state back failed.
    ReadBack(String),
    /// What the world's own step refuses ([`GpuWorld::advance`](super::GpuWorld::advance)
    /// runs its lifetimes, emitters and queued commands).
    Simulation(crate::step::SimulationError),
    /// The world's particles were changed between steps other than by
    /// spawns and despawns, which its GPU copy cannot see.
    Edited,
    /// A step's colliders reported more contacts than the room the GPU
    /// step keeps for them (a contact a particle for each reporting
    /// collider, two for one that finds its contacts inside the step, and
    /// 1 024 more): the step is whole, with the contacts that fitted; the
    /// room grows to twice what was found for the next steps.
    Contacts {
        /// The contacts the step found.
        found: u32,
        /// The room for them.
        room: u32,
    },
}

impl fmt::Display for GpuStepError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Method { method, reason } => write!(f, "the GPU step has no method {method:?}: {reason}"),
            Self::Force { force } => write!(
                f,
                "the GPU step does not evaluate the force {force:?}: it takes gravity, wind, linear and quadratic drag, \
                 attractors and n-body"
            ),
            Self::Collider { collider, reason } => write!(f, "the GPU step does not resolve this {collider}: {reason}"),
            Self::Unsupported(what) => write!(f, "the GPU step does not do {what}"),
            Self::NoCompute => f.write_str("the GPU step needs compute shaders, which this adapter (WebGL2) lacks"),
            Self::NoAdapter(why) => write!(f, "the GPU backend needs a graphics adapter: {why}"),
            Self::Limit {
                limit,
                value,
                needed,
                fits,
            } => write!(
                f,
                "the particles need {needed} of the device's {limit} ({value}): at most {fits} particles fit"
            ),
            Self::Pairs { force, pairs, limit } => write!(
                f,
                "the force {force:?} would take {pairs} pairs a step, past WorldConfig::max_pairs ({limit}): raise \
                 it to allow more"
            ),
            Self::NonFinite {
                row,
                position,
                velocity,
            } => write!(
                f,
                "the GPU's state of row {row} is not finite: position {position}, velocity {velocity}"
            ),
            Self::Step(dt) => write!(f, "a GPU step of {dt} s: the step must be finite and positive"),
            Self::ReadBack(message) => write!(f, "reading the GPU world back: {message}"),
            Self::Simulation(error) => error.fmt(f),
            Self::Contacts { found, room } => write!(
                f,
                "a step of a GPU world found {found} contacts of colliders that report them, past its room for \
                 {room}: the step is whole, but World::contacts holds only {room} of them; the next steps have \
                 room for {}",
                2 * u64::from(*found)
            ),
            Self::Edited => f.write_str(
                "the particles of a GPU world were changed outside its steps (particles_mut, set_velocity, \
                 teleport, set_visible, a restored snapshot): their state lives on the GPU, which does not see \
                 such a change; spawn and despawn instead, or store the state into the world and make a new \
                 GpuWorld from it",
            ),
        }
    }
}

impl std::error::Error for GpuStepError {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn too_many_contacts_names_what_was_found_the_room_and_what_follows() {
        let message = GpuStepError::Contacts {
            found: 2049,
            room: 2048,
        }
        .to_string();
        assert_eq!(
            message,
            "a step of a GPU world found 2049 contacts of colliders that report them, past its room for 2048: the \
             step is whole, but World::contacts holds only 2048 of them; the next steps have room for 4098"
        );
    }
}

//! The scene's force generators (gravity, drags, wind, attractors, n-body
//! gravity, springs) and a spring's ends.

use serde::{Deserialize, Serialize};

use super::numbers::{Finite, NonNegative, zero};
use super::particle_index::ParticleIndex;
use super::vectors::Vector;

/// A force generator. A misspelt field in any variant is an error.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum ForceSpec {
    /// Uniform gravity, m/s^2.
    Gravity(Vector),
    /// `a = -rate v`.
    LinearDrag {
        /// 1/s.
        rate: NonNegative,
    },
    /// `a = -coefficient |v| v`.
    QuadraticDrag {
        /// 1/m.
        coefficient: NonNegative,
    },
    /// `a = rate (velocity - v)`.
    Wind {
        /// Air velocity, m/s.
        velocity: Vector,
        /// 1/s.
        rate: NonNegative,
    },
    /// A fixed point mass.
    Attractor {
        /// Where.
        position: Vector,
        /// `G M`, m^3/s^2.
        gm: Finite,
        /// Softening length, m (default: 0).
        #[serde(default = "zero")]
        softening: NonNegative,
    },
    /// Mutual gravity of all particles.
    NBody {
        /// Gravitational constant.
        g: Finite,
        /// Softening length, m (default: 0).
        #[serde(default = "zero")]
        softening: NonNegative,
    },
    /// A damped spring.
    Spring {
        /// First end.
        a: EndSpec,
        /// Second end.
        b: EndSpec,
        /// N/m.
        stiffness: NonNegative,
        /// m.
        rest_length: NonNegative,
        /// N s/m (default: 0).
        #[serde(default = "zero")]
        damping: NonNegative,
    },
}

/// One end of a spring.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum EndSpec {
    /// The particle at this index of `particles`.
    Particle(ParticleIndex),
    /// A fixed point.
    Anchor(Vector),
}

//! What a force is in the GPU step: its form ([`GpuForce`]), and, for a
//! term of the particle's own state, the WGSL the force writes itself
//! ([`Force::write_wgsl`](super::Force::write_wgsl)), so that a new force
//! with a GPU form is one file to change.

use core::fmt;

/// What a force is in the GPU step ([`Force::gpu_form`](super::Force::gpu_form)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GpuForce {
    /// No GPU form: the GPU step refuses a world with it, naming the force
    /// (the default).
    None,
    /// Affine in the velocity ([`Force::affine_in_velocity`](super::Force::affine_in_velocity)):
    /// summed with the others into the step's uniform `c - b v`.
    Affine,
    /// A term of the particle's own position and velocity, which
    /// [`Force::write_wgsl`](super::Force::write_wgsl) writes into the
    /// shader's `acceleration`, after the affine sum, in force order.
    Term,
    /// All-pairs gravity: `G` and the softening length, summed in the
    /// step's n-body rounds (at most one such force a world).
    NBody {
        /// The gravitational constant, m^3/(kg s^2).
        g: f32,
        /// The softening length, m.
        softening: f32,
    },
}

/// An `f32` as WGSL reads back its exact bits (`bitcast<f32>(0x...u)`), so
/// that a value written into a shader is the CPU's, not a decimal's
/// rounding of it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WgslF32(pub f32);

impl fmt::Display for WgslF32 {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "bitcast<f32>({:#010x}u)", self.0.to_bits())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_literal_keeps_the_bits() {
        assert_eq!(WgslF32(1.0).to_string(), "bitcast<f32>(0x3f800000u)");
        assert_eq!(WgslF32(-0.0).to_string(), "bitcast<f32>(0x80000000u)");
    }
}

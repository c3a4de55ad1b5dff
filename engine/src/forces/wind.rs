//! Wind: drag relative to moving air, `a = k (w - v)`.

use glam::{Vec3, Vec3A};

use super::Force;

/// Particles are dragged towards the wind's velocity `w` at rate `k`: in a
/// steady wind they end up moving with it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wind {
    /// The air's velocity, m/s.
    pub velocity: Vec3,
    /// The coupling rate `k`, 1/s.
    pub rate: f32,
}

impl Force for Wind {
    fn name(&self) -> &'static str {
        "wind"
    }

    /// The `-k v` part is linear drag.
    fn linear_drag(&self) -> f32 {
        self.rate
    }

    fn affine_in_velocity(&self) -> Option<(Vec3A, f32)> {
        Some((Vec3A::from(self.velocity) * self.rate, self.rate))
    }

    fn accumulate(&self, _t: f32, _first: usize, _x: &[Vec3A], v: &[Vec3A], _w: &[f32], out: &mut [Vec3A]) {
        let w = Vec3A::from(self.velocity);
        for (a, v) in out.iter_mut().zip(v) {
            *a += (w - *v) * self.rate;
        }
    }
}

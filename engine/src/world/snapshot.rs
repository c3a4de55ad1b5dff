//! Whole-world copies and the state hash: a [`Snapshot`] to go back to (a
//! frozen world, a rollback), and a 64-bit FNV-1a hash that covers the
//! whole simulated state, for comparing runs bit for bit.

use super::World;

/// A copy of a whole world (entities, columns, forces, integrator history,
/// random generator), taken by [`World::snapshot`] and put back by
/// [`World::restore`].
#[derive(Clone, Debug)]
pub struct Snapshot {
    world: World,
}

impl Snapshot {
    /// The tick the snapshot was taken at.
    #[must_use]
    pub fn tick(&self) -> u64 {
        self.world.tick
    }
}

impl World {
    /// A copy of the whole state.
    #[must_use]
    pub fn snapshot(&self) -> Snapshot {
        Snapshot { world: self.clone() }
    }

    /// Overwrites `snapshot` with the current state, reusing its buffers.
    pub fn snapshot_into(&self, snapshot: &mut Snapshot) {
        snapshot.world.clone_from(self);
    }

    /// Puts back a snapshot's state (buffers reused). Forces, colliders and
    /// emitters come back as they were too.
    pub fn restore(&mut self, snapshot: &Snapshot) {
        self.clone_from(&snapshot.world);
    }

    /// A 64-bit FNV-1a hash of the simulated state (tick, entities, every
    /// particle and rigid-body column, the random generator), for comparing
    /// runs bit for bit.
    #[must_use]
    pub fn state_hash(&self) -> u64 {
        let mut h = Fnv::default();
        h.u64(self.tick);
        for e in self.entities.rows() {
            h.u64(e.to_bits());
        }
        let p = &self.particles;
        for column in [&p.position, &p.velocity, &p.previous_position] {
            for x in column.iter() {
                h.f32s(&x.to_array());
            }
        }
        for column in [&p.inverse_mass, &p.radius, &p.lifetime] {
            h.f32s(column);
        }
        h.u64(p.lifetimes.lived.to_bits());
        for born in &p.born {
            h.u64(born.to_bits());
        }
        for (q, w) in self.rigid.orientation.iter().zip(&self.rigid.angular_velocity) {
            h.f32s(&q.to_array());
            h.f32s(&w.to_array());
        }
        for c in &self.contacts {
            h.u64(c.entity.to_bits());
            h.u64(match c.touched {
                crate::colliders::Touched::Collider(id) => id.0,
                crate::colliders::Touched::Entity(e) => e.to_bits() | 1 << 63,
            });
            h.f32s(&c.point.to_array());
            h.f32s(&c.normal.to_array());
            h.f32s(&[c.impulse]);
        }
        h.u64(rand::Rng::next_u64(&mut self.rng.clone()));
        h.0
    }
}

/// FNV-1a, 64 bits: simple, fast enough, and stable across platforms and runs.
struct Fnv(u64);

impl Default for Fnv {
    fn default() -> Self {
        Self(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv {
    fn bytes(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    fn u64(&mut self, v: u64) {
        self.bytes(&v.to_le_bytes());
    }
    fn f32s(&mut self, values: &[f32]) {
        for v in values {
            self.bytes(&v.to_bits().to_le_bytes());
        }
    }
}

//! The state hash: one 64-bit checksum of a world's simulated state, to
//! compare runs bit for bit (replays, thread counts, rollback sync tests).
//!
//! What it covers: the tick and time; the entities; every particle column
//! (positions, velocities, previous positions, masses, radii, lifetimes,
//! birth times, colours, teleport marks) and the lived time; rigid bodies;
//! the last step's contacts; every force, collider and sensor as its
//! `Debug` form (their parameters and state: a kinematic paddle's place, a
//! game's thrust; Rust prints each float as the shortest text that reads
//! back to the same bits, so the text is as exact as the bits) and the
//! sensors' last overlaps; the characters (as their `Debug` form, with
//! what they carry between steps); 2D headings and visibility; the emitters
//! (their owed fraction too); the random generator; the integrator's name
//! and everything it remembers between steps (history, cached
//! accelerations: `Integrator::visit_state`). Not covered: the angular
//! integrator's scratch (the angular methods keep no history).
//!
//! How: xxh3 (64 bits), fed whole runs of words: the vector columns are
//! staged block by block through a stack buffer (the last block's padding
//! lanes left out: the fused step writes them, the plain step does not), so
//! the hasher sees long runs rather than one value at a time. Values are
//! hashed as their little-endian bytes, so the hash is the same on every
//! platform.

use core::fmt;

use xxhash_rust::xxh3::Xxh3;

use super::{Vec3Column, World};

/// Blocks of four particles staged per hasher call (12 KiB of the stack).
const STAGE: usize = 256;

/// A streaming hasher of little-endian words.
struct StateHasher(Xxh3);

impl StateHasher {
    fn bytes(&mut self, bytes: &[u8]) {
        self.0.update(bytes);
    }

    fn u64(&mut self, value: u64) {
        self.bytes(&value.to_le_bytes());
    }

    /// Primitive words (`f32`, `f64`, `u64`) as their little-endian bytes:
    /// as they lie in memory on little-endian machines, each reversed on
    /// big-endian ones.
    fn words<T: bytemuck::Pod>(&mut self, values: &[T]) {
        if cfg!(target_endian = "little") {
            self.bytes(bytemuck::cast_slice(values));
        } else {
            for value in values {
                let native = bytemuck::bytes_of(value);
                let mut little = [0u8; 8];
                for (to, from) in little.iter_mut().zip(native.iter().rev()) {
                    *to = *from;
                }
                self.bytes(&little[..native.len()]);
            }
        }
    }

    fn f32s(&mut self, values: &[f32]) {
        self.words(values);
    }

    fn f64s(&mut self, values: &[f64]) {
        self.words(values);
    }

    fn u64s(&mut self, values: &[u64]) {
        self.words(values);
    }

    /// The rows of a vector column: whole blocks staged (x, y, z lanes),
    /// then the last block's live rows one by one.
    fn column(&mut self, column: &Vec3Column) {
        let len = column.len();
        let whole = len / 4;
        let mut stage = [0.0f32; 12 * STAGE];
        for blocks in column.blocks()[..whole].chunks(STAGE) {
            for (k, block) in blocks.iter().enumerate() {
                stage[12 * k..12 * k + 4].copy_from_slice(&block.x.to_array());
                stage[12 * k + 4..12 * k + 8].copy_from_slice(&block.y.to_array());
                stage[12 * k + 8..12 * k + 12].copy_from_slice(&block.z.to_array());
            }
            self.f32s(&stage[..12 * blocks.len()]);
        }
        for row in 4 * whole..len {
            self.f32s(&column.row(row).to_array());
        }
    }

    /// A method's per-particle vectors, `x, y, z` each, staged.
    fn vectors(&mut self, values: &[glam::Vec3A]) {
        let mut stage = [0.0f32; 12 * STAGE];
        for chunk in values.chunks(4 * STAGE) {
            for (k, v) in chunk.iter().enumerate() {
                stage[3 * k..3 * k + 3].copy_from_slice(&v.to_array());
            }
            self.f32s(&stage[..3 * chunk.len()]);
        }
    }

    /// A value's `Debug` text, streamed without a buffer.
    fn debug(&mut self, value: &dyn fmt::Debug) {
        use fmt::Write as _;
        // Writing into the hasher cannot fail; a formatter error would be a
        // bug in a `Debug` impl, and then the text so far is hashed.
        let _ = write!(self, "{value:?}");
        self.bytes(&[0xff]); // a separator no text contains
    }
}

impl fmt::Write for StateHasher {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        self.bytes(s.as_bytes());
        Ok(())
    }
}

impl World {
    /// A 64-bit checksum of the simulated state, for comparing runs bit for
    /// bit: see what it covers in `world/checksum.rs` (the module docs).
    /// About 6 ns per particle on CI's kind of machine (0.6 ms at 100k,
    /// where the byte-wise FNV it replaced took 6.2 ms: `engine_checksum`
    /// in the step benchmark); allocates nothing.
    #[must_use]
    pub fn state_hash(&self) -> u64 {
        let mut h = StateHasher(Xxh3::new());
        h.u64(self.tick);
        h.f64s(&[self.time]);
        let rows = self.entities.rows();
        h.u64(rows.len() as u64);
        let mut stage = [0u64; 4 * STAGE];
        for entities in rows.chunks(stage.len()) {
            for (word, e) in stage.iter_mut().zip(entities) {
                *word = e.to_bits();
            }
            h.u64s(&stage[..entities.len()]);
        }
        let p = &self.particles;
        for column in [&p.position, &p.velocity, &p.previous_position] {
            h.column(column);
        }
        for column in [&p.inverse_mass, &p.radius, &p.lifetime] {
            h.f32s(column);
        }
        h.f64s(&p.born);
        h.f64s(&[p.lifetimes.lived]);
        h.u64s(&p.teleported_at);
        h.bytes(bytemuck::cast_slice(&p.colour));
        // Each list with its length first, so that items cannot shift from
        // one list into the next unseen.
        let rigid = &self.rigid;
        h.u64(rigid.len() as u64);
        for body in 0..rigid.len() {
            h.u64(u64::from(rigid.owner[body]));
            for q in [rigid.orientation[body], rigid.previous_orientation[body]] {
                h.f32s(&q.to_array());
            }
            for v in [
                rigid.angular_velocity[body],
                rigid.inertia[body],
                rigid.half_extents[body],
            ] {
                h.f32s(&v.to_array());
            }
        }
        h.u64(self.contacts.len() as u64);
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
        h.u64(self.forces.len() as u64);
        for force in &self.forces {
            h.debug(force);
        }
        h.u64(self.colliders().count() as u64);
        for (id, collider) in self.colliders() {
            h.u64(id.0);
            h.debug(&collider);
        }
        h.u64(self.emitters.len() as u64);
        for emitter in &self.emitters {
            h.debug(emitter);
        }
        // Only where there are headings or hidden particles, likewise.
        if let Some((headings, hidden)) = self.heading_state() {
            h.u64(headings.len() as u64);
            for heading in headings {
                h.debug(heading);
            }
            h.u64(hidden.len() as u64);
            for row in hidden {
                h.u64(u64::from(row.0));
            }
        }
        // Only where there are sensors (or their last overlaps), so worlds
        // without them keep the hashes they had.
        if !(self.sensors.list.is_empty() && self.sensors.overlaps.is_empty()) {
            h.u64(self.sensors.list.len() as u64);
            for (id, sensor) in &self.sensors.list {
                h.u64(id.0);
                h.debug(sensor);
            }
            h.u64(self.sensors.overlaps.len() as u64);
            for o in &self.sensors.overlaps {
                h.debug(o);
            }
        }
        // Characters likewise, each as its `Debug` form (place, velocity,
        // ground, coyote time, buffered jump: all it carries between steps).
        if !self.characters.list.is_empty() {
            h.u64(self.characters.list.len() as u64);
            for (id, character) in &self.characters.list {
                h.u64(id.0);
                h.debug(character);
            }
        }
        h.bytes(self.integrator.info().name.as_bytes());
        // What the method remembers (two passes: the closures cannot both
        // borrow the hasher; each pass keeps the method's own order).
        self.integrator
            .visit_state(&mut |vectors| h.vectors(vectors), &mut |_| {});
        self.integrator.visit_state(&mut |_| {}, &mut |bytes| h.bytes(bytes));
        h.u64(rand::Rng::next_u64(&mut self.rng.clone()));
        h.0.digest()
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use crate::{BoxCollider, Emitter, Gravity, Material, Particle, World};

    fn world() -> World {
        let mut w = World::default();
        w.add_force(Gravity::EARTH);
        for k in 0..7 {
            w.spawn(Particle {
                position: Vec3::new(k as f32, 1.0, 0.0),
                ..Particle::default()
            })
            .expect("valid");
        }
        w
    }

    #[test]
    fn the_hash_sees_what_the_positions_do_not_yet_show() {
        let base = world().state_hash();
        assert_eq!(world().state_hash(), base, "the same state, the same hash");
        // A game's force setting, a kinematic collider's place, an emitter's
        // owed fraction, a colour, the world's time: none has moved a
        // particle yet, each changes the hash.
        let mut gravity = world();
        gravity.force_mut::<Gravity>().expect("added").acceleration.y = -9.8;
        let mut paddle = world();
        paddle.add_collider(BoxCollider::solid(Vec3::ZERO, Vec3::ONE, Material::default()));
        let mut owed = world();
        owed.add_emitter(Emitter::default()).expect("valid");
        let before = owed.state_hash();
        owed.emitters_mut()[0].owed = 0.5;
        assert_ne!(owed.state_hash(), before, "the owed fraction");
        let mut colour = world();
        colour.particles_mut().colour[3] = [1, 2, 3, 4];
        let mut time = world();
        time.time = 1e-9;
        for (what, changed) in [
            ("gravity", gravity),
            ("a collider", paddle),
            ("a colour", colour),
            ("time", time),
        ] {
            assert_ne!(changed.state_hash(), base, "{what}");
        }
    }

    #[test]
    fn a_history_method_s_memory_is_in_the_hash() {
        // Two worlds at the same state, one of which has just stepped with
        // position Verlet (it remembers the previous positions) and been put
        // back to the other's columns: the positions agree, the history not.
        let config = crate::WorldConfig {
            integrator: "position_verlet".into(),
            ..crate::WorldConfig::default()
        };
        let fresh = || {
            let mut w = World::new(config.clone()).expect("registered");
            w.add_force(Gravity::EARTH);
            w.spawn(Particle::default()).expect("valid");
            w
        };
        let (mut stepped, mut other) = (fresh(), fresh());
        let step = |w: &mut World, tick| {
            w.step(crate::FixedStep {
                tick,
                time: tick as f64 / 60.0,
                dt: 1.0 / 60.0,
            })
            .expect("a finite step")
        };
        for tick in 0..3 {
            step(&mut stepped, tick);
            step(&mut other, tick);
        }
        assert_eq!(stepped.state_hash(), other.state_hash());
        stepped.integrator = tickwork_integrators::build("position_verlet").expect("registered");
        assert_eq!(stepped.particles().position.get(0), other.particles().position.get(0));
        assert_ne!(
            stepped.state_hash(),
            other.state_hash(),
            "a fresh method has no history"
        );
    }

    #[test]
    fn padding_lanes_are_not_hashed() {
        // Seven particles: the second block has one padding lane.
        let mut a = world();
        let b = world();
        let blocks = a.particles.position.blocks_mut();
        let mut last = blocks[1];
        last.x = glam::Vec4::new(last.x.x, last.x.y, last.x.z, 123.0);
        blocks[1] = last;
        assert_eq!(a.state_hash(), b.state_hash());
        a.particles.position.blocks_mut()[1].x.x = 99.0;
        assert_ne!(a.state_hash(), b.state_hash(), "a live lane is");
    }
}

/// A [`Hasher`](core::hash::Hasher) whose result is the same on every
/// machine and in every run, for [`Game::state_hash`](crate::app::Game::state_hash)
/// over a game's own fields (`(self.score, &self.bricks).hash(&mut hasher)`):
/// xxh3 with every integer written as little-endian bytes and `usize` and
/// `isize` (lengths, enum tags) as 64 bits. std's `DefaultHasher` may change
/// between Rust releases, so two peers built apart could see a desync that
/// is not there.
#[derive(Clone, Default)]
pub struct StableHasher(Xxh3);

impl core::fmt::Debug for StableHasher {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("StableHasher").finish_non_exhaustive()
    }
}

impl StableHasher {
    /// A hasher with nothing written yet.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }
}

impl core::hash::Hasher for StableHasher {
    fn finish(&self) -> u64 {
        self.0.digest()
    }

    fn write(&mut self, bytes: &[u8]) {
        self.0.update(bytes);
    }

    fn write_u16(&mut self, value: u16) {
        self.write(&value.to_le_bytes());
    }

    fn write_u32(&mut self, value: u32) {
        self.write(&value.to_le_bytes());
    }

    fn write_u64(&mut self, value: u64) {
        self.write(&value.to_le_bytes());
    }

    fn write_u128(&mut self, value: u128) {
        self.write(&value.to_le_bytes());
    }

    fn write_usize(&mut self, value: usize) {
        self.write_u64(value as u64);
    }

    fn write_i16(&mut self, value: i16) {
        self.write(&value.to_le_bytes());
    }

    fn write_i32(&mut self, value: i32) {
        self.write(&value.to_le_bytes());
    }

    fn write_i64(&mut self, value: i64) {
        self.write(&value.to_le_bytes());
    }

    fn write_i128(&mut self, value: i128) {
        self.write(&value.to_le_bytes());
    }

    fn write_isize(&mut self, value: isize) {
        self.write_i64(value as i64);
    }
}

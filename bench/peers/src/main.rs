//! The fixed step of a falling-particle world through each library's public
//! API, interleaved in one run so that noise hits all alike:
//!
//! ```text
//! prev = p;  v += dt (g - b v);  p += dt v;   floor at y = 0, restitution 0.8, no friction
//! ```
//!
//! with f32, dt = 1/60, g = (0, -9.81, 0), b = 0.1. The variants:
//! - `memcpy 48 B`: copying 48 bytes per particle (the memory floor of a step
//!   that reads and writes two `Vec3A` columns);
//! - `hand`: a hand-written loop over `Vec3A` columns, reflecting at the floor
//!   (`if y < 0 { y = -y; vy = -e vy }`), as the peers;
//! - `hand (projects)`: the same loop with Tickwork's contact (the particle is
//!   put on the floor, `vy += -(1 + e) min(vy, 0)`), whose state Tickwork must
//!   reproduce bit for bit;
//! - `per-axis blocks`: what Tickwork's planned per-axis layout reaches:
//!   the integrator crate's semi-implicit Euler stepping `Vec3x4` blocks
//!   (four particles per value) in chunks, with the projecting contact as
//!   one masked operation per block; its state must equal the projecting
//!   hand loop's bit for bit;
//! - `per-axis blocks, one loop`: the same arithmetic with integration,
//!   contact and the finiteness sum in one loop per block, to show whether
//!   fusing the passes pays (it did not: slower than the passes, measured);
//! - `per-axis blocks, tight loop`: the step as tightly as this physics
//!   allows on the layout (one indexed loop, gravity's zero x and z left out
//!   of the arithmetic, two finiteness sums), bit for bit the projecting
//!   hand loop's state: the floor of the layout on four SSE2 lanes, which
//!   the "per-axis kernel" column reports (the fastest `per-axis` variant);
//! - `hecs`, `bevy_ecs Query`, `bevy_ecs par_iter` (two threads): components
//!   `Position`, `Velocity`, `Previous` of `Vec3A`, the reflecting loop;
//! - `tickwork in-step`: a `World` with `Gravity`, `LinearDrag`, a floor
//!   `Plane` with its default rule, contacts found inside the step
//!   (`ContactRule::InStep`: a contact model of its own, the bounce at its
//!   instant, whose states agree among themselves), semi-implicit Euler,
//!   `World::step`, on one rayon thread and on two;
//! - `tickwork`: the same with the floor's contacts at the end of the step
//!   (`ContactRule::EndOfStep`, the peers' own rule), bit for bit the
//!   projecting hand loop.
//!
//! Each case (N particles: `fresh`, falling from 100 m, nothing touches;
//! `bouncing`, from 0-10 m, a few particles in a hundred meet the floor
//! each step; `resting`, the fresh crowd on the floor after 3 000 steps)
//! runs every variant for a batch
//! of steps per round, round after round, in one process; the table gives the
//! median nanoseconds per particle-step and the ratios Tickwork's goals are
//! stated in. Every library (the hand loop, hecs, bevy_ecs, Tickwork; not
//! the reference variants: the copy, the projecting loop, the kernels) is
//! built in three allocation layouts (its
//! buffers at different offsets from each other, as in different processes:
//! 4K aliasing between columns moved bevy_ecs's 1k figure between 1.8 and
//! 4.2 ns); the table takes each peer's fastest layout and Tickwork's
//! slowest, so a ratio is the least favourable to Tickwork. The table's
//! Tickwork columns are the default rule's, the end-of-step rule's beside
//! them.
//!
//! Run: `cargo run --release --manifest-path bench/peers/Cargo.toml` (add
//! `-- --quick` for fewer rounds, `-- --sizes 1000,100000`; `-- --only PREFIX
//! --case bouncing --rounds 2000` runs one variant on one case long enough for
//! a profiler).

// `y - y` puts a particle on the floor: +0 for a finite y, NaN for a
// non-finite one, which the finiteness sum then sees (as the engine does).
#![allow(clippy::eq_op)]

use std::hint::black_box;
use std::time::Instant;

use bevy_ecs::prelude::{Component, World as BevyWorld};
use bevy_ecs::query::QueryState;
use glam::Vec4;
use glam::{Vec3, Vec3A};
use tickwork_engine::{ContactRule, FixedStep, Gravity, LinearDrag, Material, Particle, Plane, World, WorldConfig};
use tickwork_integrators::{Integrator, SemiImplicitEuler, System, Vec3x4};

const DT: f32 = (1.0f64 / 60.0) as f32;
const G: Vec3A = Vec3A::new(0.0, -9.81, 0.0);
const DRAG: f32 = 0.1;
const RESTITUTION: f32 = 0.8;
/// The cases, in the order they run: `fresh` (falling from 100 m, nothing
/// touches the floor), `bouncing` (from 0-10 m, a few particles in a
/// hundred meet the floor each step) and `resting` (the fresh crowd after
/// [`SETTLE_STEPS`], on the floor).
const CASES: [&str; 3] = ["fresh", "bouncing", "resting"];

/// Steps run (untimed) before the resting case: 50 s, by which the bounces
/// from 110 m under e = 0.8 have died out.
const SETTLE_STEPS: usize = 3_000;
/// Steps per timed batch: 4 s of game time, so a fresh batch is still
/// falling, and a resting one never reaches subnormal speeds.
const STEPS: usize = 240;

/// Allocation layouts each library is built in: its buffers land at
/// different offsets from each other, as in different processes. Where two
/// columns sit at the same offset within a 4 KiB page, stores to one and
/// loads from the other alias, and a loop runs up to twice as slowly (the
/// trap of `shared/notes/design.md`): bevy_ecs's `Query` at 1k took 1.8 ns
/// or 4.2 ns a particle-step depending on what the process had allocated
/// before it. The table takes each peer's fastest layout and Tickwork's
/// slowest.
const LAYOUTS: usize = 3;

/// A spacer to allocate before spawn `k` in layout `layout` (none in layout
/// 0): columns grow by doubling while particles are spawned, so a spacer at
/// each power of two moves where the next buffers land.
fn spacer(layout: usize, k: usize) -> Option<Vec<u8>> {
    (layout > 0 && k.is_power_of_two())
        .then(|| vec![1u8; 4096 * layout + 64 * layout * (k.trailing_zeros() as usize % 7)])
}

/// Spawns every particle of `start` through `spawn`, allocating layout
/// `layout`'s spacers between the spawns; the handles in order, and the
/// spacers to keep alive.
fn spawn_spaced<E>(
    start: &[(Vec3A, Vec3A)],
    layout: usize,
    mut spawn: impl FnMut(Vec3A, Vec3A) -> E,
) -> (Vec<E>, Vec<Vec<u8>>) {
    let mut spacers = Vec::new();
    let handles = start
        .iter()
        .enumerate()
        .map(|(k, &(p, v))| {
            spacers.extend(spacer(layout, k));
            spawn(p, v)
        })
        .collect();
    (handles, spacers)
}

#[derive(Component, Clone, Copy)]
struct Position(Vec3A);
#[derive(Component, Clone, Copy)]
struct Velocity(Vec3A);
#[derive(Component, Clone, Copy)]
struct Previous(Vec3A);

/// The starting state: particles in a 20 m x 10 m x 20 m box from 100 m up,
/// moving: the fresh case falls for more than 4 s before the first contact.
fn initial(n: usize) -> Vec<(Vec3A, Vec3A)> {
    starts(n, 100.0)
}

/// The bouncing crowd's start: as [`initial`], but 0-10 m up, so that from
/// the first step a few particles in a hundred meet the floor each step
/// (the rule's cost where contacts happen, not where nothing touches).
fn bouncing(n: usize) -> Vec<(Vec3A, Vec3A)> {
    starts(n, 0.0)
}

/// `n` particles in a 20 m x 10 m x 20 m box from `floor` m up, with
/// velocities in +-2 m/s (the same random sequence whatever the height).
fn starts(n: usize, floor: f32) -> Vec<(Vec3A, Vec3A)> {
    let mut seed = 0x9e37_79b9_u32;
    let mut random = move || {
        seed ^= seed << 13;
        seed ^= seed >> 17;
        seed ^= seed << 5;
        (seed >> 8) as f32 / (1u32 << 24) as f32
    };
    (0..n)
        .map(|_| {
            let p = Vec3A::new(random() * 20.0 - 10.0, floor + random() * 10.0, random() * 20.0 - 10.0);
            let v = Vec3A::new(random() * 4.0 - 2.0, random() * 4.0 - 2.0, random() * 4.0 - 2.0);
            (p, v)
        })
        .collect()
}

/// The peers' step for one particle: integrate, then reflect at the floor.
#[inline(always)]
fn reflecting(p: &mut Vec3A, v: &mut Vec3A, prev: &mut Vec3A) {
    *prev = *p;
    let a = G - *v * DRAG;
    *v += a * DT;
    *p += *v * DT;
    if p.y < 0.0 {
        p.y = -p.y;
        v.y *= -RESTITUTION;
    }
}

/// Tickwork's arithmetic, written out: `a = c - b v`, `v += a h`, `x += v h`,
/// and its plane contact for a particle of radius 0 with friction 0.
#[inline(always)]
fn projecting(p: &mut Vec3A, v: &mut Vec3A, prev: &mut Vec3A) {
    *prev = *p;
    let a = G - *v * DRAG;
    *v += a * DT;
    *p += *v * DT;
    if p.y < 0.0 {
        v.y += -(1.0 + RESTITUTION) * v.y.min(0.0);
        p.y -= p.y;
    }
}

/// How far the two contact models may put a particle apart: reflection
/// mirrors a particle that went below the floor (`y = -y`), projection puts
/// it on the floor (`y = 0`); in one bounce they differ by at most the depth
/// it reached in a step, `v dt` at the impact speed `v = sqrt(2 g h)` from
/// the highest start (110 m): 46.5 m/s over 1/60 s, 0.78 m. The states are
/// compared while falling (identical) and once the bounces have died down
/// (3 000 steps on), where what is left is small hops out of step with each
/// other, lower than the first bounce's depth (measured: 0.03-0.04 m).
const CONTACT_MODEL_TOLERANCE: f32 = 0.78;

/// Positions and velocities of every particle, in spawn order.
type State = Vec<(Vec3A, Vec3A)>;

/// One library's world and how it steps.
trait Variant {
    fn name(&self) -> String;
    fn step(&mut self);
    /// `steps` steps (Tickwork enters its thread pool once for all of them,
    /// as a game loop does).
    fn run(&mut self, steps: usize) {
        for _ in 0..steps {
            self.step();
        }
    }
    /// Keeps the current state, to start every timed batch from it.
    fn save(&mut self);
    /// Puts the saved state back (untimed).
    fn restore(&mut self);
    /// Positions and velocities, in spawn order.
    fn state(&mut self) -> State;
    /// Whether its contact is Tickwork's (projection) rather than a reflection.
    fn projects(&self) -> bool {
        false
    }
}

/// A copy of 48 bytes per particle. The destination starts one 64-byte line
/// past its allocation: large buffers are page-aligned plus a header, so two
/// of them otherwise sit at the same offset within a 4 KiB page, where this
/// machine's memmove runs many times slower (the 4K-aliasing trap of
/// `shared/notes/design.md`), and the baseline would not be the bandwidth.
struct Memcpy {
    from: Vec<[f32; 12]>,
    to: Vec<[f32; 16]>,
}

impl Variant for Memcpy {
    fn name(&self) -> String {
        "memcpy 48 B".into()
    }
    fn step(&mut self) {
        let n = self.from.len();
        let from: &[f32] = self.from.as_flattened();
        let to = &mut self.to.as_flattened_mut()[16..16 + 12 * n];
        to.copy_from_slice(from);
        black_box(&mut self.to);
    }
    fn save(&mut self) {}
    fn restore(&mut self) {}
    fn state(&mut self) -> State {
        Vec::new()
    }
}

struct Hand {
    p: Vec<Vec3A>,
    v: Vec<Vec3A>,
    prev: Vec<Vec3A>,
    project: bool,
    layout: usize,
    saved: (Vec<Vec3A>, Vec<Vec3A>),
    /// Allocations kept alive between the columns (the layout).
    _spacers: Vec<Vec<u8>>,
}

impl Hand {
    fn new(p: &[Vec3A], v: &[Vec3A], project: bool, layout: usize) -> Self {
        let p = p.to_vec();
        let first = spacer(layout, 1);
        let v = v.to_vec();
        let second = spacer(layout, 2);
        let prev = p.clone();
        Self {
            p,
            v,
            prev,
            project,
            layout,
            saved: (Vec::new(), Vec::new()),
            _spacers: first.into_iter().chain(second).collect(),
        }
    }
}

impl Variant for Hand {
    fn name(&self) -> String {
        if self.project {
            "hand (projects)".into()
        } else {
            format!("hand (layout {})", self.layout)
        }
    }
    fn step(&mut self) {
        let f = if self.project { projecting } else { reflecting };
        for ((p, v), prev) in self.p.iter_mut().zip(&mut self.v).zip(&mut self.prev) {
            f(p, v, prev);
        }
    }
    fn state(&mut self) -> State {
        self.p.iter().copied().zip(self.v.iter().copied()).collect()
    }
    fn projects(&self) -> bool {
        self.project
    }
    fn save(&mut self) {
        self.saved = (self.p.clone(), self.v.clone());
    }
    fn restore(&mut self) {
        self.p.copy_from_slice(&self.saved.0);
        self.v.copy_from_slice(&self.saved.1);
    }
}

/// The per-axis layout's reach: the integrator crate's semi-implicit Euler
/// stepping four particles per value (`Vec3x4`, one `Vec4` per axis) in
/// chunks of 128 blocks, double-buffered previous positions, then the
/// projecting floor contact as one masked operation per block.
struct Blocks {
    p: Vec<Vec3x4>,
    prev: Vec<Vec3x4>,
    v: Vec<Vec3x4>,
    n: usize,
    method: SemiImplicitEuler<Vec3x4>,
    saved: (Vec<Vec3x4>, Vec<Vec3x4>),
}

/// `a = G - b v` for every block.
struct Falling;

impl System<Vec3x4> for Falling {
    fn acceleration(&mut self, _t: f32, _x: &[Vec3x4], v: &[Vec3x4], out: &mut [Vec3x4]) {
        let c = Vec3x4::splat(G);
        for (a, v) in out.iter_mut().zip(v) {
            *a = c - *v * DRAG;
        }
    }
    fn affine_range(&self, _first: usize, _count: usize) -> Option<(Vec3x4, f32)> {
        Some((Vec3x4::splat(G), DRAG))
    }
    fn is_pointwise(&self) -> bool {
        true
    }
}

impl Blocks {
    fn new(p: &[Vec3A], v: &[Vec3A]) -> Self {
        let pack = |s: &[Vec3A]| {
            s.chunks(4)
                .map(|c| Vec3x4::from_lanes(core::array::from_fn(|k| c.get(k).copied().unwrap_or(Vec3A::ZERO))))
                .collect::<Vec<_>>()
        };
        let p = pack(p);
        Self {
            prev: p.clone(),
            p,
            v: pack(v),
            n: v.len(),
            method: SemiImplicitEuler::new(),
            saved: (Vec::new(), Vec::new()),
        }
    }
}

impl Variant for Blocks {
    fn name(&self) -> String {
        "per-axis blocks (integrator crate)".into()
    }
    fn step(&mut self) {
        core::mem::swap(&mut self.p, &mut self.prev);
        let lift = Vec4::splat(-(1.0 + RESTITUTION));
        let mut bad = Vec4::ZERO;
        for ((x, v), x0) in self
            .p
            .chunks_mut(128)
            .zip(self.v.chunks_mut(128))
            .zip(self.prev.chunks(128))
        {
            self.method.step_from(0.0, DT, x0, x, v, &mut Falling).expect("step");
            for (x, v) in x.iter_mut().zip(v.iter_mut()) {
                let below = x.y.cmplt(Vec4::ZERO);
                v.y = Vec4::select(below, v.y + lift * v.y.min(Vec4::ZERO), v.y);
                x.y = Vec4::select(below, x.y - x.y, x.y);
                bad += (x.x + x.y + x.z + v.x + v.y + v.z) * 0.0;
            }
        }
        black_box(bad);
    }
    fn state(&mut self) -> State {
        let lanes = |s: &[Vec3x4]| s.iter().flat_map(|b| b.lanes()).take(self.n).collect::<Vec<_>>();
        lanes(&self.p).into_iter().zip(lanes(&self.v)).collect()
    }
    fn projects(&self) -> bool {
        true
    }
    fn save(&mut self) {
        self.saved = (self.p.clone(), self.v.clone());
    }
    fn restore(&mut self) {
        self.p.copy_from_slice(&self.saved.0);
        self.v.copy_from_slice(&self.saved.1);
    }
}

/// [`Blocks`] stepped by one hand-written loop over all the blocks instead
/// of the integrator crate's passes: the same start state and checks, only
/// the loop shape differs.
struct LoopBlocks {
    blocks: Blocks,
    name: &'static str,
    /// One step from `prev` into `p` and `v`; returns the finiteness sum.
    step: fn(p: &mut [Vec3x4], prev: &[Vec3x4], v: &mut [Vec3x4]) -> Vec4,
}

impl Variant for LoopBlocks {
    fn name(&self) -> String {
        self.name.into()
    }
    fn step(&mut self) {
        let b = &mut self.blocks;
        core::mem::swap(&mut b.p, &mut b.prev);
        black_box((self.step)(&mut b.p, &b.prev, &mut b.v));
    }
    fn state(&mut self) -> State {
        self.blocks.state()
    }
    fn projects(&self) -> bool {
        true
    }
    fn save(&mut self) {
        self.blocks.save();
    }
    fn restore(&mut self) {
        self.blocks.restore();
    }
}

/// The whole step in one loop per block (integration, contact, finiteness
/// sum), the arithmetic in the same order as [`Blocks`]: what a fused
/// kernel reaches.
fn one_loop_step(p: &mut [Vec3x4], prev: &[Vec3x4], v: &mut [Vec3x4]) -> Vec4 {
    let lift = Vec4::splat(-(1.0 + RESTITUTION));
    let c = Vec3x4::splat(G);
    let mut bad = Vec4::ZERO;
    for ((x, v), x0) in p.iter_mut().zip(v.iter_mut()).zip(prev.iter()) {
        let a = c - *v * DRAG;
        *v += a * DT;
        *x = *x0 + *v * DT;
        let below = x.y.cmplt(Vec4::ZERO);
        v.y = Vec4::select(below, v.y + lift * v.y.min(Vec4::ZERO), v.y);
        x.y = Vec4::select(below, x.y - x.y, x.y);
        bad += ((x.x + v.x) + (x.y + v.y)) + (x.z + v.z);
    }
    bad
}

/// The per-axis layout's step written as tightly as the physics allows:
/// one loop, gravity's zero x and z components left out of the arithmetic
/// (`0 - y` is `-y` exactly, so the bits are the projecting hand loop's),
/// the finiteness sum over two accumulators.
#[inline(never)]
fn tight_step(p: &mut [Vec3x4], prev: &[Vec3x4], v: &mut [Vec3x4]) -> Vec4 {
    let n = p.len().min(prev.len()).min(v.len());
    let (p, prev, v) = (&mut p[..n], &prev[..n], &mut v[..n]);
    let (b, dt, gy) = (Vec4::splat(DRAG), Vec4::splat(DT), Vec4::splat(G.y));
    let lift = Vec4::splat(-(1.0 + RESTITUTION));
    let mut bad = [Vec4::ZERO; 2];
    for i in 0..n {
        let (x0, u) = (prev[i], v[i]);
        let vx = u.x - (u.x * b) * dt;
        let vy = u.y + (gy - u.y * b) * dt;
        let vz = u.z - (u.z * b) * dt;
        let (x, mut y, z) = (x0.x + vx * dt, x0.y + vy * dt, x0.z + vz * dt);
        let below = y.cmplt(Vec4::ZERO);
        let vy = Vec4::select(below, vy + lift * vy.min(Vec4::ZERO), vy);
        y = Vec4::select(below, y - y, y);
        p[i] = Vec3x4 { x, y, z };
        v[i] = Vec3x4 { x: vx, y: vy, z: vz };
        bad[i & 1] += ((x + vx) + (y + vy)) + (z + vz);
    }
    bad[0] + bad[1]
}

struct Hecs {
    world: hecs::World,
    order: Vec<hecs::Entity>,
    layout: usize,
    saved: State,
    _spacers: Vec<Vec<u8>>,
}

impl Hecs {
    fn new(start: &[(Vec3A, Vec3A)], layout: usize) -> Self {
        let mut world = hecs::World::new();
        let (order, spacers) = spawn_spaced(start, layout, |p, v| {
            world.spawn((Position(p), Velocity(v), Previous(p)))
        });
        Self {
            world,
            order,
            layout,
            saved: Vec::new(),
            _spacers: spacers,
        }
    }
}

impl Variant for Hecs {
    fn name(&self) -> String {
        format!("hecs (layout {})", self.layout)
    }
    fn step(&mut self) {
        for (p, v, prev) in self.world.query_mut::<(&mut Position, &mut Velocity, &mut Previous)>() {
            reflecting(&mut p.0, &mut v.0, &mut prev.0);
        }
    }
    fn state(&mut self) -> State {
        self.order
            .iter()
            .map(|&e| {
                let p = self.world.get::<&Position>(e).expect("alive").0;
                let v = self.world.get::<&Velocity>(e).expect("alive").0;
                (p, v)
            })
            .collect()
    }
    fn save(&mut self) {
        self.saved = self.state();
    }
    fn restore(&mut self) {
        for (&e, &(p, v)) in self.order.iter().zip(&self.saved) {
            self.world.get::<&mut Position>(e).expect("alive").0 = p;
            self.world.get::<&mut Velocity>(e).expect("alive").0 = v;
        }
    }
}

struct Bevy {
    world: BevyWorld,
    query: QueryState<(&'static mut Position, &'static mut Velocity, &'static mut Previous)>,
    order: Vec<bevy_ecs::entity::Entity>,
    parallel: bool,
    layout: usize,
    saved: State,
    _spacers: Vec<Vec<u8>>,
}

impl Bevy {
    fn new(start: &[(Vec3A, Vec3A)], parallel: bool, layout: usize) -> Self {
        let mut world = BevyWorld::new();
        let (order, spacers) = spawn_spaced(start, layout, |p, v| {
            world.spawn((Position(p), Velocity(v), Previous(p))).id()
        });
        let query = world.query::<(&mut Position, &mut Velocity, &mut Previous)>();
        Self {
            world,
            query,
            order,
            parallel,
            layout,
            saved: Vec::new(),
            _spacers: spacers,
        }
    }
}

impl Variant for Bevy {
    fn name(&self) -> String {
        if self.parallel {
            format!("bevy_ecs par_iter (2 threads, layout {})", self.layout)
        } else {
            format!("bevy_ecs Query (layout {})", self.layout)
        }
    }
    fn step(&mut self) {
        if self.parallel {
            self.query
                .par_iter_mut(&mut self.world)
                .for_each(|(mut p, mut v, mut prev)| reflecting(&mut p.0, &mut v.0, &mut prev.0));
        } else {
            for (mut p, mut v, mut prev) in self.query.iter_mut(&mut self.world) {
                reflecting(&mut p.0, &mut v.0, &mut prev.0);
            }
        }
    }
    fn state(&mut self) -> State {
        self.order
            .iter()
            .map(|&e| {
                let p = self.world.get::<Position>(e).expect("alive").0;
                let v = self.world.get::<Velocity>(e).expect("alive").0;
                (p, v)
            })
            .collect()
    }
    fn save(&mut self) {
        self.saved = self.state();
    }
    fn restore(&mut self) {
        for (&e, &(p, v)) in self.order.iter().zip(&self.saved) {
            self.world.get_mut::<Position>(e).expect("alive").0 = p;
            self.world.get_mut::<Velocity>(e).expect("alive").0 = v;
        }
    }
}

struct Tickwork {
    world: World,
    saved: Option<tickwork_engine::world::Snapshot>,
    threads: usize,
    layout: usize,
    rule: ContactRule,
    /// Allocations kept alive between the world's columns (the layout).
    _spacers: Vec<Vec<u8>>,
}

impl Tickwork {
    fn new(start: &[(Vec3A, Vec3A)], threads: usize, layout: usize, rule: ContactRule) -> Self {
        let config = WorldConfig {
            integrator: "semi_implicit_euler".into(),
            parallel_threshold: if threads > 1 { 4_096 } else { usize::MAX },
            ..WorldConfig::default()
        };
        let mut world = World::new(config).expect("registered");
        world.add_force(Gravity {
            acceleration: Vec3::from(G),
        });
        world.add_force(LinearDrag { rate: DRAG });
        world.add_collider(Plane {
            contact: rule,
            ..Plane::floor(
                0.0,
                Material {
                    restitution: RESTITUTION,
                    friction: 0.0,
                },
            )
        });
        // Different allocation layouts: columns grow by doubling while the
        // particles are spawned; a spacer allocated between spawns of each
        // doubling moves where the next column buffers land.
        // (Spawned without collecting handles, unlike `spawn_spaced`: the
        // layouts stay those the published figures were measured in.)
        let mut spacers = Vec::new();
        for (k, (p, v)) in start.iter().enumerate() {
            spacers.extend(spacer(layout, k));
            let particle = Particle {
                position: Vec3::from(*p),
                velocity: Vec3::from(*v),
                radius: 0.0,
                ..Particle::default()
            };
            world.spawn(particle).expect("valid");
        }
        Self {
            world,
            saved: None,
            threads,
            layout,
            rule,
            _spacers: spacers,
        }
    }
}

impl Variant for Tickwork {
    fn name(&self) -> String {
        format!(
            "tickwork{} ({} thread{}, layout {})",
            if self.rule == ContactRule::InStep {
                " in-step"
            } else {
                ""
            },
            self.threads,
            if self.threads == 1 { "" } else { "s" },
            self.layout
        )
    }
    fn step(&mut self) {
        self.run(1);
    }
    fn run(&mut self, steps: usize) {
        // Stepped on the caller, as a game's loop would: one thread when
        // the world never splits (threshold usize::MAX), rayon's global pool
        // (the caller its thread 0, as `run` sets up; see `main`) for the
        // lanes when it does.
        let world = &mut self.world;
        for _ in 0..steps {
            let step = FixedStep {
                tick: world.tick(),
                time: world.tick() as f64 / 60.0,
                dt: 1.0 / 60.0,
            };
            world.step(step).expect("step");
        }
    }
    fn save(&mut self) {
        match &mut self.saved {
            Some(snapshot) => self.world.snapshot_into(snapshot),
            None => self.saved = Some(self.world.snapshot()),
        }
    }
    fn restore(&mut self) {
        if let Some(snapshot) = &self.saved {
            self.world.restore(snapshot);
        }
    }
    fn state(&mut self) -> State {
        let p = self.world.particles();
        // Rows stay in spawn order: nothing is despawned.
        p.position.iter().zip(p.velocity.iter()).collect()
    }
    fn projects(&self) -> bool {
        true
    }
}

fn variants(start: &[(Vec3A, Vec3A)]) -> Vec<Box<dyn Variant>> {
    let n = start.len();
    let (p, v): (Vec<Vec3A>, Vec<Vec3A>) = start.iter().copied().unzip();
    let mut all: Vec<Box<dyn Variant>> = vec![
        Box::new(Memcpy {
            from: vec![[1.0; 12]; n],
            // 12 n floats from float 16 on: 3 n / 4 + 1 blocks of 16 floats.
            to: vec![[0.0; 16]; (3 * n).div_ceil(4) + 1],
        }),
        Box::new(Hand::new(&p, &v, true, 0)),
        Box::new(Blocks::new(&p, &v)),
        Box::new(LoopBlocks {
            blocks: Blocks::new(&p, &v),
            name: "per-axis blocks, one loop",
            step: one_loop_step,
        }),
        Box::new(LoopBlocks {
            blocks: Blocks::new(&p, &v),
            name: "per-axis blocks, tight loop",
            step: tight_step,
        }),
    ];
    for layout in 0..LAYOUTS {
        all.push(Box::new(Hand::new(&p, &v, false, layout)));
        all.push(Box::new(Hecs::new(start, layout)));
        all.push(Box::new(Bevy::new(start, false, layout)));
        all.push(Box::new(Bevy::new(start, true, layout)));
        for rule in [ContactRule::EndOfStep, ContactRule::InStep] {
            all.push(Box::new(Tickwork::new(start, 1, layout, rule)));
            all.push(Box::new(Tickwork::new(start, 2, layout, rule)));
        }
    }
    all
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

/// Runs every variant `rounds` times, interleaved, each batch from the saved
/// state; returns the median ns per particle-step of each.
fn measure(variants: &mut [Box<dyn Variant>], n: usize, rounds: usize, steps: usize) -> Vec<f64> {
    let mut samples = vec![Vec::new(); variants.len()];
    for round in 0..rounds {
        // Rotate the order, so no variant always follows the same one.
        for k in 0..variants.len() {
            let i = (k + round) % variants.len();
            variants[i].restore();
            let start = Instant::now();
            variants[i].run(steps);
            let elapsed = start.elapsed().as_nanos() as f64;
            samples[i].push(elapsed / (steps * n) as f64);
        }
    }
    samples.into_iter().map(median).collect()
}

/// The largest difference in position between two states.
fn max_difference(a: &[(Vec3A, Vec3A)], b: &[(Vec3A, Vec3A)]) -> f32 {
    a.iter().zip(b).map(|(a, b)| (a.0 - b.0).length()).fold(0.0, f32::max)
}

/// Checks the states: reflecting variants agree bit for bit, and so do
/// Tickwork and the hand loop that projects; prints the gap between the two
/// contact models, and fails past `tolerance` where one is given (in a
/// bouncing crowd the two models' bounces drift apart in phase: no bound).
fn check(variants: &mut [Box<dyn Variant>], tolerance: Option<f32>) -> Result<(), String> {
    let (in_step, states): (Vec<(String, bool, State)>, Vec<_>) = variants
        .iter_mut()
        .map(|v| (v.name(), v.projects(), v.state()))
        .filter(|s| !s.2.is_empty())
        .partition(|s| s.0.contains("in-step"));
    // The in-step variants, a contact model of their own, agree among
    // themselves (threads, layouts).
    if let Some((first, _, reference)) = in_step.first() {
        for (name, _, state) in &in_step {
            if state != reference {
                return Err(format!(
                    "{name} differs from {first}: largest position difference {:e} m",
                    max_difference(state, reference)
                ));
            }
        }
    }
    let Some(reference) = states.first().map(|s| s.1) else {
        return Ok(());
    };
    let _ = reference;
    if states.iter().any(|s| s.1) != states.iter().any(|s| !s.1) {
        return Ok(());
    }
    let reference = |projects: bool| states.iter().find(|s| s.1 == projects).expect("a reference");
    for (name, projects, state) in &states {
        let (reference_name, _, reference_state) = reference(*projects);
        if state != reference_state {
            return Err(format!(
                "{name} differs from {reference_name}: largest position difference {:e} m",
                max_difference(state, reference_state)
            ));
        }
    }
    let gap = max_difference(&reference(true).2, &reference(false).2);
    if let Some(tolerance) = tolerance
        && gap > tolerance
    {
        return Err(format!(
            "projection and reflection differ by {gap:e} m, more than the {tolerance} m one step's fall at the impact speed explains"
        ));
    }
    let bound = tolerance.map_or("none: the bounces drift apart".to_string(), |t| format!("{t} m"));
    println!(
        "  states: reflecting variants identical; Tickwork identical to the projecting hand loop; projection vs reflection differ by at most {gap:.3e} m (tolerance {bound})"
    );
    Ok(())
}

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().collect();
    let quick = args.iter().any(|a| a == "--quick");
    let sizes: Vec<usize> = match args.iter().position(|a| a == "--sizes") {
        Some(i) => args
            .get(i + 1)
            .ok_or("--sizes takes a list such as 1000,100000")?
            .split(',')
            .map(|s| s.parse().map_err(|_| format!("--sizes: '{s}' is not a count")))
            .collect::<Result<_, _>>()?,
        None => vec![1_000, 100_000, 1_000_000],
    };
    // `--rounds N`: more rounds than the default 21 (5 with `--quick`), for a profiler.
    let rounds = match args.iter().position(|a| a == "--rounds") {
        Some(i) => args
            .get(i + 1)
            .and_then(|s| s.parse().ok())
            .filter(|&r: &usize| r > 0)
            .ok_or("--rounds takes a count of at least 1")?,
        None if quick => 5,
        None => 21,
    };
    // `--only PREFIX`: just the variants whose name starts with it (for a profiler).
    let only = args
        .iter()
        .position(|a| a == "--only")
        .and_then(|i| args.get(i + 1))
        .cloned();
    // `--case fresh`, `bouncing` or `resting`: time just that case (for a profiler).
    let only_case = args
        .iter()
        .position(|a| a == "--case")
        .map(|i| args.get(i + 1).map(String::as_str));
    if let Some(case) = only_case {
        if !case.is_some_and(|case| CASES.contains(&case)) {
            return Err("--case takes fresh, bouncing or resting".into());
        }
    }
    // What a Tickwork game's `run` does: this thread (the one that steps)
    // becomes thread 0 of rayon's global pool, of one thread per core.
    tickwork_engine::threads::join_thread_pool().map_err(|e| format!("rayon's global pool: {e}"))?;
    if rayon::current_num_threads() != 2 {
        return Err(format!(
            "the two-thread variants need a pool of 2, this machine gives {}: run with RAYON_NUM_THREADS=2",
            rayon::current_num_threads()
        ));
    }
    bevy_tasks::ComputeTaskPool::get_or_init(|| bevy_tasks::TaskPoolBuilder::new().num_threads(2).build());
    println!("Tickwork peer benchmark: median ns per particle-step over {rounds} interleaved rounds");
    let mut rows = Vec::new();
    for &n in &sizes {
        let mut variants = Vec::new();
        for case in CASES {
            if only_case.is_some_and(|only| only != Some(case)) {
                continue;
            }
            // Fresh and resting share one set of worlds (resting is fresh
            // settled); the bouncing crowd starts from its own state.
            if case != "resting" || variants.is_empty() {
                variants = self::variants(&if case == "bouncing" { bouncing(n) } else { initial(n) });
                if let Some(prefix) = &only {
                    variants.retain(|v| v.name().starts_with(prefix.as_str()));
                }
            }
            if case == "resting" {
                for v in variants.iter_mut() {
                    v.restore();
                    v.run(SETTLE_STEPS);
                }
            }
            for v in variants.iter_mut() {
                v.save();
            }
            println!("N = {n}, {case}:");
            if case == "resting" {
                for v in variants.iter_mut() {
                    let state = v.state();
                    let airborne = state.iter().filter(|(p, _)| p.y > 1e-3).count();
                    if !state.is_empty() {
                        println!(
                            "  {:<34} {airborne} of {} particles more than 1 mm above the floor",
                            v.name(),
                            state.len()
                        );
                    }
                }
            }
            let times = measure(&mut variants, n, rounds, STEPS);
            for (v, t) in variants.iter().zip(&times) {
                println!("  {:<34} {t:>7.2}", v.name());
            }
            let tolerance = (case != "bouncing").then_some(CONTACT_MODEL_TOLERANCE);
            check(&mut variants, tolerance)?;
            rows.push((n, case, variants.iter().map(|v| v.name()).collect::<Vec<_>>(), times));
        }
    }
    // The table's ratios need every variant and case: not with `--only` or `--case`.
    if only.is_none() && only_case.is_none() {
        print_table(&rows);
    }
    Ok(())
}

type Row<'a> = (usize, &'a str, Vec<String>, Vec<f64>);

/// The README's table: each peer's time (fastest layout), and Tickwork's
/// (slowest layout) under its default contact rule (inside the step) as a
/// ratio to the peers its goals name; then the end-of-step rule (the
/// peers' own: a contact found where the step ends) and the default's
/// ratio to it.
fn print_table(rows: &[Row<'_>]) {
    println!();
    println!(
        "| N | memcpy 48 B | hand | hecs | bevy_ecs Query | bevy_ecs par_iter | per-axis kernel | Tickwork 1 thread | Tickwork 2 threads | 1 thread / bevy Query | 1 thread / hand | 2 threads / bevy Query | 2 threads / bevy par_iter | kernel / bevy Query | end-of-step 1 thread | end-of-step 2 threads | default / end-of-step, 1 thread | default / end-of-step, 2 threads |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for (n, case, names, times) in rows {
        // A peer's fastest layout, Tickwork's slowest.
        let fold = |prefix: &str, start: f64, pick: fn(f64, f64) -> f64| {
            names
                .iter()
                .zip(times)
                .filter(|(name, _)| name.starts_with(prefix))
                .fold(start, |acc, (_, t)| pick(acc, *t))
        };
        let fastest = |prefix: &str| fold(prefix, f64::INFINITY, f64::min);
        let slowest = |prefix: &str| fold(prefix, 0.0, f64::max);
        let (memcpy, hand, hecs) = (fastest("memcpy"), fastest("hand (layout"), fastest("hecs"));
        let (query, par) = (fastest("bevy_ecs Query"), fastest("bevy_ecs par_iter"));
        let (one, two) = (
            slowest("tickwork in-step (1 thread"),
            slowest("tickwork in-step (2 threads"),
        );
        let (end_one, end_two) = (slowest("tickwork (1 thread"), slowest("tickwork (2 threads"));
        // The floor of the layout: its integration and contact kernels
        // alone, without the engine (the fastest of the three loop shapes).
        let kernel = fastest("per-axis");
        println!(
            "| {n} {case} | {memcpy:.2} | {hand:.2} | {hecs:.2} | {query:.2} | {par:.2} | {kernel:.2} | {one:.2} | {two:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {end_one:.2} | {end_two:.2} | {:.2} | {:.2} |",
            one / query,
            one / hand,
            two / query,
            two / par,
            kernel / query,
            one / end_one,
            two / end_two
        );
    }
}

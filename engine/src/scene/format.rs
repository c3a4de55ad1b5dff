//! The scene file format: serde types that mirror the RON text.
//!
//! Values are checked while they are read (finite vectors, positive masses,
//! known integrator names, spring ends that exist), so an error carries the
//! line and column where the bad value is, and the field path.

use core::cell::Cell;
use core::fmt;

use serde::de::{self, Deserializer};
use serde::{Deserialize, Serialize};

use crate::clock::Number;

thread_local! {
    /// Number of particles in the scene being read, for checking spring ends
    /// (set by the second pass of `Scene::parse`; `usize::MAX` = not checked).
    pub(crate) static PARTICLE_COUNT: Cell<usize> = const { Cell::new(usize::MAX) };
}

macro_rules! checked_f32 {
    ($(#[$doc:meta])* $name:ident, $check:expr, $expected:literal) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Serialize)]
        pub struct $name(pub f32);

        impl<'de> Deserialize<'de> for $name {
            fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                let value = f32::deserialize(d)?;
                let check: fn(f32) -> bool = $check;
                if check(value) {
                    Ok(Self(value))
                } else {
                    Err(de::Error::custom(format_args!(concat!("expected ", $expected, ", got {}"), value)))
                }
            }
        }
    };
}

checked_f32!(
    /// A finite number.
    Finite,
    |v| v.is_finite(),
    "a finite number"
);
checked_f32!(
    /// A finite number above zero.
    Positive,
    |v| v.is_finite() && v > 0.0,
    "a finite number above zero"
);
checked_f32!(
    /// A finite number, not negative.
    NonNegative,
    |v| v.is_finite() && v >= 0.0,
    "a finite number, not negative"
);
checked_f32!(
    /// A number in `[0, 1]`.
    Unit,
    |v| (0.0..=1.0).contains(&v),
    "a number from 0 to 1"
);

/// A vector `(x, y, z)` of finite numbers.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Vector(pub [f32; 3]);

impl<'de> Deserialize<'de> for Vector {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = <[f32; 3]>::deserialize(d)?;
        if let Some(bad) = v.iter().position(|c| !c.is_finite()) {
            return Err(de::Error::custom(format_args!(
                "expected finite coordinates, got {} for {}",
                v[bad],
                ["x", "y", "z"][bad]
            )));
        }
        Ok(Self(v))
    }
}

impl From<Vector> for glam::Vec3 {
    fn from(v: Vector) -> Self {
        glam::Vec3::from_array(v.0)
    }
}

/// A direction: a vector of finite coordinates whose length is neither zero
/// nor overflows (`(3e38, 3e38, 0)` has an infinite length), so it can be
/// normalised.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Direction(pub [f32; 3]);

impl<'de> Deserialize<'de> for Direction {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let Vector(v) = Vector::deserialize(d)?;
        if glam::Vec3::from_array(v).try_normalize().is_none() {
            return Err(de::Error::custom(format_args!(
                "expected a direction of non-zero, finite length, got {v:?}"
            )));
        }
        Ok(Self(v))
    }
}

impl From<Direction> for glam::Vec3 {
    fn from(v: Direction) -> Self {
        glam::Vec3::from_array(v.0)
    }
}

/// An integrator name that the registry knows.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MethodName(pub String);

impl<'de> Deserialize<'de> for MethodName {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let name = String::deserialize(d)?;
        match tickwork_integrators::find(&name) {
            Ok(info) => Ok(Self(info.name.to_owned())),
            Err(unknown) => Err(de::Error::custom(unknown)),
        }
    }
}

/// The index of a particle in the scene's `particles` list.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ParticleIndex(pub usize);

impl<'de> Deserialize<'de> for ParticleIndex {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let index = usize::deserialize(d)?;
        let count = PARTICLE_COUNT.with(Cell::get);
        if index >= count {
            return Err(de::Error::custom(format_args!(
                "particle index {index} is out of range: the scene lists {count} particles"
            )));
        }
        Ok(Self(index))
    }
}

/// The fixed step.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum RateSpec {
    /// Steps per second.
    Hz(Positive),
    /// Step in seconds.
    Dt(Positive),
}

/// A scene file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// Name shown in titles and summaries (default: the file name).
    #[serde(default)]
    pub name: Option<String>,
    /// One line saying what the scene shows (default: empty).
    #[serde(default)]
    pub description: String,
    /// The integrator (default: `"semi_implicit_euler"`).
    #[serde(default = "default_integrator")]
    pub integrator: MethodName,
    /// The fixed step (default: `Hz(60)`).
    #[serde(default = "default_rate")]
    pub rate: RateSpec,
    /// Seed of the world's random generator (default: `0`).
    #[serde(default)]
    pub seed: u64,
    /// Simulated seconds a headless run lasts unless told otherwise (default: `10.0`).
    #[serde(default = "default_duration")]
    pub duration: Positive,
    /// How a renderer should frame the scene (default: 2D, centred, 10 m tall).
    #[serde(default)]
    pub camera: CameraHint,
    /// Force generators (default: none).
    #[serde(default)]
    pub forces: Vec<ForceSpec>,
    /// Colliders (default: none).
    #[serde(default, deserialize_with = "checked_list")]
    pub colliders: Vec<ColliderSpec>,
    /// Particles, one by one; springs refer to them by index (default: none).
    #[serde(default)]
    pub particles: Vec<ParticleSpec>,
    /// Blocks of particles on a lattice (default: none).
    #[serde(default)]
    pub lattices: Vec<LatticeSpec>,
    /// Emitters (default: none).
    #[serde(default, deserialize_with = "checked_list")]
    pub emitters: Vec<EmitterSpec>,
    /// Rigid bodies (default: none).
    #[serde(default, deserialize_with = "checked_list")]
    pub rigid_bodies: Vec<RigidBodySpec>,
}

fn default_integrator() -> MethodName {
    MethodName("semi_implicit_euler".into())
}
fn default_rate() -> RateSpec {
    RateSpec::Hz(Positive(60.0))
}
fn default_duration() -> Positive {
    Positive(10.0)
}

/// Projection hint for renderers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Projection {
    /// Orthographic, looking down -z (default).
    #[default]
    TwoD,
    /// Perspective orbit camera.
    ThreeD,
}

/// Where a renderer should look.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraHint {
    /// 2D or 3D (default: `TwoD`).
    #[serde(default)]
    pub projection: Projection,
    /// The point looked at (default: origin).
    #[serde(default = "origin")]
    pub target: Vector,
    /// Visible height in metres (2D) or distance from the target (3D) (default: `10.0`).
    #[serde(default = "ten")]
    pub extent: Positive,
    /// Orbit angles in degrees, yaw and pitch (3D) (default: `(30, 20)`).
    #[serde(default = "default_angles")]
    pub angles: (Finite, Finite),
}

impl Default for CameraHint {
    fn default() -> Self {
        Self {
            projection: Projection::TwoD,
            target: origin(),
            extent: ten(),
            angles: default_angles(),
        }
    }
}

fn origin() -> Vector {
    Vector([0.0; 3])
}
fn ten() -> Positive {
    Positive(10.0)
}
fn default_angles() -> (Finite, Finite) {
    (Finite(30.0), Finite(20.0))
}

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

fn zero() -> NonNegative {
    NonNegative(0.0)
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

/// Bounce and friction (defaults: restitution 0.5, friction 0).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    /// In `[0, 1]` (default: `0.5`).
    #[serde(default = "half")]
    pub restitution: Unit,
    /// Coulomb coefficient (default: `0.0`).
    #[serde(default = "zero")]
    pub friction: NonNegative,
}

impl Default for MaterialSpec {
    fn default() -> Self {
        Self {
            restitution: half(),
            friction: zero(),
        }
    }
}

fn half() -> Unit {
    Unit(0.5)
}

/// A collider. A misspelt field in any variant is an error.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum ColliderSpec {
    /// An infinite plane `normal . x >= offset`.
    Plane {
        /// Normal into the free side (normalised on load).
        normal: Direction,
        /// Offset along the normal, finite (default: 0).
        #[serde(default = "zero_offset")]
        offset: Finite,
        /// Material (default: restitution 0.5, no friction).
        #[serde(default)]
        material: MaterialSpec,
    },
    /// An axis-aligned box.
    Box {
        /// Lower corner.
        min: Vector,
        /// Upper corner.
        max: Vector,
        /// Keep particles inside (true) or outside (default: true).
        #[serde(default = "yes")]
        inside: bool,
        /// Material.
        #[serde(default)]
        material: MaterialSpec,
    },
    /// Particle-particle collisions.
    Spheres {
        /// Material.
        #[serde(default)]
        material: MaterialSpec,
    },
}

fn yes() -> bool {
    true
}

fn zero_offset() -> Finite {
    Finite(0.0)
}

/// A colour `(r, g, b, a)`, each from 0 to 1, sRGB.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ColourSpec(pub Unit, pub Unit, pub Unit, pub Unit);

impl ColourSpec {
    /// As 8-bit sRGB.
    #[must_use]
    pub fn to_rgba8(self) -> [u8; 4] {
        [self.0, self.1, self.2, self.3].map(|c| (c.0 * 255.0).round() as u8)
    }
}

fn white() -> ColourSpec {
    ColourSpec(Unit(1.0), Unit(1.0), Unit(1.0), Unit(1.0))
}

/// A particle.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParticleSpec {
    /// m.
    pub position: Vector,
    /// m/s (default: zero).
    #[serde(default = "origin")]
    pub velocity: Vector,
    /// kg (default: 1).
    #[serde(default = "one")]
    pub mass: Positive,
    /// Infinite mass (default: false).
    #[serde(default)]
    pub immovable: bool,
    /// m (default: 0.05).
    #[serde(default = "small_radius")]
    pub radius: NonNegative,
    /// Colour (default: white).
    #[serde(default = "white")]
    pub colour: ColourSpec,
    /// Seconds to live (default: forever).
    #[serde(default)]
    pub lifetime: Option<Positive>,
}

fn one() -> Positive {
    Positive(1.0)
}
fn small_radius() -> NonNegative {
    NonNegative(0.05)
}

/// A block of identical particles on a lattice: `count` along each axis,
/// `spacing` apart, starting at `origin`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LatticeSpec {
    /// First particle's position.
    pub origin: Vector,
    /// Particles along x, y, z (at most [`MAX_LATTICE_PARTICLES`] in all).
    pub count: LatticeCount,
    /// Distance between neighbours, m.
    pub spacing: Positive,
    /// Every particle's velocity (default: zero).
    #[serde(default = "origin")]
    pub velocity: Vector,
    /// kg (default: 1).
    #[serde(default = "one")]
    pub mass: Positive,
    /// m (default: 0.05).
    #[serde(default = "small_radius")]
    pub radius: NonNegative,
    /// Colour (default: white).
    #[serde(default = "white")]
    pub colour: ColourSpec,
}

/// The most particles one lattice may hold: ten million (about a gigabyte
/// of world). A larger request is an error naming this limit, not an
/// allocation that aborts the process; split the lattice to go past it.
pub const MAX_LATTICE_PARTICLES: u64 = 10_000_000;

/// A lattice's particle counts along x, y and z, whose product is checked
/// against [`MAX_LATTICE_PARTICLES`] while read.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct LatticeCount(pub u32, pub u32, pub u32);

impl LatticeCount {
    /// Particles in the lattice: in u128, since three u32 can pass u64
    /// (494967295 x 10 x 4294967295 did).
    #[must_use]
    pub fn total(self) -> u128 {
        u128::from(self.0) * u128::from(self.1) * u128::from(self.2)
    }
}

impl<'de> Deserialize<'de> for LatticeCount {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let (x, y, z) = <(u32, u32, u32)>::deserialize(d)?;
        let total = Self(x, y, z).total();
        if total > u128::from(MAX_LATTICE_PARTICLES) {
            return Err(de::Error::custom(format_args!(
                "expected at most {MAX_LATTICE_PARTICLES} particles in a lattice (MAX_LATTICE_PARTICLES), \
                 got {x} x {y} x {z} = {total}; split it into several lattices"
            )));
        }
        Ok(Self(x, y, z))
    }
}

/// An emitter.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EmitterSpec {
    /// Where particles appear.
    pub position: Vector,
    /// Launch direction, of non-zero, finite length (default: +y).
    #[serde(default = "up")]
    pub direction: Direction,
    /// Cone half-angle, degrees (default: 15).
    #[serde(default = "fifteen")]
    pub spread_degrees: NonNegative,
    /// m/s.
    pub speed: NonNegative,
    /// Relative speed variation, 0 to 1 (default: 0.2).
    #[serde(default = "fifth")]
    pub speed_jitter: Unit,
    /// Particles per second.
    pub rate: NonNegative,
    /// Seconds each particle lives.
    pub lifetime: Positive,
    /// Colour (default: orange).
    #[serde(default = "orange")]
    pub colour: ColourSpec,
    /// m (default: 0.03).
    #[serde(default = "tiny_radius")]
    pub radius: NonNegative,
    /// kg (default: 0.01).
    #[serde(default = "centigram")]
    pub mass: Positive,
}

fn up() -> Direction {
    Direction([0.0, 1.0, 0.0])
}
fn fifteen() -> NonNegative {
    NonNegative(15.0)
}
fn fifth() -> Unit {
    Unit(0.2)
}
fn orange() -> ColourSpec {
    ColourSpec(Unit(1.0), Unit(0.63), Unit(0.24), Unit(1.0))
}
fn tiny_radius() -> NonNegative {
    NonNegative(0.03)
}
fn centigram() -> Positive {
    Positive(0.01)
}

/// A rigid body.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RigidBodySpec {
    /// Centre of mass.
    pub particle: ParticleSpec,
    /// Quaternion `(x, y, z, w)`, of non-zero, finite length; normalised on
    /// load (default: identity).
    #[serde(default = "identity")]
    pub orientation: Orientation,
    /// rad/s, world frame (default: zero).
    #[serde(default = "origin")]
    pub angular_velocity: Vector,
    /// Half extents of a solid box, m, none negative and at most one zero; the
    /// inertia follows from them and the mass (checked: above zero, finite
    /// and of finite inverse on every axis).
    pub half_extents: Vector,
}

fn identity() -> Orientation {
    Orientation([0.0, 0.0, 0.0, 1.0])
}

/// A rotation quaternion `(x, y, z, w)`: finite, of a length that can be
/// normalised (`(0, 0, 0, 0)` is no rotation at all).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Orientation(pub [f32; 4]);

impl<'de> Deserialize<'de> for Orientation {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let (x, y, z, w) = <(f32, f32, f32, f32)>::deserialize(d)?;
        let q = glam::Vec4::new(x, y, z, w);
        let length = q.length();
        if !q.is_finite() || !length.is_finite() || length < 1e-6 {
            return Err(de::Error::custom(format_args!(
                "expected a quaternion (x, y, z, w) of finite coordinates and non-zero, finite length, \
                 got ({x}, {y}, {z}, {w})"
            )));
        }
        Ok(Self([x, y, z, w]))
    }
}

/// Checks across the fields of one list item (a box's two corners, a rigid
/// body's mass and extents), run once the item is read: the error then
/// carries the item's path (`colliders[2]`) and the position just past it,
/// and names the fields inside.
pub(crate) trait CheckItem {
    /// `Err` says which fields disagree and what is required.
    fn check(&self) -> Result<(), String>;
}

struct Checked<T>(T);

impl<'de, T: Deserialize<'de> + CheckItem> Deserialize<'de> for Checked<T> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let item = T::deserialize(d)?;
        item.check().map_err(de::Error::custom)?;
        Ok(Self(item))
    }
}

fn checked_list<'de, D, T>(d: D) -> Result<Vec<T>, D::Error>
where
    D: Deserializer<'de>,
    T: Deserialize<'de> + CheckItem,
{
    let items = Vec::<Checked<T>>::deserialize(d)?;
    Ok(items.into_iter().map(|item| item.0).collect())
}

impl CheckItem for ColliderSpec {
    fn check(&self) -> Result<(), String> {
        let Self::Box { min, max, .. } = self else {
            return Ok(());
        };
        for (axis, name) in ["x", "y", "z"].into_iter().enumerate() {
            let (lo, hi) = (Number::from(min.0[axis]), Number::from(max.0[axis]));
            if min.0[axis] >= max.0[axis] {
                return Err(format!(
                    "Box.max.{name} = {hi} is not above Box.min.{name} = {lo}: a box's max corner must be \
                     above its min corner on every axis (swap them if they are inverted)"
                ));
            }
            if !(max.0[axis] - min.0[axis]).is_finite() {
                return Err(format!(
                    "Box from min.{name} = {lo} to max.{name} = {hi}: expected a width that is a finite number"
                ));
            }
        }
        Ok(())
    }
}

impl EmitterSpec {
    /// The engine's emitter with these settings.
    #[must_use]
    pub fn emitter(&self) -> crate::emitter::Emitter {
        crate::emitter::Emitter {
            position: self.position.into(),
            direction: self.direction.into(),
            spread: self.spread_degrees.0.to_radians(),
            speed: self.speed.0,
            speed_jitter: self.speed_jitter.0,
            rate: self.rate.0,
            lifetime: self.lifetime.0,
            colour: self.colour.to_rgba8(),
            radius: self.radius.0,
            mass: self.mass.0,
            owed: 0.0,
        }
    }
}

impl CheckItem for EmitterSpec {
    fn check(&self) -> Result<(), String> {
        // The same check as `World::add_emitter` (a jittered speed past f32,
        // a spread past 180 degrees), here so that it has a position.
        self.emitter().validate().map_err(|e| e.to_string())
    }
}

impl CheckItem for RigidBodySpec {
    fn check(&self) -> Result<(), String> {
        let h = self.half_extents.0;
        let [x, y, z] = h.map(Number::from);
        if let Some(axis) = h.iter().position(|&c| c < 0.0) {
            return Err(format!(
                "half_extents.{} = {}: expected half extents that are not negative",
                ["x", "y", "z"][axis],
                Number::from(h[axis])
            ));
        }
        // The same check as `World::spawn_rigid`, here so that it has a position.
        let mass = self.particle.mass.0;
        let body = crate::world::RigidBody::solid_box(mass, glam::Vec3::from_array(h));
        body.validate().map_err(|e| match e {
            crate::world::SpawnError::Invalid { field, value, .. } if field.starts_with("inertia") => format!(
                "half_extents ({x}, {y}, {z}) and mass {} give the moment of inertia {field} = {}: expected \
                 one above zero and finite, whose inverse is finite (at most one half extent may be zero)",
                Number::from(mass),
                Number::from(value)
            ),
            _ => e.to_string(),
        })
    }
}

impl fmt::Display for RateSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Hz(hz) => write!(f, "{} Hz", hz.0),
            Self::Dt(dt) => write!(f, "dt = {} s", dt.0),
        }
    }
}

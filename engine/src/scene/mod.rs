//! Scenes: RON files that describe a world (particles, emitters, rigid
//! bodies, forces, colliders, integrator, rate, seed, camera).
//!
//! ```ron
//! SceneFile(
//!     name: Some("ball"),
//!     integrator: "velocity_verlet",
//!     rate: Hz(120),
//!     forces: [Gravity((0, -9.81, 0))],
//!     colliders: [Plane(normal: (0, 1, 0), material: (restitution: 0.8))],
//!     particles: [(position: (0, 2, 0), radius: 0.1)],
//! )
//! ```
//!
//! A malformed file is a [`SceneError`] with the file, line, column, the path
//! of the field at fault (`particles[1].mass`) and what was expected.

pub mod format;

use core::fmt;
use std::path::Path;

use glam::{Quat, Vec3};

pub use format::SceneFile;
use format::{ColliderSpec, EndSpec, ForceSpec, PARTICLE_COUNT, ParticleSpec, RateSpec};

use crate::clock::Rate;
use crate::colliders::{BoxCollider, Material, Plane, SphereCollisions};
use crate::forces::{Attractor, Gravity, LinearDrag, NBody, QuadraticDrag, Spring, SpringEnd, Springs, Wind};
use crate::world::{Entity, Particle, RigidBody, World, WorldConfig};

/// A scene that could not be read.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SceneError {
    /// The file (or `<string>`).
    pub file: String,
    /// Line and column (1-based) of the fault, when the text has one.
    pub position: Option<(usize, usize)>,
    /// Path of the field at fault (`particles[1].mass`); empty for the whole file.
    pub field: String,
    /// What was wrong.
    pub message: String,
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file)?;
        if let Some((line, column)) = self.position {
            write!(f, ":{line}:{column}")?;
        }
        if !self.field.is_empty() && self.field != "." && self.field != "?" {
            write!(f, ": {}", self.field)?;
        }
        write!(f, ": {}", self.message)
    }
}

impl std::error::Error for SceneError {}

/// A parsed scene, ready to build worlds from.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// Where it came from.
    pub file: String,
    /// The parsed description.
    pub spec: SceneFile,
}

impl Scene {
    /// Reads a scene file.
    ///
    /// # Errors
    /// [`SceneError`] for an unreadable or malformed file.
    pub fn load(path: &Path) -> Result<Self, SceneError> {
        let file = path.display().to_string();
        let text =
            crate::text_file::read_limited(path, Self::MAX_FILE_BYTES, "Scene::MAX_FILE_BYTES").map_err(|e| {
                let hint = if e.starts_with("it is larger") {
                    "; a scene this large is better built by a program"
                } else {
                    ""
                };
                SceneError {
                    file: file.clone(),
                    position: None,
                    field: String::new(),
                    message: format!("cannot read the scene: {e}{hint}"),
                }
            })?;
        Self::parse(&text, &file)
    }

    /// The largest scene file read: 16 MiB.
    pub const MAX_FILE_BYTES: u64 = 16 << 20;

    /// Parses scene text; `file` names it in errors.
    ///
    /// # Errors
    /// [`SceneError`] with line, column and field for malformed text.
    pub fn parse(text: &str, file: &str) -> Result<Self, SceneError> {
        // First pass: everything but spring ends; second pass: spring ends
        // checked against the number of particles the first pass found, so
        // an out-of-range index is reported where it is written.
        let first = read(text, file, usize::MAX)?;
        let spec = if first.forces.iter().any(|f| matches!(f, ForceSpec::Spring { .. })) {
            read(text, file, first.particles.len())?
        } else {
            first
        };
        Ok(Self {
            file: file.to_owned(),
            spec,
        })
    }

    /// The scene's name: its `name` field or the file's stem.
    #[must_use]
    pub fn name(&self) -> String {
        self.spec.name.clone().unwrap_or_else(|| {
            Path::new(&self.file)
                .file_stem()
                .map_or_else(|| self.file.clone(), |s| s.to_string_lossy().into())
        })
    }

    /// The fixed step the scene asks for.
    ///
    /// # Errors
    /// [`SceneError`] for a rate the clock cannot represent.
    pub fn rate(&self) -> Result<Rate, SceneError> {
        let rate = match self.spec.rate {
            RateSpec::Hz(hz) => Rate::hz_f64(f64::from(hz.0)),
            RateSpec::Dt(dt) => Rate::seconds(f64::from(dt.0)),
        };
        rate.map_err(|e| self.error("rate", e.to_string()))
    }

    fn error(&self, field: &str, message: String) -> SceneError {
        SceneError {
            file: self.file.clone(),
            position: None,
            field: field.into(),
            message,
        }
    }

    /// The settings of the scene's world: its integrator and seed, the rest
    /// [`WorldConfig::default`].
    #[must_use]
    pub fn world_config(&self) -> WorldConfig {
        WorldConfig {
            integrator: self.spec.integrator.0.clone(),
            seed: self.spec.seed,
            backend: self.spec.backend,
            ..WorldConfig::default()
        }
    }

    /// Builds a world: particles (in file order, then lattices), rigid
    /// bodies, emitters, forces (springs grouped into one force), colliders.
    /// Returns the world and the entities of the listed `particles`.
    ///
    /// # Errors
    /// [`SceneError`] if a value is refused by the world (which the format's
    /// checks should already have caught), or the scene holds more particles
    /// than [`WorldConfig::max_particles`].
    pub fn build(&self) -> Result<(World, Vec<Entity>), SceneError> {
        self.build_with(self.world_config())
    }

    /// [`build`](Self::build) with other settings (limits, threads): the
    /// scene's integrator and seed are taken from `config`, so start from
    /// [`world_config`](Self::world_config).
    ///
    /// # Errors
    /// As [`build`](Self::build).
    pub fn build_with(&self, config: WorldConfig) -> Result<(World, Vec<Entity>), SceneError> {
        let s = &self.spec;
        // Counted before anything is allocated: two lattices under their own
        // limit can still be past the world's.
        let lattice_particles = s.lattices.iter().map(|l| l.count.total()).sum::<u128>();
        let total = lattice_particles + s.particles.len() as u128 + s.rigid_bodies.len() as u128;
        if total > config.max_particles as u128 {
            return Err(self.error(
                "",
                format!(
                    "the scene holds {total} particles, past the world's limit of {} \
                     (WorldConfig::max_particles); build it with Scene::build_with and a higher limit",
                    config.max_particles
                ),
            ));
        }
        let mut world = World::new(config).map_err(|e| self.error("integrator", e.to_string()))?;
        let mut listed = Vec::with_capacity(s.particles.len());
        for (k, p) in s.particles.iter().enumerate() {
            let entity = world
                .spawn(particle(p))
                .map_err(|e| self.error(&format!("particles[{k}]"), e.to_string()))?;
            listed.push(entity);
        }
        for (k, l) in s.lattices.iter().enumerate() {
            let format::LatticeCount(nx, ny, nz) = l.count;
            for (i, j, m) in (0..nz).flat_map(|m| (0..ny).flat_map(move |j| (0..nx).map(move |i| (i, j, m)))) {
                let offset = Vec3::new(i as f32, j as f32, m as f32) * l.spacing.0;
                let p = Particle {
                    position: Vec3::from(l.origin) + offset,
                    velocity: l.velocity.into(),
                    mass: l.mass.0,
                    radius: l.radius.0,
                    colour: l.colour.to_rgba8(),
                    ..Particle::default()
                };
                world
                    .spawn(p)
                    .map_err(|e| self.error(&format!("lattices[{k}]"), e.to_string()))?;
            }
        }
        for (k, b) in s.rigid_bodies.iter().enumerate() {
            let mut body = RigidBody::solid_box(b.particle.mass.0, b.half_extents.into());
            body.particle = particle(&b.particle);
            // Checked while read: finite, of a length that normalises.
            body.orientation = Quat::from_array(b.orientation.0).normalize();
            body.angular_velocity = b.angular_velocity.into();
            world
                .spawn_rigid(body)
                .map_err(|e| self.error(&format!("rigid_bodies[{k}]"), e.to_string()))?;
        }
        for (k, e) in s.emitters.iter().enumerate() {
            world
                .add_emitter(e.emitter())
                .map_err(|e| self.error(&format!("emitters[{k}]"), e.to_string()))?;
        }
        let mut springs = Springs::default();
        let end = |e: EndSpec| match e {
            EndSpec::Particle(i) => SpringEnd::Entity(listed[i.0]),
            EndSpec::Anchor(p) => SpringEnd::Anchor(p.into()),
        };
        for f in &s.forces {
            match *f {
                ForceSpec::Gravity(g) => world.add_force(Gravity { acceleration: g.into() }),
                ForceSpec::LinearDrag { rate } => world.add_force(LinearDrag { rate: rate.0 }),
                ForceSpec::QuadraticDrag { coefficient } => {
                    world.add_force(QuadraticDrag {
                        coefficient: coefficient.0,
                    });
                }
                ForceSpec::Wind { velocity, rate } => world.add_force(Wind {
                    velocity: velocity.into(),
                    rate: rate.0,
                }),
                ForceSpec::Attractor {
                    position,
                    gm,
                    softening,
                } => {
                    world.add_force(Attractor {
                        position: position.into(),
                        gm: gm.0,
                        softening: softening.0,
                    });
                }
                ForceSpec::NBody { g, softening } => world.add_force(NBody::new(g.0, softening.0)),
                ForceSpec::Spring {
                    a,
                    b,
                    stiffness,
                    rest_length,
                    damping,
                } => springs.push(Spring {
                    a: end(a),
                    b: end(b),
                    stiffness: stiffness.0,
                    rest_length: rest_length.0,
                    damping: damping.0,
                }),
            }
        }
        if !springs.springs().is_empty() {
            world.add_force(springs);
        }
        for c in &s.colliders {
            match *c {
                ColliderSpec::Plane {
                    normal,
                    offset,
                    material,
                    contact,
                } => {
                    // Checked while read: finite, of non-zero, finite length.
                    let unit = Vec3::from(normal).normalize_or(Vec3::Y);
                    world.add_collider(Plane {
                        normal: unit,
                        offset: offset.0,
                        material: material_of(material),
                        contact: contact.into(),
                        ..Plane::default()
                    });
                }
                ColliderSpec::Box {
                    min,
                    max,
                    inside,
                    material,
                    contact,
                } => {
                    world.add_collider(BoxCollider {
                        min: min.into(),
                        max: max.into(),
                        inside,
                        material: material_of(material),
                        contact: contact.into(),
                        ..BoxCollider::default()
                    });
                }
                ColliderSpec::Spheres { material, swept } => {
                    let mut spheres = SphereCollisions::new(material_of(material));
                    spheres.swept = swept;
                    world.add_collider(spheres);
                }
            }
        }
        Ok((world, listed))
    }
}

fn particle(p: &ParticleSpec) -> Particle {
    Particle {
        position: p.position.into(),
        velocity: p.velocity.into(),
        mass: p.mass.0,
        immovable: p.immovable,
        radius: p.radius.0,
        colour: p.colour.to_rgba8(),
        lifetime: p.lifetime.map(|l| l.0),
    }
}

fn material_of(m: format::MaterialSpec) -> Material {
    Material {
        restitution: m.restitution.0,
        friction: m.friction.0,
    }
}

fn read(text: &str, file: &str, particles: usize) -> Result<SceneFile, SceneError> {
    let error = |position: ron::error::Position, field: String, message: String| SceneError {
        file: file.to_owned(),
        position: Some((position.line, position.col)),
        field,
        message,
    };
    let mut de =
        ron::Deserializer::from_str(text).map_err(|e| error(e.span.start, String::new(), e.code.to_string()))?;
    PARTICLE_COUNT.with(|c| c.set(particles));
    let result: Result<SceneFile, _> = serde_path_to_error::deserialize(&mut de);
    PARTICLE_COUNT.with(|c| c.set(usize::MAX));
    match result {
        Ok(spec) => {
            de.end().map_err(|e| {
                let spanned = de.span_error(e);
                error(spanned.span.start, String::new(), spanned.code.to_string())
            })?;
            Ok(spec)
        }
        Err(e) => {
            let field = e.path().to_string();
            let spanned = de.span_error(e.into_inner());
            Err(error(spanned.span.start, field, spanned.code.to_string()))
        }
    }
}

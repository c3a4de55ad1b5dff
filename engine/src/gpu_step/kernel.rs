//! What a world asks of the GPU step, read from it once: the method's
//! WGSL, the affine forces' sums and the colliders, or the error that names
//! what the GPU step does not do.

use glam::Vec3A;

use super::error::GpuStepError;
use crate::colliders::{BoxCollider, Plane};
use crate::forces::{Attractor, Force, NBody, QuadraticDrag};
use crate::world::World;

/// The step's shader: the common part (the bindings and entry points, the
/// end-of-step colliders, history, n-body), then the contacts inside the
/// step, then the method's `advance`.
const COMMON: &str = concat!(
    include_str!("../../shaders/gpu_step/step.wgsl"),
    "\n",
    include_str!("../../shaders/gpu_step/colliders.wgsl"),
    "\n",
    include_str!("../../shaders/gpu_step/history.wgsl"),
    "\n",
    include_str!("../../shaders/gpu_step/nbody.wgsl"),
);

/// Contacts inside the step (`ContactRule::InStep` planes and boxes).
const IN_STEP: &str = include_str!("../../shaders/gpu_step/in_step.wgsl");

/// The methods with a GPU form: name, WGSL, and the most evaluations of
/// the acceleration it makes in one step (where a particle starts by RK4:
/// one more than RK4's four for Beeman), the n-body rounds of its step.
const METHODS: &[(&str, &str, u32)] = &[
    (
        "semi_implicit_euler",
        include_str!("../../shaders/gpu_step/semi_implicit_euler.wgsl"),
        1,
    ),
    (
        "explicit_euler",
        include_str!("../../shaders/gpu_step/explicit_euler.wgsl"),
        1,
    ),
    ("midpoint", include_str!("../../shaders/gpu_step/midpoint.wgsl"), 2),
    ("heun", include_str!("../../shaders/gpu_step/heun.wgsl"), 2),
    ("rk4", include_str!("../../shaders/gpu_step/rk4.wgsl"), 4),
    (
        "forest_ruth",
        include_str!("../../shaders/gpu_step/forest_ruth.wgsl"),
        3,
    ),
    (
        "velocity_verlet",
        include_str!("../../shaders/gpu_step/velocity_verlet.wgsl"),
        2,
    ),
    ("leapfrog", include_str!("../../shaders/gpu_step/leapfrog.wgsl"), 2),
    (
        "position_verlet",
        include_str!("../../shaders/gpu_step/position_verlet.wgsl"),
        4,
    ),
    ("beeman", include_str!("../../shaders/gpu_step/beeman.wgsl"), 5),
    (
        "adams_bashforth2",
        include_str!("../../shaders/gpu_step/adams_bashforth.wgsl"),
        4,
    ),
    (
        "adams_bashforth3",
        include_str!("../../shaders/gpu_step/adams_bashforth.wgsl"),
        4,
    ),
    (
        "adams_bashforth4",
        include_str!("../../shaders/gpu_step/adams_bashforth.wgsl"),
        4,
    ),
];

/// Whether the GPU step has a form of the method `name` (the registry's
/// canonical name): what the viewer's Tab offers a GPU world.
pub(crate) fn takes_method(name: &str) -> bool {
    METHODS.iter().any(|(method, ..)| *method == name)
}

/// The methods of [`METHODS`] that keep a history between steps, and its
/// records (`vec4`s) a particle: `HISTORY` in the shader, written there
/// from this table (restarted as the CPU's `History` restarts).
const HISTORY_RECORDS: &[(&str, u32)] = &[
    ("velocity_verlet", 1),
    ("leapfrog", 1),
    ("position_verlet", 1),
    ("beeman", 2),
    ("adams_bashforth2", 2),
    ("adams_bashforth3", 4),
    ("adams_bashforth4", 6),
];

/// An f32 as WGSL reads back its exact bits (written without allocating).
struct Bits(f32);

impl core::fmt::Display for Bits {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "bitcast<f32>({:#010x}u)", self.0.to_bits())
    }
}

fn bits(value: f32) -> Bits {
    Bits(value)
}

/// Writes the WGSL `acceleration(x, v, w)` of `forces` into `out`: the
/// affine sum from the uniform, then each other force in force order, with
/// its values written in (their exact bits), as the CPU's force field adds
/// them.
fn acceleration_into(forces: &[Box<dyn Force>], out: &mut String) -> Result<(), GpuStepError> {
    use core::fmt::Write;
    // Writing into a String cannot fail.
    let _ = out.write_str("fn acceleration(x: vec3<f32>, v: vec3<f32>, w: f32) -> vec3<f32> {\n");
    if forces.iter().any(|f| f.as_any().downcast_ref::<NBody>().is_some()) {
        // Every particle's evaluation counts, an immovable one's too: its
        // trial position is written down for the others' sums.
        out.push_str("    let pull = nbody_term(x);\n");
    }
    let _ = out.write_str(
        "    if (!(w > 0.0)) {\n        return vec3<f32>(0.0);\n    }\n    var a = params.c - v * params.b;\n",
    );
    for force in forces.iter().filter(|f| f.affine_in_velocity().is_none()) {
        let any = force.as_any();
        if let Some(drag) = any.downcast_ref::<QuadraticDrag>() {
            let _ = writeln!(
                out,
                "    a = a - v * ({} * sqrt(length_squared(v)));",
                bits(drag.coefficient)
            );
        } else if let Some(attractor) = any.downcast_ref::<Attractor>() {
            let p = attractor.position;
            let _ = writeln!(
                out,
                "    {{\n        let d = vec3<f32>({}, {}, {}) - x;\n        let r2 = length_squared(d) + {};\n        \
                 a = a + d * ({} / (r2 * sqrt(r2)));\n    }}",
                bits(p.x),
                bits(p.y),
                bits(p.z),
                bits(attractor.softening * attractor.softening),
                bits(attractor.gm)
            );
        } else if any.downcast_ref::<NBody>().is_some() {
            out.push_str("    a = a + pull;\n");
        } else {
            return Err(GpuStepError::Force { force: force.name() });
        }
    }
    out.push_str("    return a;\n}\n");
    Ok(())
}

/// A method's step coefficients for a step of `h` seconds, `(drift,
/// kick)` as `Params` carries them: Forest-Ruth's weights times `h`, in
/// f64 then rounded, as `integrators/src/methods/forest_ruth.rs` does;
/// Adams-Bashforth's `beta` in `drift`; unused (zero) for the others.
pub(super) fn coefficients(method: &str, h: f32) -> ([f32; 4], [f32; 4]) {
    // Adams-Bashforth's b_j h, formed in f64 and rounded, as
    // `integrators/src/methods/adams_bashforth.rs` forms its beta.
    let adams: &[f64] = match method {
        "adams_bashforth2" => &[3.0 / 2.0, -1.0 / 2.0],
        "adams_bashforth3" => &[23.0 / 12.0, -16.0 / 12.0, 5.0 / 12.0],
        "adams_bashforth4" => &[55.0 / 24.0, -59.0 / 24.0, 37.0 / 24.0, -9.0 / 24.0],
        _ => &[],
    };
    if !adams.is_empty() {
        let beta = std::array::from_fn(|j| adams.get(j).map_or(0.0, |b| (b * f64::from(h)) as f32));
        return (beta, [0.0; 4]);
    }
    if method != "forest_ruth" {
        return ([0.0; 4], [0.0; 4]);
    }
    let theta = 1.0 / (2.0 - tickwork_integrators::math::powf(2f64, 1.0 / 3.0));
    let h = f64::from(h);
    let drifts = [theta / 2.0, (1.0 - theta) / 2.0, (1.0 - theta) / 2.0, theta / 2.0];
    let kicks = [theta, 1.0 - 2.0 * theta, theta, 0.0];
    (drifts.map(|d| (d * h) as f32), kicks.map(|k| (k * h) as f32))
}

/// What a collider record is (`ColliderRecord::kind`).
pub(super) const PLANE: u32 = 0;
/// A box that keeps particles inside.
pub(super) const CONTAINER: u32 = 1;
/// A box that keeps particles out.
pub(super) const SOLID: u32 = 2;
/// A plane moving along its normal (the normal in `min`).
pub(super) const MOVING_PLANE: u32 = 3;

/// A collider as the shader reads it (`Collider` in `step.wgsl`): a plane
/// (`axis`, `sign`, `offset`; moving: its normal in `min`) or a box
/// (`min`, `max`), with its material and, kinematic, its velocity `u`,
/// where it stands after the step's move; `flags`: [`MOVES`], [`REPORTS`].
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct ColliderRecord {
    pub kind: u32,
    pub axis: u32,
    pub sign: f32,
    pub offset: f32,
    pub restitution: f32,
    pub friction: f32,
    pub min: [f32; 3],
    pub max: [f32; 3],
    pub u: [f32; 3],
    pub flags: u32,
}

/// `ColliderRecord::flags`: the collider is kinematic.
pub(super) const MOVES: u32 = 1;
/// `ColliderRecord::flags`: the collider reports its contacts.
pub(super) const REPORTS: u32 = 2;
/// `ColliderRecord::flags`: the collider finds its contacts inside the
/// step (`IN_STEP_FLAG` in `in_step.wgsl`).
pub(super) const FINDS_IN_STEP: u32 = 4;

const _: () = assert!(std::mem::size_of::<ColliderRecord>() == 64);

/// Contacts a step of a world with a reporting collider has room for
/// beyond [`Plan::touch_records`] a particle.
pub(super) const SPARE_TOUCHES: u64 = 1024;

/// A world's step as the GPU runs it.
#[derive(Clone, Debug)]
pub(super) struct Plan {
    /// The method's name.
    pub method: &'static str,
    /// The shader's source.
    pub source: String,
    /// The affine forces' sums `(c, b)`: `a = c - b v`, in force order from
    /// `(0, 0)` as the CPU's force field sums them.
    pub affine: (Vec3A, f32),
    /// The n-body force's `G` and softening squared, if the world has one.
    pub nbody: Option<(f32, f32)>,
    /// With n-body, the most evaluations the method makes in a step: the
    /// rounds of probe and sums before the step proper (0 without).
    pub stages: u32,
    /// The colliders, in the order they act.
    pub colliders: Vec<ColliderRecord>,
    /// The method's history records (`vec4`s) a particle (0: none).
    pub history: u32,
    /// Whether a collider moves (kinematic): its record changes every step.
    pub moving: bool,
    /// How many colliders report their contacts (read back every step).
    pub reporting: u32,
    /// How many of those find their contacts inside the step (up to
    /// `MAX_CONTACT_EVENTS` and one more at its end, a particle a step).
    pub reporting_in_step: u32,
}

impl Plan {
    /// The most vec4s a particle that a buffer of the step holds (history,
    /// the n-body rounds, the contacts of reporting colliders: three a
    /// contact): what bounds the particles a device fits.
    pub(super) fn records(&self) -> u32 {
        let touches = u32::try_from(3 * self.touch_records()).unwrap_or(u32::MAX);
        self.history.max(self.stages + 1).max(touches)
    }

    /// Room for the contacts of a step of `n` particles:
    /// [`touch_records`](Self::touch_records) a particle and, where a
    /// collider reports, [`SPARE_TOUCHES`] more (a few particles, such as a
    /// game's one ball, may meet many contacts in one step).
    pub(super) fn touch_room(&self, n: u64) -> u64 {
        let spare = if self.reporting > 0 { SPARE_TOUCHES } else { 0 };
        n.saturating_mul(self.touch_records()).saturating_add(spare)
    }

    /// The contacts a particle may report in a step (the touches buffer's
    /// records a particle): one for a collider found at the step's end,
    /// two for one that finds them inside it (a bounce and the end-of-step
    /// rule; more in one step, a particle in a corner, is rare: a step
    /// past the room is [`GpuStepError::Contacts`]).
    pub(super) fn touch_records(&self) -> u64 {
        u64::from(self.reporting) + u64::from(self.reporting_in_step)
    }

    /// A plan of nothing, to [`refresh`](Self::refresh).
    pub(super) fn empty() -> Self {
        Self {
            method: "",
            source: String::new(),
            affine: (Vec3A::ZERO, 0.0),
            nbody: None,
            stages: 0,
            colliders: Vec::new(),
            history: 0,
            moving: false,
            reporting: 0,
            reporting_in_step: 0,
        }
    }
}

/// The plan of `world`'s step, or what the GPU step does not do of it.
pub(super) fn plan(world: &World) -> Result<Plan, GpuStepError> {
    let mut plan = Plan::empty();
    refresh(world, &mut plan)?;
    Ok(plan)
}

/// Whether `world` changes its rows in its steps, so that a GPU world
/// follows it step by step ([`GpuWorld::advance`](super::GpuWorld::advance)):
/// emitters, particles that expire, queued spawns or despawns.
pub(super) fn changes_rows(world: &World) -> bool {
    // (NaN never expires, as on the CPU.)
    !world.emitters.is_empty()
        || !world.queue.is_empty()
        || world
            .particles()
            .lifetime
            .iter()
            .any(|&l| l != f32::INFINITY && !l.is_nan())
}

/// Writes the plan of `world`'s step into `plan`, reusing its buffers (a
/// step re-reads the world's forces and colliders without allocating), or
/// the error naming what the GPU step does not do of it.
pub(super) fn refresh(world: &World, plan: &mut Plan) -> Result<(), GpuStepError> {
    let info = world.integrator().info();
    let Some(&(method, wgsl, evaluations)) = METHODS.iter().find(|(name, ..)| *name == info.name) else {
        let reason = if info.implicit || info.variable_cost {
            "implicit and adaptive methods stay on the CPU"
        } else {
            "not on the GPU yet (these are: explicit and semi-implicit Euler, midpoint, Heun, RK4, Forest-Ruth, \
             velocity Verlet, leapfrog, position Verlet, Beeman and Adams-Bashforth 2-4)"
        };
        return Err(GpuStepError::Method {
            method: info.name.to_owned(),
            reason,
        });
    };
    let mut affine = (Vec3A::ZERO, 0.0f32);
    for force in world.forces() {
        if let Some((c, b)) = force.affine_in_velocity() {
            affine = (affine.0 + c, affine.1 + b);
        }
    }
    plan.source.clear();
    plan.source.push_str(COMMON);
    plan.source.push('\n');
    plan.source.push_str(IN_STEP);
    plan.source.push('\n');
    acceleration_into(world.forces(), &mut plan.source)?;
    plan.source.push('\n');
    plan.source.push_str(wgsl);
    let history = HISTORY_RECORDS
        .iter()
        .find(|(name, _)| *name == method)
        .map_or(0, |&(_, records)| records);
    // Writing into a String cannot fail.
    let _ = core::fmt::Write::write_fmt(&mut plan.source, format_args!("\nconst HISTORY: u32 = {history}u;\n"));
    let mut nbodies = world.forces().iter().filter_map(|f| f.as_any().downcast_ref::<NBody>());
    let nbody = nbodies.next().map(|n| (n.g, n.softening * n.softening));
    if nbodies.next().is_some() {
        return Err(GpuStepError::Unsupported("more than one n-body force"));
    }
    // A step of a world with n-body is `stages` rounds of sums (1 without).
    let stages = if nbody.is_some() { evaluations } else { 0 };
    let _ = core::fmt::Write::write_fmt(
        &mut plan.source,
        format_args!(
            "const COUPLED: bool = {};\nconst STAGES: u32 = {};\n",
            nbody.is_some(),
            stages.max(1)
        ),
    );
    let colliders = &mut plan.colliders;
    colliders.clear();
    plan.moving = false;
    plan.reporting = 0;
    plan.reporting_in_step = 0;
    let (mut in_step, mut in_step_boxes) = (false, false);
    for (id, collider) in world.colliders() {
        let name = collider.name();
        let refuse = |reason| GpuStepError::Collider { collider: name, reason };
        let reports = world.colliders.index(id).is_ok_and(|k| world.colliders.reports[k]);
        plan.reporting += u32::from(reports);
        plan.reporting_in_step += u32::from(reports && collider.in_step());
        in_step |= collider.in_step();
        in_step_boxes |= collider.in_step() && collider.as_any().downcast_ref::<BoxCollider>().is_some();
        let reports = if reports { REPORTS } else { 0 } | if collider.in_step() { FINDS_IN_STEP } else { 0 };
        if let Some(b) = collider.as_any().downcast_ref::<BoxCollider>() {
            let moving = b.velocity != glam::Vec3::ZERO;
            plan.moving |= moving;
            colliders.push(ColliderRecord {
                kind: if b.inside { CONTAINER } else { SOLID },
                axis: 0,
                sign: 0.0,
                offset: 0.0,
                restitution: b.material.restitution,
                friction: b.material.friction,
                min: b.min.to_array(),
                max: b.max.to_array(),
                u: b.velocity.to_array(),
                flags: if moving { MOVES } else { 0 } | reports,
            });
            continue;
        }
        if name == "spheres" {
            return Err(refuse(
                "sphere-sphere collisions stay on the CPU (the GPU step resolves planes and boxes)",
            ));
        }
        let plane = collider
            .as_any()
            .downcast_ref::<Plane>()
            .ok_or(GpuStepError::Collider {
                collider: name,
                reason: "the GPU step resolves planes and boxes only",
            })?;
        let n = plane.normal;
        let axis = [n.x, n.y, n.z]
            .iter()
            .position(|c| c.abs() == 1.0)
            .filter(|&a| (0..3).all(|k| k == a || n[k] == 0.0))
            .ok_or(refuse("its normal is not an axis"))?;
        let moving = plane.speed != 0.0;
        plan.moving |= moving;
        colliders.push(ColliderRecord {
            kind: if moving { MOVING_PLANE } else { PLANE },
            axis: axis as u32,
            sign: n[axis],
            offset: plane.offset,
            restitution: plane.material.restitution,
            friction: plane.material.friction,
            // A moving plane's contact is the general one, along its normal.
            min: if moving { n.to_array() } else { [0.0; 3] },
            max: [0.0; 3],
            // u = n speed, as the CPU forms it (f32, lane by lane).
            u: (glam::Vec3A::from(n) * plane.speed).to_array(),
            flags: if moving { MOVES } else { 0 } | reports,
        });
    }
    if world.sensors().next().is_some() {
        return Err(GpuStepError::Unsupported("sensors"));
    }
    if !world.rigid.is_empty() {
        return Err(GpuStepError::Unsupported("rigid bodies"));
    }
    if world.has_headings() {
        return Err(GpuStepError::Unsupported("2D headings"));
    }
    let particles = world.len();
    for force in world.forces() {
        let pairs = force.pairs(particles);
        if pairs > world.config.max_pairs {
            return Err(GpuStepError::Pairs {
                force: force.name(),
                pairs,
                limit: world.config.max_pairs,
            });
        }
    }
    // What the colliders' loop compiles in (see `resolve_colliders`), and
    // the in-step rule's rest speed (as the CPU's `Sweep` takes it: NaN or
    // negative rests none, infinite is f32::MAX) and limit.
    let rest = world.config.rest_speed;
    let rest = if rest >= 0.0 { rest.min(f32::MAX) } else { 0.0 };
    let _ = core::fmt::Write::write_fmt(
        &mut plan.source,
        format_args!(
            "const KINEMATIC: bool = {};\nconst REPORTING: bool = {};\nconst IN_STEP: bool = {in_step};\n\
             const IN_STEP_BOXES: bool = {in_step_boxes};\n\
             fn rest_speed() -> f32 {{ return {}; }}\nconst MAX_EVENTS: u32 = {}u;\n",
            plan.moving,
            plan.reporting > 0,
            bits(rest),
            crate::colliders::MAX_CONTACT_EVENTS,
        ),
    );
    plan.method = method;
    plan.history = history;
    plan.affine = affine;
    plan.nbody = nbody;
    plan.stages = stages;
    Ok(())
}

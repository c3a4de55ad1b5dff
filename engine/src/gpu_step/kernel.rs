//! What a world asks of the GPU step, read from it once: the method's
//! WGSL, the affine forces' sums and the colliders, or the error that names
//! what the GPU step does not do.

use glam::Vec3A;

use tickwork_integrators::MethodInfo;
use tickwork_integrators::methods::{
    adams_bashforth, adams_bashforth2, adams_bashforth3, adams_bashforth4, beeman, explicit_euler, forest_ruth, heun,
    leapfrog, midpoint, position_verlet, rk4, semi_implicit_euler, velocity_verlet,
};

use super::error::GpuStepError;
use crate::colliders::GpuCollider;
use crate::device::wgsl;
use crate::forces::{Force, GpuForce, WgslF32, affine_sum};
use crate::world::World;

/// The step's shader: the common part (the bindings and entry points, the
/// end-of-step colliders, history, n-body), then the contacts inside the
/// step, then the method's `advance`.
const COMMON: &str = wgsl!(
    "gpu_step/step.wgsl",
    "gpu_step/colliders.wgsl",
    "gpu_step/history.wgsl",
    "gpu_step/nbody.wgsl",
);

/// Contacts inside the step (`ContactRule::InStep` planes and boxes).
const IN_STEP: &str = wgsl!("gpu_step/in_step.wgsl");

/// How a method's step coefficients are formed (`drift`, `kick` in
/// `Params`): from the integrators crate's own weights.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Coefficients {
    /// None (zero).
    None,
    /// Forest-Ruth's drifts and kicks times `h`
    /// ([`forest_ruth::weights`]).
    ForestRuth,
    /// Adams-Bashforth's betas of `K` steps in `drift`
    /// ([`adams_bashforth::coefficients`]).
    AdamsBashforth(usize),
}

/// A method's GPU form: the registry's entry (its name), its WGSL, the
/// most evaluations of the acceleration it makes in one step (where a
/// particle starts by RK4: one more than RK4's four for Beeman), the
/// n-body rounds of its step; its history records (`vec4`s) a particle
/// (`HISTORY` in the shader, restarted as the CPU's `History` restarts;
/// 0: none); and its coefficients.
struct GpuMethod {
    info: MethodInfo,
    wgsl: &'static str,
    evaluations: u32,
    history: u32,
    coefficients: Coefficients,
}

/// A method's GPU form (see [`GpuMethod`]).
const fn method(info: MethodInfo, wgsl: &'static str, evaluations: u32, history: u32) -> GpuMethod {
    GpuMethod {
        info,
        wgsl,
        evaluations,
        history,
        coefficients: Coefficients::None,
    }
}

/// Adams-Bashforth of any steps (`HISTORY` and the betas say how many).
const ADAMS_BASHFORTH: &str = wgsl!("gpu_step/adams_bashforth.wgsl");

/// The methods with a GPU form.
const METHODS: &[GpuMethod] = &[
    method(
        semi_implicit_euler::INFO,
        wgsl!("gpu_step/semi_implicit_euler.wgsl"),
        1,
        0,
    ),
    method(explicit_euler::INFO, wgsl!("gpu_step/explicit_euler.wgsl"), 1, 0),
    method(midpoint::INFO, wgsl!("gpu_step/midpoint.wgsl"), 2, 0),
    method(heun::INFO, wgsl!("gpu_step/heun.wgsl"), 2, 0),
    method(rk4::INFO, wgsl!("gpu_step/rk4.wgsl"), 4, 0),
    GpuMethod {
        coefficients: Coefficients::ForestRuth,
        ..method(forest_ruth::INFO, wgsl!("gpu_step/forest_ruth.wgsl"), 3, 0)
    },
    method(velocity_verlet::INFO, wgsl!("gpu_step/velocity_verlet.wgsl"), 2, 1),
    method(leapfrog::INFO, wgsl!("gpu_step/leapfrog.wgsl"), 2, 1),
    method(position_verlet::INFO, wgsl!("gpu_step/position_verlet.wgsl"), 4, 1),
    method(beeman::INFO, wgsl!("gpu_step/beeman.wgsl"), 5, 2),
    GpuMethod {
        coefficients: Coefficients::AdamsBashforth(2),
        ..method(adams_bashforth2::INFO, ADAMS_BASHFORTH, 4, 2)
    },
    GpuMethod {
        coefficients: Coefficients::AdamsBashforth(3),
        ..method(adams_bashforth3::INFO, ADAMS_BASHFORTH, 4, 4)
    },
    GpuMethod {
        coefficients: Coefficients::AdamsBashforth(4),
        ..method(adams_bashforth4::INFO, ADAMS_BASHFORTH, 4, 6)
    },
];

/// The GPU form of the method the registry calls `name`.
fn gpu_method(name: &str) -> Option<&'static GpuMethod> {
    METHODS.iter().find(|m| m.info.name == name)
}

/// The registry's names of the methods the GPU step has a form of, in the
/// registry's order of its table here: what `--gpu` accepts.
pub fn methods() -> impl Iterator<Item = &'static str> {
    METHODS.iter().map(|m| m.info.name)
}

/// Whether the GPU step has a form of the method `name` (the registry's
/// canonical name): what the viewer's Tab offers a GPU world.
pub(crate) fn takes_method(name: &str) -> bool {
    gpu_method(name).is_some()
}

/// Writes the WGSL `acceleration(x, v, w)` of `forces` into `out`: the
/// affine sum from the uniform, then each other force's own term
/// ([`Force::write_wgsl`]) in force order, as the CPU's force field adds
/// them; n-body's sum from its rounds.
fn acceleration_into(forces: &[Box<dyn Force>], out: &mut String) -> Result<(), GpuStepError> {
    use core::fmt::Write;
    // Writing into a String cannot fail.
    let _ = out.write_str("fn acceleration(x: vec3<f32>, v: vec3<f32>, w: f32) -> vec3<f32> {\n");
    if forces.iter().any(|f| matches!(f.gpu_form(), GpuForce::NBody { .. })) {
        // Every particle's evaluation counts, an immovable one's too: its
        // trial position is written down for the others' sums.
        out.push_str("    let pull = nbody_term(x);\n");
    }
    let _ = out.write_str(
        "    if (!(w > 0.0)) {\n        return vec3<f32>(0.0);\n    }\n    var a = params.c - v * params.b;\n",
    );
    for force in forces.iter().filter(|f| f.affine_in_velocity().is_none()) {
        match force.gpu_form() {
            GpuForce::Term => {
                let _ = force.write_wgsl(out);
            }
            GpuForce::NBody { .. } => out.push_str("    a = a + pull;\n"),
            GpuForce::None | GpuForce::Affine => return Err(GpuStepError::Force { force: force.name() }),
        }
    }
    out.push_str("    return a;\n}\n");
    Ok(())
}

/// A method's step coefficients for a step of `h` seconds, `(drift,
/// kick)` as `Params` carries them: Forest-Ruth's weights times `h`, in
/// f64 then rounded, as its CPU step forms them; Adams-Bashforth's `beta`
/// in `drift`, likewise; unused (zero) for the others.
pub(super) fn coefficients(method: &str, h: f32) -> ([f32; 4], [f32; 4]) {
    let h = f64::from(h);
    match gpu_method(method).map(|m| m.coefficients) {
        Some(Coefficients::ForestRuth) => {
            let (drifts, kicks) = forest_ruth::weights();
            let kicks = [kicks[0], kicks[1], kicks[2], 0.0];
            (drifts.map(|d| (d * h) as f32), kicks.map(|k| (k * h) as f32))
        }
        Some(Coefficients::AdamsBashforth(steps)) => {
            let b = adams_bashforth::coefficients(steps).unwrap_or(&[]);
            let beta = std::array::from_fn(|j| b.get(j).map_or(0.0, |b| (b * h) as f32));
            (beta, [0.0; 4])
        }
        Some(Coefficients::None) | None => ([0.0; 4], [0.0; 4]),
    }
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
    let Some(gpu) = gpu_method(info.name) else {
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
    let affine = affine_sum(world.forces());
    plan.source.clear();
    plan.source.push_str(COMMON);
    plan.source.push('\n');
    plan.source.push_str(IN_STEP);
    plan.source.push('\n');
    acceleration_into(world.forces(), &mut plan.source)?;
    plan.source.push('\n');
    plan.source.push_str(gpu.wgsl);
    let history = gpu.history;
    // Writing into a String cannot fail.
    let _ = core::fmt::Write::write_fmt(&mut plan.source, format_args!("\nconst HISTORY: u32 = {history}u;\n"));
    let mut nbodies = world.forces().iter().filter_map(|f| match f.gpu_form() {
        GpuForce::NBody { g, softening } => Some((g, softening * softening)),
        _ => None,
    });
    let nbody = nbodies.next();
    if nbodies.next().is_some() {
        return Err(GpuStepError::Unsupported("more than one n-body force"));
    }
    // A step of a world with n-body is `stages` rounds of sums (1 without).
    let stages = if nbody.is_some() { gpu.evaluations } else { 0 };
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
        let form = collider.gpu_form();
        in_step_boxes |= collider.in_step() && matches!(form, GpuCollider::Box { .. });
        let reports = if reports { REPORTS } else { 0 } | if collider.in_step() { FINDS_IN_STEP } else { 0 };
        match form {
            GpuCollider::Box {
                min,
                max,
                inside,
                velocity,
                material,
            } => {
                let moving = velocity != glam::Vec3::ZERO;
                plan.moving |= moving;
                colliders.push(ColliderRecord {
                    kind: if inside { CONTAINER } else { SOLID },
                    axis: 0,
                    sign: 0.0,
                    offset: 0.0,
                    restitution: material.restitution,
                    friction: material.friction,
                    min: min.to_array(),
                    max: max.to_array(),
                    u: velocity.to_array(),
                    flags: if moving { MOVES } else { 0 } | reports,
                });
            }
            GpuCollider::Plane {
                normal: n,
                offset,
                speed,
                material,
            } => {
                let axis = [n.x, n.y, n.z]
                    .iter()
                    .position(|c| c.abs() == 1.0)
                    .filter(|&a| (0..3).all(|k| k == a || n[k] == 0.0))
                    .ok_or(refuse("its normal is not an axis"))?;
                let moving = speed != 0.0;
                plan.moving |= moving;
                colliders.push(ColliderRecord {
                    kind: if moving { MOVING_PLANE } else { PLANE },
                    axis: axis as u32,
                    sign: n[axis],
                    offset,
                    restitution: material.restitution,
                    friction: material.friction,
                    // A moving plane's contact is the general one, along its normal.
                    min: if moving { n.to_array() } else { [0.0; 3] },
                    max: [0.0; 3],
                    // u = n speed, as the CPU forms it (f32, lane by lane).
                    u: (glam::Vec3A::from(n) * speed).to_array(),
                    flags: if moving { MOVES } else { 0 } | reports,
                });
            }
            GpuCollider::None { reason } => return Err(refuse(reason)),
        }
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
        if pairs > world.config().max_pairs {
            return Err(GpuStepError::Pairs {
                force: force.name(),
                pairs,
                limit: world.config().max_pairs,
            });
        }
    }
    // What the colliders' loop compiles in (see `resolve_colliders`), and
    // the in-step rule's rest speed (as the CPU's `Sweep` takes it: NaN or
    // negative rests none, infinite is f32::MAX) and limit.
    let rest = world.config().rest_speed;
    let rest = if rest >= 0.0 { rest.min(f32::MAX) } else { 0.0 };
    let _ = core::fmt::Write::write_fmt(
        &mut plan.source,
        format_args!(
            "const KINEMATIC: bool = {};\nconst REPORTING: bool = {};\nconst IN_STEP: bool = {in_step};\n\
             const IN_STEP_BOXES: bool = {in_step_boxes};\n\
             fn rest_speed() -> f32 {{ return {}; }}\nconst MAX_EVENTS: u32 = {}u;\n",
            plan.moving,
            plan.reporting > 0,
            WgslF32(rest),
            crate::colliders::MAX_CONTACT_EVENTS,
        ),
    );
    plan.method = gpu.info.name;
    plan.history = history;
    plan.affine = affine;
    plan.nbody = nbody;
    plan.stages = stages;
    Ok(())
}

//! Angular integration: orientation quaternions with angular velocities, and
//! torque-free or torqued rigid bodies with a diagonal inertia tensor.
//!
//! The state of a body is its orientation `q` (a unit quaternion, body to
//! world) and its angular velocity `w` in the **world** frame, as in the
//! lecture's `dq/dt = 1/2 (0, w) q`. Angular acceleration comes from Euler's
//! equations in the body frame, with principal moments `I = (I1, I2, I3)`:
//!
//! ```text
//! w_b = q^-1 w q,   tau_b = q^-1 tau q
//! dw_b/dt = I^-1 (tau_b - w_b x (I w_b)),   dw/dt = q (dw_b/dt) q^-1
//! ```
//!
//! (`d/dt (R w_b) = R dw_b/dt` because `w x w = 0`.) The gyroscopic term
//! `w_b x (I w_b)` is what makes an asymmetric top flip about its
//! intermediate axis (the Dzhanibekov effect).
//!
//! Three methods, each in its own file: [`QuaternionEuler`] (forward Euler
//! with renormalisation, as the lecture), [`ExponentialMap`] (exact rotation
//! for the step's angular velocity, angular momentum updated exactly when
//! torque-free) and [`AngularRk4`].

pub mod exponential_map;
pub mod quaternion_euler;
pub mod rk4;

use core::fmt::Debug;
use core::ops::{Add, Mul};

pub use exponential_map::ExponentialMap;
pub use quaternion_euler::QuaternionEuler;
pub use rk4::AngularRk4;

use crate::integrator::StepError;
use crate::registry::{UnknownMethod, same_name};
use crate::vector::{Real, Vector};

/// A three-dimensional vector with the products rigid-body dynamics needs.
pub trait Vector3: Vector {
    /// Cross product.
    fn cross(self, other: Self) -> Self;
    /// Component-wise product (a diagonal matrix times a vector).
    fn scale_by(self, other: Self) -> Self;
    /// Component-wise quotient (the inverse diagonal matrix times a vector).
    fn divide_by(self, other: Self) -> Self;
}

/// A unit quaternion type: glam's `Quat` (with `Vec3`) or `DQuat` (with `DVec3`).
pub trait Rotation:
    Copy + Debug + PartialEq + Add<Output = Self> + Mul<Self, Output = Self> + Send + Sync + 'static
{
    /// The matching vector type.
    type Vector: Vector3;
    /// The identity rotation.
    const IDENTITY: Self;
    /// The pure quaternion `(0, v)`.
    fn pure(v: Self::Vector) -> Self;
    /// Scales all four components.
    fn scaled(self, s: <Self::Vector as Vector>::Real) -> Self;
    /// Euclidean norm of the four components.
    fn norm(self) -> <Self::Vector as Vector>::Real;
    /// This quaternion divided by its norm.
    fn normalized(self) -> Self;
    /// Rotates a vector (body to world).
    fn rotate(self, v: Self::Vector) -> Self::Vector;
    /// Rotates a vector by the inverse (world to body).
    fn unrotate(self, v: Self::Vector) -> Self::Vector;
    /// The exponential map: rotation by angle `|v|` about `v`.
    fn from_rotation_vector(v: Self::Vector) -> Self;
}

macro_rules! impl_rotation {
    ($q:ty, $v:ty, $r:ty) => {
        impl Vector3 for $v {
            #[inline]
            fn cross(self, other: Self) -> Self {
                <$v>::cross(self, other)
            }
            #[inline]
            fn scale_by(self, other: Self) -> Self {
                self * other
            }
            #[inline]
            fn divide_by(self, other: Self) -> Self {
                self / other
            }
        }
        impl Rotation for $q {
            type Vector = $v;
            const IDENTITY: Self = <$q>::IDENTITY;
            #[inline]
            fn pure(v: $v) -> Self {
                <$q>::from_xyzw(v.x, v.y, v.z, 0.0)
            }
            #[inline]
            fn scaled(self, s: $r) -> Self {
                self * s
            }
            #[inline]
            fn norm(self) -> $r {
                self.length()
            }
            #[inline]
            fn normalized(self) -> Self {
                self.normalize()
            }
            #[inline]
            fn rotate(self, v: $v) -> $v {
                self * v
            }
            #[inline]
            fn unrotate(self, v: $v) -> $v {
                self.conjugate() * v
            }
            #[inline]
            fn from_rotation_vector(v: $v) -> Self {
                <$q>::from_scaled_axis(v)
            }
        }
    };
}
impl_rotation!(glam::Quat, glam::Vec3, f32);
impl_rotation!(glam::DQuat, glam::DVec3, f64);

/// World-frame torques on every body: `out[i]` for orientation `q[i]` and
/// world angular velocity `w[i]` at time `t`. Any closure of that shape is
/// a torque; [`TorqueFree`] is none.
pub trait Torque<Q: Rotation> {
    /// Fills `out` with world-frame torques.
    fn torque(&mut self, t: <Q::Vector as Vector>::Real, q: &[Q], w: &[Q::Vector], out: &mut [Q::Vector]);
}

impl<Q, F> Torque<Q> for F
where
    Q: Rotation,
    F: FnMut(<Q::Vector as Vector>::Real, &[Q], &[Q::Vector], &mut [Q::Vector]),
{
    fn torque(&mut self, t: <Q::Vector as Vector>::Real, q: &[Q], w: &[Q::Vector], out: &mut [Q::Vector]) {
        self(t, q, w, out)
    }
}

/// No torque: free rotation.
#[derive(Clone, Copy, Debug, Default)]
pub struct TorqueFree;

impl<Q: Rotation> Torque<Q> for TorqueFree {
    fn torque(&mut self, _t: <Q::Vector as Vector>::Real, _q: &[Q], _w: &[Q::Vector], out: &mut [Q::Vector]) {
        out.fill(<Q::Vector as Vector>::ZERO);
    }
}

/// The bodies being stepped: orientations and world angular velocities are
/// updated in place; `inertia` holds principal moments (body frame, all > 0).
#[derive(Debug)]
pub struct Bodies<'a, Q: Rotation> {
    /// Unit quaternions, body to world.
    pub orientations: &'a mut [Q],
    /// Angular velocities in the world frame.
    pub angular_velocities: &'a mut [Q::Vector],
    /// Principal moments of inertia `(I1, I2, I3)`.
    pub inertia: &'a [Q::Vector],
}

/// What an angular method is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AngularMethodInfo {
    /// Canonical name.
    pub name: &'static str,
    /// Other accepted names.
    pub aliases: &'static [&'static str],
    /// Human-readable title.
    pub title: &'static str,
    /// Global order of orientation and angular velocity.
    pub order: u32,
    /// Torque (and Euler-equation) evaluations per step.
    pub evaluations: u32,
}

/// A time-integration method for orientations and angular velocities.
pub trait AngularIntegrator<Q: Rotation>: Send + AngularState<Q> {
    /// The method's description.
    fn info(&self) -> AngularMethodInfo;

    /// Advances the bodies from `t` to `t + dt`.
    ///
    /// # Errors
    /// [`StepError::InvalidTimeStep`] for a zero or non-finite `dt`,
    /// [`StepError::LengthMismatch`] when the slices differ in length.
    fn step(
        &mut self,
        t: <Q::Vector as Vector>::Real,
        dt: <Q::Vector as Vector>::Real,
        bodies: Bodies<'_, Q>,
        torque: &mut dyn Torque<Q>,
    ) -> Result<(), StepError>;
}

/// Every angular method.
pub const ANGULAR_METHODS: &[AngularMethodInfo] = &[quaternion_euler::INFO, exponential_map::INFO, rk4::INFO];

/// Builds an angular method by name or alias, matched by the same rule as
/// [`find`](crate::find) (case-insensitive, `-`, `_` and spaces ignored). No
/// name or alias here is also a linear method's, so `rk4` and `euler` each
/// mean one method.
///
/// # Errors
/// [`UnknownMethod`] for a name that is not in [`ANGULAR_METHODS`].
pub fn build_angular<Q: Rotation>(name: &str) -> Result<Box<dyn AngularIntegrator<Q>>, UnknownMethod> {
    let info = ANGULAR_METHODS
        .iter()
        .find(|m| same_name(name, m.name) || m.aliases.iter().any(|alias| same_name(name, alias)))
        .ok_or_else(|| UnknownMethod {
            name: name.to_owned(),
            valid: ANGULAR_METHODS.iter().map(|m| m.name).collect(),
        })?;
    Ok(match info.name {
        "quaternion_euler" => Box::new(QuaternionEuler::new()),
        "exponential_map" => Box::new(ExponentialMap::new()),
        _ => Box::new(AngularRk4::new()),
    })
}

/// World-frame angular acceleration from Euler's equations (see the module doc).
#[inline]
pub fn angular_acceleration<Q: Rotation>(q: Q, w: Q::Vector, inertia: Q::Vector, torque: Q::Vector) -> Q::Vector {
    let w_body = q.unrotate(w);
    let tau_body = q.unrotate(torque);
    let gyroscopic = w_body.cross(w_body.scale_by(inertia));
    q.rotate((tau_body - gyroscopic).divide_by(inertia))
}

/// World-frame angular momentum `R I R^T w`.
#[inline]
pub fn angular_momentum<Q: Rotation>(q: Q, w: Q::Vector, inertia: Q::Vector) -> Q::Vector {
    q.rotate(q.unrotate(w).scale_by(inertia))
}

/// Rotational kinetic energy `1/2 w_b . I w_b`.
#[inline]
pub fn rotational_energy<Q: Rotation>(q: Q, w: Q::Vector, inertia: Q::Vector) -> <Q::Vector as Vector>::Real {
    let w_body = q.unrotate(w);
    w_body.dot(w_body.scale_by(inertia)) * <<Q::Vector as Vector>::Real as Real>::from_f64(0.5)
}

/// `dq/dt = 1/2 (0, w) q`.
#[inline]
pub(crate) fn orientation_rate<Q: Rotation>(q: Q, w: Q::Vector) -> Q {
    (Q::pure(w) * q).scaled(<<Q::Vector as Vector>::Real as Real>::from_f64(0.5))
}

/// The checks every angular step makes.
pub(crate) fn check_bodies<Q: Rotation>(
    method: &'static str,
    dt: <Q::Vector as Vector>::Real,
    bodies: &Bodies<'_, Q>,
) -> Result<(), StepError> {
    if !dt.is_finite() || dt == <<Q::Vector as Vector>::Real as Real>::ZERO {
        return Err(StepError::InvalidTimeStep {
            method,
            dt: dt.to_f64(),
        });
    }
    let n = bodies.orientations.len();
    for other in [bodies.angular_velocities.len(), bodies.inertia.len()] {
        if other != n {
            return Err(StepError::LengthMismatch {
                method,
                positions: n,
                velocities: other,
            });
        }
    }
    Ok(())
}

/// Copying an angular method's whole state, for snapshots.
///
/// Implemented for every `AngularIntegrator + Clone`.
pub trait AngularState<Q: Rotation> {
    /// A boxed copy of the method and everything it remembers.
    fn clone_boxed(&self) -> Box<dyn AngularIntegrator<Q>>;

    /// The method as `Any`, so a state can be copied into a method of the same type.
    fn as_any(&self) -> &dyn core::any::Any;

    /// Overwrites this method's state with `source`'s, reusing buffers.
    /// Returns false, leaving `self` unchanged, for a different method type.
    fn copy_state_from(&mut self, source: &dyn AngularIntegrator<Q>) -> bool;
}

impl<Q: Rotation, T: AngularIntegrator<Q> + Clone + 'static> AngularState<Q> for T {
    fn clone_boxed(&self) -> Box<dyn AngularIntegrator<Q>> {
        Box::new(self.clone())
    }

    fn as_any(&self) -> &dyn core::any::Any {
        self
    }

    fn copy_state_from(&mut self, source: &dyn AngularIntegrator<Q>) -> bool {
        source
            .as_any()
            .downcast_ref::<T>()
            .map(|s| self.clone_from(s))
            .is_some()
    }
}

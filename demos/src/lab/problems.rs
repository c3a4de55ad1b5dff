//! The test problems of the lab, with exact or reference solutions.

use core::f64::consts::TAU;

use glam::DVec2;
use tickwork_integrators::math;
use tickwork_integrators::{DormandPrince, Integrator, MethodInfo, StepError, System, build};

use super::LabError;

/// A problem `x'' = a(t, x, v)` in the plane, one particle, `f64`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Problem {
    /// `x'' = -x` from `(1, 0)` to `t = 10`: positions against `cos t`.
    Harmonic,
    /// `x'' = -x - 0.5 x'` from `(1, 0)` to `t = 10`: the state against the
    /// closed form of the underdamped oscillator.
    Damped,
    /// `x'' = g - 0.1 |x'| x'` from the origin at `(10, 10)` m/s to `t = 2`:
    /// the state against a reference computed with RK4 at `2^14` steps.
    Projectile,
    /// `q'' = -q / |q|^3`, eccentricity 0.5, from perihelion to `t = 5`
    /// (most of a period of `2 pi`): positions against Kepler's equation.
    /// (Not a whole period: there symmetry makes semi-implicit Euler's
    /// position error second order.)
    Kepler,
}

impl Problem {
    /// Every problem, in the order of the report.
    pub const ALL: [Problem; 4] = [Problem::Harmonic, Problem::Damped, Problem::Projectile, Problem::Kepler];

    /// Short name, as `--problem` takes it.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Harmonic => "harmonic",
            Self::Damped => "damped",
            Self::Projectile => "projectile",
            Self::Kepler => "kepler",
        }
    }

    /// Title for plots.
    #[must_use]
    pub fn title(self) -> &'static str {
        match self {
            Self::Harmonic => "harmonic oscillator x'' = -x (position error at t = 10)",
            Self::Damped => "damped oscillator x'' = -x - 0.5 x' (state error at t = 10)",
            Self::Projectile => "projectile with quadratic drag (state error at t = 2)",
            Self::Kepler => "Kepler orbit, e = 0.5 (position error at t = 5)",
        }
    }

    /// The problem called `name`.
    ///
    /// # Errors
    /// A message listing the valid names.
    pub fn parse(name: &str) -> Result<Self, LabError> {
        Self::ALL
            .into_iter()
            .find(|p| p.name() == name)
            .ok_or_else(|| LabError::UnknownProblem {
                name: name.to_owned(),
                valid: Self::ALL.iter().map(|p| p.name()).collect(),
            })
    }

    /// Initial position and velocity.
    #[must_use]
    pub fn start(self) -> (DVec2, DVec2) {
        match self {
            Self::Harmonic | Self::Damped => (DVec2::X, DVec2::ZERO),
            Self::Projectile => (DVec2::ZERO, DVec2::new(10.0, 10.0)),
            Self::Kepler => (DVec2::new(0.5, 0.0), DVec2::new(0.0, 3f64.sqrt())),
        }
    }

    /// Length of the run, seconds.
    #[must_use]
    pub fn duration(self) -> f64 {
        match self {
            Self::Harmonic | Self::Damped => 10.0,
            Self::Projectile => 2.0,
            Self::Kepler => 5.0,
        }
    }

    /// Steps at the coarsest time step of the convergence study (halved four
    /// times) for `info`'s method. Chosen so each method's error is past its
    /// pre-asymptotic range and above round-off: on the projectile and the
    /// orbit, fourth and fifth-order one-step methods start from larger steps
    /// (from the same step their errors reach the 1e-12 floor within two
    /// halvings); Adams-Bashforth 4 does not, as its RK4 start and small
    /// stability region need the finer steps.
    #[must_use]
    pub fn coarsest_steps(self, info: &MethodInfo) -> usize {
        let order = if info.self_starting {
            self.expected_order(info)
        } else {
            0
        };
        match self {
            Self::Harmonic | Self::Damped => 100,
            Self::Projectile if order >= 4 => 20,
            Self::Projectile => 40,
            Self::Kepler if order >= 5 => 125,
            Self::Kepler if order >= 4 => 500,
            Self::Kepler => 1000,
        }
    }

    /// The order the error should show: of positions for velocity-independent
    /// forces, of the whole state under drag.
    #[must_use]
    pub fn expected_order(self, info: &MethodInfo) -> u32 {
        match self {
            Self::Harmonic | Self::Kepler => info.order,
            Self::Damped | Self::Projectile => info.order_velocity_forces,
        }
    }

    /// The exact (or reference) state at the end of the run.
    #[must_use]
    pub fn reference(self) -> (DVec2, DVec2) {
        match self {
            Self::Harmonic | Self::Damped => {
                let b: f64 = if self == Self::Damped { 0.5 } else { 0.0 };
                let zeta = b / 2.0;
                let omega = (1.0 - zeta * zeta).sqrt();
                let t = self.duration();
                let decay = math::exp(-zeta * t);
                let (a, bb) = (1.0, zeta / omega);
                let (s, c) = math::sin_cos(omega * t);
                let x = decay * (a * c + bb * s);
                let v = decay * ((bb * omega - zeta * a) * c - (a * omega + zeta * bb) * s);
                (DVec2::new(x, 0.0), DVec2::new(v, 0.0))
            }
            Self::Projectile => {
                let mut method = tickwork_integrators::Rk4::<DVec2>::default();
                let (x, v) = self.start();
                let steps = 1 << 14;
                integrate(&mut method, self, x, v, steps).map_or((DVec2::NAN, DVec2::NAN), |r| (r.0, r.1))
            }
            Self::Kepler => kepler_at(self.duration()),
        }
    }

    /// The error measure of a final state.
    #[must_use]
    pub fn error(self, x: DVec2, v: DVec2, reference: (DVec2, DVec2)) -> f64 {
        let (dx, dv) = ((x - reference.0).length(), (v - reference.1).length());
        match self {
            Self::Harmonic | Self::Kepler => dx,
            Self::Damped | Self::Projectile => dx.max(dv),
        }
    }
}

/// Position and velocity on the orbit `a = 1`, `e = 0.5`, `GM = 1`, `t`
/// after perihelion on `+x`: solve Kepler's equation `E - e sin E = t` by
/// Newton's method, then `x = cos E - e`, `y = sqrt(1 - e^2) sin E`.
fn kepler_at(t: f64) -> (DVec2, DVec2) {
    let e = 0.5;
    let mean = t.rem_euclid(TAU);
    let mut anomaly = mean;
    for _ in 0..50 {
        anomaly -= (anomaly - e * math::sin(anomaly) - mean) / (1.0 - e * math::cos(anomaly));
    }
    let (s, c) = math::sin_cos(anomaly);
    let b = (1.0 - e * e).sqrt();
    let rate = 1.0 / (1.0 - e * c);
    (DVec2::new(c - e, b * s), DVec2::new(-s * rate, b * c * rate))
}

/// The problem as the integrators' [`System`].
#[derive(Clone, Copy, Debug)]
pub struct ProblemSystem(pub Problem);

impl System<DVec2> for ProblemSystem {
    fn acceleration(&mut self, _t: f64, x: &[DVec2], v: &[DVec2], out: &mut [DVec2]) {
        for ((a, x), v) in out.iter_mut().zip(x).zip(v) {
            *a = match self.0 {
                Problem::Harmonic => -*x,
                Problem::Damped => -*x - *v * 0.5,
                Problem::Projectile => DVec2::new(0.0, -9.81) - *v * (0.1 * v.length()),
                Problem::Kepler => -*x / (x.length_squared() * x.length()),
            };
        }
    }

    fn linear_drag(&self) -> f64 {
        if self.0 == Problem::Damped { 0.5 } else { 0.0 }
    }
}

/// Builds a method for the lab: Dormand-Prince with loose tolerances, so one
/// sub-step per fixed step shows the formula's order (its tolerance would
/// otherwise hide it); every other method as the registry builds it.
///
/// # Errors
/// [`LabError::Method`], with the registry's [`UnknownMethod`](tickwork_integrators::UnknownMethod)
/// as its source, for an unknown name.
pub fn method(name: &str) -> Result<Box<dyn Integrator<DVec2>>, LabError> {
    if tickwork_integrators::find(name)?.name == "dormand_prince" {
        return Ok(Box::new(DormandPrince::with_tolerances(1.0, 1.0)));
    }
    Ok(build::<DVec2>(name)?)
}

/// Runs `steps` steps over the problem's duration; returns the final state
/// and the force evaluations spent.
///
/// # Errors
/// The method's [`StepError`].
pub fn integrate(
    method: &mut dyn Integrator<DVec2>,
    problem: Problem,
    x0: DVec2,
    v0: DVec2,
    steps: usize,
) -> Result<(DVec2, DVec2, u64), StepError> {
    let dt = problem.duration() / steps as f64;
    let (mut x, mut v) = ([x0], [v0]);
    let mut system = ProblemSystem(problem);
    let mut evaluations = 0;
    for n in 0..steps {
        let stats = method.step(n as f64 * dt, dt, &mut x, &mut v, &mut system)?;
        evaluations += u64::from(stats.evaluations);
    }
    Ok((x[0], v[0], evaluations))
}

/// Least-squares slope of `ln y` against `ln x`.
#[must_use]
pub fn log_slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (xs, ys): (Vec<f64>, Vec<f64>) = points.iter().map(|(x, y)| (math::ln(*x), math::ln(*y))).unzip();
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

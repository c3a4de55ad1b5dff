//! Energy: relative energy error over 100 Kepler orbits.

use core::f64::consts::TAU;

use glam::DVec2;
use tickwork_integrators::METHODS;

use super::LabError;
use super::problems::{Problem, ProblemSystem, method};

/// Orbits simulated.
pub const ORBITS: usize = 100;
/// Steps per orbit (dt = 2 pi / 500, about 0.0126).
pub const STEPS_PER_ORBIT: usize = 500;

/// One method's energy error history.
#[derive(Clone, Debug, PartialEq)]
pub struct EnergyHistory {
    /// The method.
    pub method: &'static str,
    /// Whether the registry calls it symplectic.
    pub symplectic: bool,
    /// `(t, largest |E - E0| / |E0| over the orbit ending at t)`, one per
    /// orbit (the envelope: the error within an orbit swings by orders of
    /// magnitude between perihelion and aphelion); stops at a failure.
    pub samples: Vec<(f64, f64)>,
    /// Largest error in the first tenth of the run.
    pub first_tenth: f64,
    /// Largest error in the last tenth of the run (infinite if the run failed).
    pub last_tenth: f64,
    /// When a step failed (implicit Euler's orbit decays into the singularity
    /// at the centre, where its solve cannot converge), the time and message.
    pub failed: Option<(f64, String)>,
}

/// What a method's energy error did over the run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// The last tenth's largest error is at most twice the first tenth's, and
    /// small: it oscillates without growing (symplectic methods).
    Bounded,
    /// It grows.
    Drifts,
    /// Above 10%: the orbit is lost (spiralled out or escaped).
    LostOrbit,
    /// A step failed.
    Failed,
}

impl EnergyHistory {
    /// The verdict on the run.
    #[must_use]
    pub fn verdict(&self) -> Verdict {
        if self.failed.is_some() {
            Verdict::Failed
        } else if self.last_tenth >= 0.1 {
            Verdict::LostOrbit
        } else if self.last_tenth <= 2.0 * self.first_tenth {
            Verdict::Bounded
        } else {
            Verdict::Drifts
        }
    }
}

fn energy(x: DVec2, v: DVec2) -> f64 {
    0.5 * v.length_squared() - 1.0 / x.length()
}

/// Runs every method over [`ORBITS`] orbits; a method whose step fails
/// keeps its history up to the failure.
///
/// # Errors
/// [`LabError::Method`] for a method that cannot be built.
pub fn study() -> Result<Vec<EnergyHistory>, LabError> {
    let (x0, v0) = Problem::Kepler.start();
    let e0 = energy(x0, v0);
    let dt = TAU / STEPS_PER_ORBIT as f64;
    let total = ORBITS * STEPS_PER_ORBIT;
    METHODS
        .iter()
        .map(|info| {
            let mut m = method(info.name)?;
            let mut system = ProblemSystem(Problem::Kepler);
            let (mut x, mut v) = ([x0], [v0]);
            let mut samples = Vec::with_capacity(ORBITS);
            let mut orbit_max = 0.0f64;
            let (mut first, mut last) = (0.0f64, 0.0f64);
            let mut failed = None;
            for n in 0..total {
                let t = n as f64 * dt;
                if let Err(e) = m.step(t, dt, &mut x, &mut v, &mut system) {
                    failed = Some((t, e.to_string()));
                    last = f64::INFINITY;
                    break;
                }
                let error = ((energy(x[0], v[0]) - e0) / e0).abs();
                if !error.is_finite() {
                    failed = Some((t + dt, "the state became non-finite".to_owned()));
                    last = f64::INFINITY;
                    break;
                }
                if n < total / 10 {
                    first = first.max(error);
                } else if n >= total - total / 10 {
                    last = last.max(error);
                }
                orbit_max = orbit_max.max(error);
                if (n + 1) % STEPS_PER_ORBIT == 0 {
                    samples.push(((n + 1) as f64 * dt, orbit_max));
                    orbit_max = 0.0;
                }
            }
            Ok(EnergyHistory {
                method: info.name,
                symplectic: info.symplectic,
                samples,
                first_tenth: first,
                last_tenth: last,
                failed,
            })
        })
        .collect()
}

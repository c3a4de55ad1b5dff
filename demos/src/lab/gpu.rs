//! The convergence study's GPU column: the projectile under quadratic drag
//! (gravity and `QuadraticDrag`, the GPU step's own forces; the orbit, an
//! `Attractor`, needs more steps than f32 round-off lets show an order
//! above one, and stays in the f64 table), one particle in f32,
//! stepped by every method the GPU step takes, on the GPU and in the CPU's
//! f32 world, at the convergence study's steps, with fitted slopes and the
//! cost (force evaluations, counted by the CPU twin: each method's WGSL
//! makes the CPU's evaluations, call for call). On an adapter that
//! computes as the CPU does (lavapipe) the two errors are the same
//! numbers; elsewhere they differ by the adapter's roundings.

use glam::{DVec2, Vec3};
use tickwork_engine::clock::FixedStep;
use tickwork_engine::forces::{Attractor, Gravity, QuadraticDrag};
use tickwork_engine::gpu_step::{GpuStepError, GpuWorld};
use tickwork_engine::render::Gpu;
use tickwork_engine::{Particle, World, WorldConfig};
use tickwork_integrators::METHODS;

use super::LabError;
use super::problems::{Problem, log_slope};

/// Errors below this are f32 round-off (positions of order 1 to 10), not
/// truncation, and are left out of the fits.
pub const F32_FLOOR: f64 = 1e-5;

/// The problems of the GPU column.
pub const PROBLEMS: [Problem; 1] = [Problem::Projectile];

/// One method on one problem, in f32, on the CPU and on the GPU.
#[derive(Clone, Debug, PartialEq)]
pub struct GpuConvergence {
    /// The problem.
    pub problem: Problem,
    /// The method's canonical name.
    pub method: &'static str,
    /// The order the registry states for this problem's error measure.
    pub stated: u32,
    /// `(dt, CPU f32 error, GPU error, force evaluations)` from the
    /// coarsest step down.
    pub points: Vec<(f64, f64, f64, u64)>,
    /// Fitted slopes over the points above [`F32_FLOOR`]: the CPU's f32
    /// world's and the GPU's (`None` with fewer than three).
    pub slopes: (Option<f64>, Option<f64>),
}

/// The problem's particle in an f32 world under `method`.
fn world(problem: Problem, method: &str) -> World {
    let mut world = World::new(WorldConfig {
        integrator: method.into(),
        ..WorldConfig::default()
    })
    .unwrap_or_else(|_| unreachable!("a registered method"));
    match problem {
        Problem::Kepler => world.add_force(Attractor {
            position: Vec3::ZERO,
            gm: 1.0,
            softening: 0.0,
        }),
        _ => {
            world.add_force(Gravity::EARTH);
            world.add_force(QuadraticDrag { coefficient: 0.1 });
        }
    }
    let (x, v) = problem.start();
    // A valid particle: finite, positive mass (the problems' starts are).
    let _ = world.spawn(Particle {
        position: Vec3::new(x.x as f32, x.y as f32, 0.0),
        velocity: Vec3::new(v.x as f32, v.y as f32, 0.0),
        ..Particle::default()
    });
    world
}

/// The particle's state as the problems measure it.
fn state(x: Vec3, v: Vec3) -> (DVec2, DVec2) {
    (
        DVec2::new(f64::from(x.x), f64::from(x.y)),
        DVec2::new(f64::from(v.x), f64::from(v.y)),
    )
}

/// Runs every method the GPU step takes on `problem` at the coarsest step
/// and four halvings, on `gpu` and on the CPU.
///
/// # Errors
/// [`LabError::Gpu`] for a GPU step that fails (not for a method the GPU
/// step does not take: those are left out).
pub fn study(gpu: &Gpu, problem: Problem) -> Result<Vec<GpuConvergence>, LabError> {
    let reference = problem.reference();
    let fail = |e: GpuStepError| LabError::Gpu(e.to_string());
    let mut runs = Vec::new();
    for info in METHODS {
        match GpuWorld::new(gpu, &world(problem, info.name)) {
            Err(GpuStepError::Method { .. }) => continue,
            Err(e) => return Err(fail(e)),
            Ok(_) => {}
        }
        let mut points = Vec::new();
        for k in 0..5 {
            let steps = problem.coarsest_steps(info) << k;
            let dt = problem.duration() / steps as f64;
            let mut cpu = world(problem, info.name);
            let mut on_gpu = GpuWorld::new(gpu, &cpu).map_err(fail)?;
            let mut evaluations = 0u64;
            let cpu_error = (0..steps as u64)
                .try_for_each(|tick| {
                    cpu.step(FixedStep {
                        tick,
                        time: tick as f64 * dt,
                        dt,
                    })
                    .map(|report| evaluations += u64::from(report.evaluations))
                })
                .map_or(f64::INFINITY, |()| {
                    let p = cpu.particles();
                    let (x, v) = (p.position.get(0), p.velocity.get(0));
                    let (x, v) = state(
                        x.unwrap_or(glam::Vec3A::NAN).into(),
                        v.unwrap_or(glam::Vec3A::NAN).into(),
                    );
                    problem.error(x, v, reference)
                });
            on_gpu
                .step(gpu, dt as f32, u32::try_from(steps).unwrap_or(u32::MAX))
                .map_err(fail)?;
            let (x, v) = on_gpu.read_back(gpu).map_err(fail)?;
            let (x, v) = state(x[0], v[0]);
            let gpu_error = problem.error(x, v, reference);
            points.push((
                dt,
                cpu_error,
                if gpu_error.is_nan() { f64::INFINITY } else { gpu_error },
                evaluations,
            ));
        }
        let fit = |pick: fn(&(f64, f64, f64, u64)) -> f64| {
            let fit: Vec<(f64, f64)> = points
                .iter()
                .filter(|p| pick(p).is_finite() && pick(p) > F32_FLOOR)
                .map(|p| (p.0, pick(p)))
                .collect();
            (fit.len() >= 3).then(|| log_slope(&fit))
        };
        let slopes = (fit(|p| p.1), fit(|p| p.2));
        runs.push(GpuConvergence {
            problem,
            method: info.name,
            stated: problem.expected_order(info),
            points,
            slopes,
        });
    }
    Ok(runs)
}

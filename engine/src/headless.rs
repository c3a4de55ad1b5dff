//! Running a world without a window: fixed steps as fast as possible, a CSV
//! trace, and a summary (what `tickwork sim` prints).

use crate::platform::Instant;
use std::io::{self, Write};

use crate::clock::{FixedClock, Rate};
use crate::step::SimulationError;
use crate::world::World;

/// Writes the state of every entity as CSV rows:
/// `step,t,entity,generation,x,y,z,vx,vy,vz,qx,qy,qz,qw,wx,wy,wz` (the orientation and
/// angular velocity columns are empty for plain particles). Numbers are
/// written in the shortest form that reads back to the same `f32`.
#[derive(Debug)]
pub struct TraceWriter<W: Write> {
    out: W,
}

impl<W: Write> TraceWriter<W> {
    /// A trace to `out`; writes the header.
    ///
    /// # Errors
    /// I/O errors of `out`.
    pub fn new(mut out: W) -> io::Result<Self> {
        writeln!(out, "step,t,entity,generation,x,y,z,vx,vy,vz,qx,qy,qz,qw,wx,wy,wz")?;
        Ok(Self { out })
    }

    /// One row per entity, in row order.
    ///
    /// # Errors
    /// I/O errors of the output.
    pub fn write(&mut self, world: &World) -> io::Result<()> {
        let p = world.particles();
        let r = world.rigid_bodies();
        for (row, entity) in world.entities().rows().iter().enumerate() {
            let (x, v) = (p.position.row(row), p.velocity.row(row));
            write!(
                self.out,
                "{},{},{},{},{},{},{},{},{},{}",
                world.tick(),
                world.time(),
                entity.index(),
                entity.generation(),
                x.x,
                x.y,
                x.z,
                v.x,
                v.y,
                v.z
            )?;
            // u32::MAX (a plain particle) is out of range: no rigid columns.
            let body = p.rigid_row[row] as usize;
            match r.orientation.get(body).zip(r.angular_velocity.get(body)) {
                Some((q, w)) => {
                    writeln!(self.out, ",{},{},{},{},{},{},{}", q.x, q.y, q.z, q.w, w.x, w.y, w.z)?;
                }
                None => writeln!(self.out, ",,,,,,,")?,
            }
        }
        Ok(())
    }

    /// Flushes and returns the output.
    ///
    /// # Errors
    /// I/O errors of the flush.
    pub fn finish(mut self) -> io::Result<W> {
        self.out.flush()?;
        Ok(self.out)
    }
}

/// What a headless run did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeadlessSummary {
    /// Steps run.
    pub steps: u64,
    /// Simulated seconds at the end.
    pub time: f64,
    /// Entities at the start and at the end, and the most at once.
    pub particles: (usize, usize, usize),
    /// Total energy at the start and at the end, joules.
    pub energy: (f64, f64),
    /// Wall-clock seconds spent stepping (tracing included).
    pub wall_seconds: f64,
    /// Sum over steps of the particles stepped.
    pub particle_steps: u64,
}

impl HeadlessSummary {
    /// `(end - start) / |start|` of the total energy; `None` when the start
    /// energy is zero (a scene that starts empty, such as a fountain).
    #[must_use]
    pub fn energy_drift(&self) -> Option<f64> {
        (self.energy.0 != 0.0).then(|| (self.energy.1 - self.energy.0) / self.energy.0.abs())
    }

    /// Particle-steps per wall-clock second.
    #[must_use]
    pub fn throughput(&self) -> f64 {
        self.particle_steps as f64 / self.wall_seconds.max(1e-9)
    }
}

/// Runs `steps` fixed steps of `rate`, writing a trace row set every `every`
/// steps (and of the initial state) when `trace` is given, and calling
/// `progress(done)` every 1% or so.
///
/// # Errors
/// The first [`SimulationError`], or an I/O error of the trace, as a message.
pub fn run_headless<W: Write>(
    world: &mut World,
    rate: Rate,
    steps: u64,
    mut trace: Option<&mut TraceWriter<W>>,
    every: u64,
    mut progress: impl FnMut(u64),
) -> Result<HeadlessSummary, HeadlessError> {
    let mut clock = FixedClock::default();
    clock.set_rate(rate);
    let start_particles = world.len();
    // Refused before it starts where a potential has too many pairs.
    let start_energy = world.energy()?.total();
    let every = every.max(1);
    if let Some(t) = trace.as_deref_mut() {
        t.write(world)?;
    }
    let started = Instant::now();
    let mut peak = start_particles;
    let mut particle_steps = 0;
    let report_every = (steps / 100).max(1);
    for done in 0..steps {
        particle_steps += world.len() as u64;
        for step in clock.step(1).fixed_steps() {
            world.step(step)?;
        }
        peak = peak.max(world.len());
        if (done + 1) % every == 0
            && let Some(t) = trace.as_deref_mut()
        {
            t.write(world)?;
        }
        if (done + 1) % report_every == 0 {
            progress(done + 1);
        }
    }
    Ok(HeadlessSummary {
        steps,
        time: clock.time(),
        particles: (start_particles, world.len(), peak),
        energy: (start_energy, world.energy()?.total()),
        wall_seconds: started.elapsed().as_secs_f64(),
        particle_steps,
    })
}

/// A headless run that stopped.
#[derive(Debug)]
pub enum HeadlessError {
    /// The simulation failed.
    Simulation(SimulationError),
    /// The trace could not be written.
    Trace(io::Error),
}

impl core::fmt::Display for HeadlessError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::Simulation(e) => e.fmt(f),
            Self::Trace(e) => write!(f, "writing the trace: {e}"),
        }
    }
}

/// `source()` is the inner error itself (the simulation's, or the file's).
impl std::error::Error for HeadlessError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Simulation(e) => Some(e),
            Self::Trace(e) => Some(e),
        }
    }
}

impl From<SimulationError> for HeadlessError {
    fn from(e: SimulationError) -> Self {
        Self::Simulation(e)
    }
}

impl From<io::Error> for HeadlessError {
    fn from(e: io::Error) -> Self {
        Self::Trace(e)
    }
}

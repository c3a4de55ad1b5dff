//! Bouncing: an elastic ball dropped onto a floor, with every method, with
//! contacts found at the end of the step and inside it.
//!
//! A ball of radius 0.05 m falls from rest (its centre) at [`HEIGHT`] onto a floor at
//! `y = 0` of restitution 1 and friction 0, under `g = 9.81` m/s^2, in the
//! engine's [`World`] at [`HZ`]. Each flight's apex is read where the ball
//! turns at the top (rising, then not), as its height plus `v_y^2 / 2g`;
//! the energy per unit mass is `g y + |v|^2 / 2`. A run ends after
//! [`BOUNCES`] apexes, when a step fails, or after [`max_steps`] steps.

use std::fmt::Write as _;

use glam::Vec3;
use tickwork_engine::clock::FixedStep;
use tickwork_engine::{
    ContactRule, EntityError, Gravity, Material, Particle, Plane, SimulationError, SpawnError, World, WorldConfig,
};
use tickwork_integrators::METHODS;

use super::{LabError, Out, plot};

/// Bounces in a run.
pub const BOUNCES: usize = 100;
/// The drop height, m.
pub const HEIGHT: f64 = 10.0;
/// Gravity, m/s^2 (the engine's is this as an `f32`).
pub const G: f64 = 9.81;
/// Steps per second.
pub const HZ: f64 = 60.0;

/// The apex figure's y range, m: lines above it leave the chart (the
/// legend and the table give every method's apex).
pub const APEX_AXIS: (f64, f64) = (7.0, 30.0);

/// The two rules, in the order of the figures and the table.
pub const RULES: [ContactRule; 2] = [ContactRule::EndOfStep, ContactRule::InStep];

/// The rule's name, as the CSV and the table give it.
#[must_use]
pub fn rule_name(rule: ContactRule) -> &'static str {
    match rule {
        ContactRule::EndOfStep => "end_of_step",
        ContactRule::InStep => "in_step",
    }
}

/// The step budget of a run: twice the steps [`BOUNCES`] exact flights from
/// [`HEIGHT`] take (each `2 sqrt(2h / g)` s, 171.3 steps at 60 Hz), 34 400.
#[must_use]
pub fn max_steps() -> usize {
    let flight = 2.0 * (2.0 * HEIGHT / G).sqrt() * HZ;
    2 * BOUNCES * flight.ceil() as usize
}

/// The energy per unit mass, `g y + |v|^2 / 2`, J/kg.
#[must_use]
pub fn energy(y: f64, v: Vec3) -> f64 {
    let v = v.as_dvec3();
    G * y + 0.5 * v.length_squared()
}

/// One flight's top.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Apex {
    /// The time the ball turned, s.
    pub t: f64,
    /// Its height plus `v_y^2 / 2g` there, m.
    pub height: f64,
    /// The energy per unit mass there, J/kg.
    pub energy: f64,
    /// The largest `|E - E0| / E0` since the last apex (or the drop): the
    /// envelope of the energy error over the flight.
    pub largest_energy_error: f64,
}

/// Why a run failed: the engine's own error, kept whole (its `source()`
/// chain and fields), or a state that became non-finite.
#[derive(Clone, Debug, PartialEq)]
pub enum Failure {
    /// The ball could not be spawned.
    Spawn(SpawnError),
    /// A step failed.
    Step(SimulationError),
    /// The ball's state could not be read back.
    Read(EntityError),
    /// The ball's position or velocity became non-finite.
    NonFinite,
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Spawn(e) => write!(f, "cannot spawn the ball: {e}"),
            Self::Step(e) => e.fmt(f),
            Self::Read(e) => write!(f, "cannot read the ball: {e}"),
            Self::NonFinite => f.write_str("the state became non-finite"),
        }
    }
}

impl std::error::Error for Failure {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Spawn(e) => Some(e),
            Self::Step(e) => Some(e),
            Self::Read(e) => Some(e),
            Self::NonFinite => None,
        }
    }
}

/// How a run ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Outcome {
    /// [`BOUNCES`] apexes.
    Completed,
    /// The step budget ran out first (the ball came to rest, or slowed).
    OutOfSteps,
    /// A step failed, or the state became non-finite: when and why.
    Failed {
        /// The step that failed.
        step: usize,
        /// Why.
        error: Failure,
    },
}

/// One method under one rule.
#[derive(Clone, Debug, PartialEq)]
pub struct BounceRun {
    /// The method.
    pub method: &'static str,
    /// Whether the registry calls it symplectic.
    pub symplectic: bool,
    /// The contact rule.
    pub rule: ContactRule,
    /// The apexes, in order (up to [`BOUNCES`]).
    pub apexes: Vec<Apex>,
    /// Steps taken.
    pub steps: usize,
    /// The energy per unit mass after the last step, J/kg.
    pub final_energy: f64,
    /// How it ended.
    pub outcome: Outcome,
}

impl BounceRun {
    /// The apex after `n` bounces (1-based), if the run got that far.
    #[must_use]
    pub fn apex(&self, n: usize) -> Option<f64> {
        n.checked_sub(1).and_then(|k| self.apexes.get(k)).map(|a| a.height)
    }

    /// `(E - E0) / E0` after the last step.
    #[must_use]
    pub fn final_energy_error(&self) -> f64 {
        let e0 = G * HEIGHT;
        (self.final_energy - e0) / e0
    }
}

/// Drops the ball with `method` under `rule`.
///
/// # Errors
/// [`LabError::Method`] for a method the registry does not know.
pub fn run(method: &'static str, symplectic: bool, rule: ContactRule) -> Result<BounceRun, LabError> {
    let mut w = World::new(WorldConfig {
        integrator: method.into(),
        ..WorldConfig::default()
    })?;
    w.add_force(Gravity {
        acceleration: Vec3::new(0.0, -G as f32, 0.0),
    });
    w.add_collider(Plane {
        material: Material {
            restitution: 1.0,
            friction: 0.0,
        },
        contact: rule,
        ..Plane::default()
    });
    let e0 = G * HEIGHT;
    let mut result = BounceRun {
        method,
        symplectic,
        rule,
        apexes: Vec::with_capacity(BOUNCES),
        steps: 0,
        final_energy: e0,
        outcome: Outcome::OutOfSteps,
    };
    let ball = match w.spawn(Particle {
        position: Vec3::new(0.0, HEIGHT as f32, 0.0),
        radius: 0.05,
        ..Particle::default()
    }) {
        Ok(ball) => ball,
        Err(e) => {
            result.outcome = Outcome::Failed {
                step: 0,
                error: Failure::Spawn(e),
            };
            return Ok(result);
        }
    };
    let dt = 1.0 / HZ;
    let mut last_vy = 0.0f32;
    let mut largest = 0.0f64;
    for n in 0..max_steps() {
        let tick = w.tick();
        let stepped = w
            .step(FixedStep {
                tick,
                time: tick as f64 * dt,
                dt,
            })
            .map_err(Failure::Step)
            .and_then(|_| {
                let x = w.position(ball).map_err(Failure::Read)?;
                let v = w.velocity(ball).map_err(Failure::Read)?;
                Ok((x, v))
            });
        result.steps = n + 1;
        let (x, v) = match stepped {
            Ok(state) if state.0.is_finite() && state.1.is_finite() => state,
            Ok(_) => {
                result.outcome = Outcome::Failed {
                    step: n + 1,
                    error: Failure::NonFinite,
                };
                break;
            }
            Err(error) => {
                result.outcome = Outcome::Failed { step: n + 1, error };
                break;
            }
        };
        let e = energy(f64::from(x.y), v);
        result.final_energy = e;
        largest = largest.max(((e - e0) / e0).abs());
        // The top: rising, then not.
        if last_vy > 0.0 && v.y <= 0.0 {
            result.apexes.push(Apex {
                t: (n + 1) as f64 * dt,
                height: f64::from(x.y) + f64::from(v.y) * f64::from(v.y) / (2.0 * G),
                energy: e,
                largest_energy_error: largest,
            });
            largest = 0.0;
            if result.apexes.len() == BOUNCES {
                result.outcome = Outcome::Completed;
                break;
            }
        }
        last_vy = v.y;
    }
    Ok(result)
}

/// Every method of the registry under each of [`RULES`]: the runs, method
/// by method in the registry's order, end-of-step before in-step.
///
/// # Errors
/// [`LabError::Method`] for a method that cannot be built.
pub fn study() -> Result<Vec<BounceRun>, LabError> {
    let mut runs = Vec::with_capacity(METHODS.len() * RULES.len());
    for info in METHODS {
        for rule in RULES {
            runs.push(run(info.name, info.symplectic, rule)?);
        }
    }
    Ok(runs)
}

/// An apex for the table: metres to 5 places, or why there is none.
fn apex_text(run: &BounceRun, n: usize) -> String {
    match (run.apex(n), &run.outcome) {
        (Some(a), _) => format!("{a:.5}"),
        (None, Outcome::Failed { step, error }) => format!("- (step {step} failed: {error})"),
        (None, _) => format!("- ({} bounces in {} steps)", run.apexes.len(), run.steps),
    }
}

/// A signed percentage, to two places or two significant figures below 0.01%.
fn percent_text(fraction: f64) -> String {
    let p = 100.0 * fraction;
    if p.abs() >= 0.01 || p == 0.0 {
        format!("{p:+.2}%")
    } else {
        format!("{p:+.1e}%")
    }
}

/// Runs the study and writes `bounce.png` (the apexes), `bounce-energy.png`
/// (the energy error), `bounce.csv` (a row per bounce of each method and
/// rule) and `bounce.md` (the table).
///
/// # Errors
/// A [`LabError`] for a method that cannot be built, an existing file
/// without `--force`, or a file or chart that cannot be written.
pub(super) fn write(out: &mut Out<'_>) -> Result<(), LabError> {
    let runs = study()?;
    let rules = RULES;
    // runs[k * 2 + r]: method k under rules[r].
    let pairs: Vec<&[BounceRun]> = runs.chunks(rules.len()).collect();
    let panel = |r: usize, f: &dyn Fn(&Apex, usize) -> (f64, f64)| -> Vec<Vec<(f64, f64)>> {
        pairs
            .iter()
            .map(|p| p[r].apexes.iter().enumerate().map(|(n, a)| f(a, n)).collect())
            .collect()
    };
    let title = |rule| match rule {
        ContactRule::EndOfStep => "contacts at the end of the step",
        ContactRule::InStep => "contacts inside the step",
    };
    let final_apex = |run: &BounceRun| run.apex(BOUNCES).map_or("-".to_owned(), |a| format!("{a:.3}"));
    let apex_legend: Vec<(String, bool)> = pairs
        .iter()
        .map(|p| {
            (
                format!("{}  {} | {}", p[0].method, final_apex(&p[0]), final_apex(&p[1])),
                p[0].symplectic,
            )
        })
        .collect();
    let apex_panels: Vec<plot::Panel> = (0..rules.len())
        .map(|r| plot::Panel {
            title: title(rules[r]).to_owned(),
            lines: panel(r, &|a, n| ((n + 1) as f64, a.height)),
        })
        .collect();
    let path = out.path("bounce.png")?;
    plot::panels(
        &path,
        &plot::Panels {
            title: &format!(
                "Bouncing: apex of an elastic ball dropped from {} m, g = {}, {} Hz, {} bounces",
                HEIGHT, G, HZ, BOUNCES
            ),
            x_label: "bounce",
            y_label: "apex, m",
            log_y: false,
            y_range: Some(APEX_AXIS),
            legend_title: &[
                "apex after 100 bounces, m:",
                "end of step | in step",
                &format!("(bold: symplectic; lines past {} m leave the chart)", APEX_AXIS.1),
            ],
            legend: &apex_legend,
            panels: &apex_panels,
        },
    )?;
    let energy_legend: Vec<(String, bool)> = pairs
        .iter()
        .map(|p| {
            (
                format!(
                    "{}  {} | {}",
                    p[0].method,
                    percent_text(p[0].final_energy_error()),
                    percent_text(p[1].final_energy_error())
                ),
                p[0].symplectic,
            )
        })
        .collect();
    let energy_panels: Vec<plot::Panel> = (0..rules.len())
        .map(|r| plot::Panel {
            title: title(rules[r]).to_owned(),
            lines: panel(r, &|a, _| (a.t, a.largest_energy_error)),
        })
        .collect();
    let path = out.path("bounce-energy.png")?;
    plot::panels(
        &path,
        &plot::Panels {
            title: "Bouncing: largest relative energy error |E - E0| / E0 over each flight, E = g y + |v|^2 / 2",
            x_label: "t, s",
            y_label: "largest |E - E0| / E0 over the flight",
            log_y: true,
            y_range: None,
            legend_title: &[
                "energy error at the end:",
                "end of step | in step",
                "(bold: symplectic)",
            ],
            legend: &energy_legend,
            panels: &energy_panels,
        },
    )?;
    let mut csv =
        String::from("method,rule,bounce,t,apex,energy_per_unit_mass,largest_relative_energy_error_over_the_flight\n");
    for run in &runs {
        for (n, a) in run.apexes.iter().enumerate() {
            let _ = writeln!(
                csv,
                "{},{},{},{},{},{},{:e}",
                run.method,
                rule_name(run.rule),
                n + 1,
                a.t,
                a.height,
                a.energy,
                a.largest_energy_error
            );
        }
    }
    let mut md = format!(
        "## Bouncing: the instant of contact\n\n![apex over {n} bounces](bounce.png)\n\n\
         ![energy error over {n} bounces](bounce-energy.png)\n\n\
         A ball of radius 0.05 m dropped from rest (its centre) at {h} m onto an elastic floor (restitution 1, friction 0) under \
         g = {g} m/s^2 at {hz} Hz, for {n} bounces, with each contact rule of the engine. \
         `ContactRule::EndOfStep` looks for contacts after the step: the ball, found below the floor, is \
         moved back onto it and its velocity reflected there. `ContactRule::InStep` finds the instant the \
         step's path meets the floor, bounces there and follows the method's path for the rest of the step; \
         where that path leaves out the acceleration (semi-implicit and implicit Euler run straight at the \
         step's end velocity), the bounce keeps the method's own energy (`y + v^2 / 2g - v dt / 2` for \
         semi-implicit Euler) rather than reflecting the velocity. The apex is read where the ball turns at the top of a flight, as y + v_y^2 / 2g; the energy error is \
         that of g y + |v|^2 / 2 against g h, at the end of the run. A run stops after {n} bounces, a failed \
         step or {max} steps.\n\n\
         | method | end of step: apex after 1 | 10 | {n} bounces, m | energy error | in step: apex after 1 | 10 | {n} bounces, m | energy error |\n\
         |---|---|---|---|---|---|---|---|---|\n",
        n = BOUNCES,
        h = HEIGHT,
        g = G,
        hz = HZ,
        max = max_steps(),
    );
    for pair in &pairs {
        let _ = write!(md, "| {} |", pair[0].method);
        for run in *pair {
            let _ = write!(
                md,
                " {} | {} | {} | {} |",
                apex_text(run, 1),
                apex_text(run, 10),
                apex_text(run, BOUNCES),
                percent_text(run.final_energy_error())
            );
        }
        md.push('\n');
    }
    out.text("bounce.csv", &csv)?;
    out.text("bounce.md", &md)?;
    out.written.markdown.push(md);
    Ok(())
}

//! The integrator lab: plots and tables that compare every method
//! (`tickwork lab convergence | energy | stability | cost | bounce | all`).
//!
//! Each study writes PNG charts, the same data as CSV, and a Markdown table;
//! `all` also writes `report.md`, which embeds the charts and tables. A
//! study that cannot finish returns a [`LabError`].

pub mod bounce;
pub mod convergence;
pub mod cost;
pub mod energy;
pub mod error;
pub mod gpu;
pub mod plot;
pub mod problems;
pub mod stability;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};
use tickwork_integrators::METHODS;

use convergence::Convergence;
pub use error::LabError;
use plot::Series;
use problems::Problem;

/// Which study to run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Study {
    /// Error against dt, log-log, with fitted slopes beside the stated orders.
    Convergence,
    /// Relative energy error over 100 Kepler orbits.
    Energy,
    /// Largest stable h omega and h b, measured and in theory.
    Stability,
    /// Error against force evaluations (work-precision).
    Cost,
    /// An elastic ball's apex and energy over 100 bounces, with contacts at
    /// the end of the step and inside it.
    Bounce,
    /// Everything, plus report.md.
    All,
}

/// Arguments of `tickwork lab`.
#[derive(Debug, Args)]
pub struct LabArgs {
    /// The study.
    #[arg(value_enum)]
    pub study: Study,
    /// Only this problem for convergence and cost: harmonic, damped, projectile, kepler (default: all).
    #[arg(long)]
    pub problem: Option<String>,
    /// Directory for the PNG, CSV and Markdown files (created if missing).
    #[arg(long, default_value = "lab")]
    pub out: PathBuf,
    /// Overwrite files of an earlier run in the directory.
    #[arg(long)]
    pub force: bool,
}

/// What a study wrote.
#[derive(Debug, Default)]
pub struct Written {
    /// Every file, in order.
    pub files: Vec<PathBuf>,
    /// Markdown sections, in order (the report's body).
    pub markdown: Vec<String>,
}

struct Out<'a> {
    dir: &'a Path,
    force: bool,
    written: Written,
}

impl Out<'_> {
    fn path(&mut self, name: &str) -> Result<PathBuf, LabError> {
        let path = self.dir.join(name);
        if path.exists() && !self.force {
            return Err(LabError::Exists(path));
        }
        self.written.files.push(path.clone());
        Ok(path)
    }

    fn text(&mut self, name: &str, text: &str) -> Result<(), LabError> {
        let path = self.path(name)?;
        std::fs::write(&path, text).map_err(|source| LabError::Write { path, source })
    }
}

/// Runs a study, writing into `args.out`; returns what was written.
///
/// # Errors
/// A [`LabError`] for an unknown problem, an existing file without
/// `--force`, a file or chart that cannot be written, or a method that
/// cannot be built.
pub fn run(args: &LabArgs) -> Result<Written, LabError> {
    let problems = match &args.problem {
        Some(name) => vec![Problem::parse(name)?],
        None => Problem::ALL.to_vec(),
    };
    if args.out.exists() && !args.out.is_dir() {
        return Err(LabError::OutIsFile(args.out.clone()));
    }
    std::fs::create_dir_all(&args.out).map_err(|source| LabError::CreateDir {
        path: args.out.clone(),
        source,
    })?;
    let mut out = Out {
        dir: &args.out,
        force: args.force,
        written: Written::default(),
    };
    let all = args.study == Study::All;
    let mut runs = Vec::new();
    if all || matches!(args.study, Study::Convergence | Study::Cost) {
        for &problem in &problems {
            runs.push(convergence::study(problem)?);
        }
    }
    if all || args.study == Study::Convergence {
        write_convergence(&mut out, &runs)?;
        write_gpu_convergence(&mut out, &problems)?;
    }
    if all || args.study == Study::Energy {
        write_energy(&mut out)?;
    }
    if all || args.study == Study::Stability {
        write_stability(&mut out)?;
    }
    if all || args.study == Study::Cost {
        write_cost(&mut out, &runs)?;
    }
    if all || args.study == Study::Bounce {
        bounce::write(&mut out)?;
    }
    if all {
        let mut report = String::from(
            "# Integrator lab\n\nEvery method of Tickwork's registry, compared. Regenerate with \
             `cargo run --release --bin tickwork -- lab all --out docs/lab --force`.\n\n",
        );
        for section in &out.written.markdown {
            report.push_str(section);
            report.push('\n');
        }
        out.text("report.md", &report)?;
    }
    Ok(out.written)
}

fn write_convergence(out: &mut Out<'_>, runs: &[Vec<Convergence>]) -> Result<(), LabError> {
    let mut csv = String::from("problem,method,dt,error,evaluations\n");
    let mut md = String::from(
        "## Convergence\n\nError against time step for every method (dt halved four times), and the \
         least-squares slope of log error against log dt beside the order the registry states \
         (of positions for the harmonic oscillator and the Kepler orbit; of the whole state under \
         drag). Errors below 1e-12 are round-off and are left out of the fits. On the projectile and \
         the orbit, Dormand-Prince's fifth-order error term is small beside the sixth at every step \
         above round-off, so its slope is above 5 there.\n\n",
    );
    for problem_runs in runs {
        let problem = problem_runs[0].problem;
        let name = format!("convergence-{}.png", problem.name());
        let series: Vec<Series> = problem_runs
            .iter()
            .map(|r| Series {
                label: format!("{} ({})", r.method, r.slope.map_or("-".into(), |s| format!("{s:.2}"))),
                points: r.points.iter().map(|p| (p.0, p.1)).collect(),
                bold: false,
            })
            .collect();
        let path = out.path(&name)?;
        plot::lines(
            &path,
            &format!("Convergence: {}", problem.title()),
            "dt",
            "error",
            true,
            &series,
        )?;
        for r in problem_runs {
            for p in &r.points {
                let _ = writeln!(csv, "{},{},{},{:e},{}", problem.name(), r.method, p.0, p.1, p.2);
            }
        }
        let _ = writeln!(
            md,
            "### {}\n\n![convergence on the {}]({name})\n",
            problem.title(),
            problem.name()
        );
    }
    let _ = write!(md, "| method |");
    for problem_runs in runs {
        let _ = write!(md, " {}: stated / fitted |", problem_runs[0].problem.name());
    }
    let _ = write!(md, "\n|---|{}\n", "---|".repeat(runs.len()));
    for (k, info) in METHODS.iter().enumerate() {
        let _ = write!(md, "| {} |", info.name);
        for problem_runs in runs {
            let r = &problem_runs[k];
            let fitted = r.slope.map_or("-".to_owned(), |s| format!("{s:.2}"));
            let _ = write!(md, " {} / {} |", r.stated, fitted);
        }
        md.push('\n');
    }
    out.text("convergence.csv", &csv)?;
    out.text("convergence.md", &md)?;
    out.written.markdown.push(md);
    Ok(())
}

/// The GPU column of the convergence study (`gpu.rs`), for the problems it
/// takes among `problems`: a table of fitted slopes, the CPU's f32 world's
/// beside the GPU's, whether their errors are the same numbers, and the
/// evaluations each needs for an error of 1e-3 and 1e-4; the points as CSV. Without an adapter the section says why (natively a
/// user's machine may have none; CI installs lavapipe, and its test fails
/// if the section is missing).
fn write_gpu_convergence(out: &mut Out<'_>, problems: &[Problem]) -> Result<(), LabError> {
    let problems: Vec<Problem> = gpu::PROBLEMS.into_iter().filter(|p| problems.contains(p)).collect();
    if problems.is_empty() {
        return Ok(());
    }
    let mut md = String::from(
        "### On the GPU\n\nThe projectile under quadratic drag (gravity and quadratic drag are the GPU \
         step's own forces), one particle in f32, stepped by every method the GPU step takes, at the \
         convergence study's steps: the fitted slope of the CPU's f32 world and of the GPU (errors below \
         1e-5 are f32 round-off, left out of the fits: `-` where fewer than three points remain, as for \
         RK4), and whether the two errors are the same numbers at every step; then the cost, as in \
         the cost tables: the force evaluations each needs to reach an error of 1e-3 and 1e-4 (f32's \
         round-off is near 1e-5), interpolated from the CPU f32 world's errors and from the GPU's \
         (the evaluations are counted by the CPU twin: each method's shader makes the CPU's \
         evaluations, call for call). (The orbit needs thousands of steps, whose f32 round-off passes \
         the truncation error of every method above first order: it stays in the f64 table.)\n\n",
    );
    let gpu = match tickwork_engine::render::Gpu::headless() {
        Ok(gpu) => gpu,
        Err(error) => {
            let _ = writeln!(md, "Not run: {error}\n");
            out.text("convergence-gpu.md", &md)?;
            out.written.markdown.push(md);
            return Ok(());
        }
    };
    let info = gpu.adapter.get_info();
    let _ = writeln!(md, "Adapter: {} ({:?}).\n", info.name, info.backend);
    let mut runs = Vec::new();
    for &problem in &problems {
        runs.push(gpu::study(&gpu, problem)?);
    }
    let mut csv = String::from("problem,method,dt,cpu_f32_error,gpu_error,evaluations\n");
    let _ = write!(md, "| method |");
    for problem_runs in &runs {
        let _ = write!(
            md,
            " {}: stated / CPU f32 / GPU | same errors | evaluations for 1e-3: CPU f32 / GPU | for 1e-4: \
             CPU f32 / GPU |",
            problem_runs[0].problem.name()
        );
    }
    let _ = write!(md, "\n|---|{}\n", "---|---|---|---|".repeat(runs.len()));
    let fitted = |s: Option<f64>| s.map_or("-".to_owned(), |s| format!("{s:.2}"));
    let cost = |r: &gpu::GpuConvergence, target: f64| {
        let of = |pick: fn(&(f64, f64, f64, u64)) -> f64| match cost::evaluations_for(
            r.points.iter().map(|p| (p.3 as f64, pick(p))),
            target,
        ) {
            Some((n, true)) => format!("at most {n:.0}"),
            Some((n, false)) => format!("{n:.0}"),
            None => "-".to_owned(),
        };
        format!("{} / {}", of(|p| p.1), of(|p| p.2))
    };
    for (k, first) in runs[0].iter().enumerate() {
        let _ = write!(md, "| {} |", first.method);
        for problem_runs in &runs {
            let r = &problem_runs[k];
            let same = r.points.iter().all(|p| p.1.to_bits() == p.2.to_bits());
            let _ = write!(
                md,
                " {} / {} / {} | {} | {} | {} |",
                r.stated,
                fitted(r.slopes.0),
                fitted(r.slopes.1),
                if same { "yes" } else { "no" },
                cost(r, 1e-3),
                cost(r, 1e-4)
            );
            for p in &r.points {
                let _ = writeln!(
                    csv,
                    "{},{},{},{:e},{:e},{}",
                    r.problem.name(),
                    r.method,
                    p.0,
                    p.1,
                    p.2,
                    p.3
                );
            }
        }
        md.push('\n');
    }
    out.text("convergence-gpu.csv", &csv)?;
    out.text("convergence-gpu.md", &md)?;
    out.written.markdown.push(md);
    Ok(())
}

fn write_energy(out: &mut Out<'_>) -> Result<(), LabError> {
    let histories = energy::study()?;
    let series: Vec<Series> = histories
        .iter()
        .map(|h| Series {
            label: format!("{}{}", h.method, if h.symplectic { " (symplectic)" } else { "" }),
            points: h.samples.clone(),
            bold: h.symplectic,
        })
        .collect();
    let path = out.path("energy.png")?;
    let title = format!(
        "Energy: relative energy error, Kepler e = 0.5, dt = 2 pi / {}, {} orbits",
        energy::STEPS_PER_ORBIT,
        energy::ORBITS
    );
    plot::lines(&path, &title, "t", "largest |E - E0| / |E0| per orbit", false, &series)?;
    let mut csv = String::from("method,t,largest_relative_energy_error_over_the_orbit\n");
    let mut md = format!(
        "## Energy\n\n![energy error over {} orbits](energy.png)\n\nThe largest relative energy error \
         in the first and the last tenth of {} Kepler orbits (e = 0.5, {} steps per orbit). Bounded: the \
         last tenth's error is at most twice the first's (and below 10%); the symplectic methods' \
         errors oscillate without growing, the others drift or lose the orbit. Implicit Euler's orbit loses energy and decays into the \
         singularity at the centre, where its solve stops converging.\n\n| method | symplectic | first tenth | last tenth | verdict |\n|---|---|---|---|---|\n",
        energy::ORBITS,
        energy::ORBITS,
        energy::STEPS_PER_ORBIT
    );
    for h in &histories {
        for (t, e) in &h.samples {
            let _ = writeln!(csv, "{},{t},{e:e}", h.method);
        }
        let _ = writeln!(
            md,
            "| {} | {} | {:.2e} | {:.2e} | {} |",
            h.method,
            if h.symplectic { "yes" } else { "-" },
            h.first_tenth,
            h.last_tenth,
            match (h.verdict(), &h.failed) {
                (_, Some((t, _))) => format!("step failed at t = {t:.1}"),
                (energy::Verdict::Bounded, _) => "bounded".to_owned(),
                (energy::Verdict::LostOrbit, _) => "lost the orbit".to_owned(),
                _ => "drifts".to_owned(),
            }
        );
    }
    out.text("energy.csv", &csv)?;
    out.text("energy.md", &md)?;
    out.written.markdown.push(md);
    Ok(())
}

fn limit_text(v: f64) -> String {
    if v == 0.0 {
        "0 (unstable for every h)".into()
    } else if v.is_infinite() {
        "infinite".into()
    } else {
        format!("{v:.4}")
    }
}

fn write_stability(out: &mut Out<'_>) -> Result<(), LabError> {
    let limits = stability::study()?;
    let mut csv = String::from("method,equation,measured,theory\n");
    let mut md = String::from(
        "## Stability\n\nThe largest stable step on the undamped oscillator `x'' = -x` (in units of \
         h omega) and on linear drag `x'' = -x'` (h b), found by bisection: stable means the \
         amplitude of the second half of a 20 000-step run exceeds the first half's by no more than \
         1e-5. 0: unstable for every step tried (from 0.001); infinite: stable up to 100. Weakly \
         unstable methods (midpoint, Heun, AB2 on the oscillator: `|g| = 1 + O(h^4)`) show small \
         positive limits where the growth stays below the threshold over the run.\n\n",
    );
    for equation in [stability::TestEquation::Oscillator, stability::TestEquation::Drag] {
        let rows: Vec<(&str, f64, Option<f64>)> = limits
            .iter()
            .filter(|l| l.equation == equation)
            .map(|l| (l.method, l.measured, l.theory))
            .collect();
        let file = match equation {
            stability::TestEquation::Oscillator => "stability-oscillator.png",
            stability::TestEquation::Drag => "stability-drag.png",
        };
        let path = out.path(file)?;
        plot::limits(
            &path,
            &format!("Stability: {}", equation.name()),
            equation.name(),
            &rows,
        )?;
        let _ = writeln!(md, "![stability, {}]({file})\n", equation.name());
    }
    md.push_str("| method | oscillator: measured | theory | linear drag: measured | theory |\n|---|---|---|---|---|\n");
    let n = METHODS.len();
    for k in 0..n {
        let (o, d) = (&limits[k], &limits[n + k]);
        let theory = |t: Option<f64>| t.map_or("-".into(), limit_text);
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} |",
            o.method,
            limit_text(o.measured),
            theory(o.theory),
            limit_text(d.measured),
            theory(d.theory)
        );
    }
    for l in &limits {
        let t = l.theory.map_or(String::new(), |t| t.to_string());
        let _ = writeln!(csv, "{},{},{},{t}", l.method, l.equation.name(), l.measured);
    }
    out.text("stability.csv", &csv)?;
    out.text("stability.md", &md)?;
    out.written.markdown.push(md);
    Ok(())
}

/// A method and the evaluations it needs for the two error targets.
type CostRow<'a> = (&'a str, Option<(f64, bool)>, Option<(f64, bool)>);

fn write_cost(out: &mut Out<'_>, runs: &[Vec<Convergence>]) -> Result<(), LabError> {
    let targets = [1e-3, 1e-6];
    let mut csv = String::from("problem,method,evaluations,error\n");
    let mut md = String::from(
        "## Cost\n\nError against force evaluations over the whole run (a work-precision diagram): \
         the lower left is better. The tables give the evaluations each method needs to reach an \
         error of 1e-3 and 1e-6 (interpolated log-log between runs; \"at most\": the coarsest run was \
         already below it; `-`: not reached at the steps tried), cheapest first: at a game's budget, pick from the top.\n\n",
    );
    for problem_runs in runs {
        let problem = problem_runs[0].problem;
        let name = format!("cost-{}.png", problem.name());
        let series: Vec<Series> = problem_runs
            .iter()
            .map(|r| Series {
                label: r.method.to_owned(),
                points: r.points.iter().map(|p| (p.2 as f64, p.1)).collect(),
                bold: false,
            })
            .collect();
        let path = out.path(&name)?;
        plot::lines(
            &path,
            &format!("Cost: {}", problem.title()),
            "force evaluations",
            "error",
            true,
            &series,
        )?;
        let _ = writeln!(
            md,
            "### {}\n\n![cost on the {}]({name})\n",
            problem.title(),
            problem.name()
        );
        let mut rows: Vec<CostRow<'_>> = problem_runs
            .iter()
            .map(|r| {
                (
                    r.method,
                    cost::evaluations_for(r.points.iter().map(|p| (p.2 as f64, p.1)), targets[0]),
                    cost::evaluations_for(r.points.iter().map(|p| (p.2 as f64, p.1)), targets[1]),
                )
            })
            .collect();
        rows.sort_by(|a, b| {
            let key = |r: &CostRow<'_>| (r.2.map_or(f64::INFINITY, |v| v.0), r.1.map_or(f64::INFINITY, |v| v.0));
            key(a).partial_cmp(&key(b)).unwrap_or(core::cmp::Ordering::Equal)
        });
        md.push_str("| method | evaluations for error 1e-3 | for 1e-6 |\n|---|---|---|\n");
        let fmt = |v: Option<(f64, bool)>| match v {
            Some((n, true)) => format!("at most {n:.0}"),
            Some((n, false)) => format!("{n:.0}"),
            None => "-".to_owned(),
        };
        for (method, a, b) in rows {
            let _ = writeln!(md, "| {method} | {} | {} |", fmt(a), fmt(b));
        }
        md.push('\n');
        for r in problem_runs {
            for p in &r.points {
                let _ = writeln!(csv, "{},{},{},{:e}", problem.name(), r.method, p.2, p.1);
            }
        }
    }
    out.text("cost.csv", &csv)?;
    out.text("cost.md", &md)?;
    out.written.markdown.push(md);
    Ok(())
}

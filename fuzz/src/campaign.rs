//! A campaign: many mutated cases from the shipped scenes, each run inside
//! `catch_unwind` under the limits, and the defects found, minimised.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;
use std::sync::Mutex;
use std::time::{Duration, Instant};

use crate::case::{Outcome, Stage, run_case};
use crate::cpu_time::process_cpu_time;
use crate::limits::{Watchdog, begin_case, peak_bytes};
use crate::minimise::minimise;
use crate::mutate::Mutator;

/// What a campaign runs.
#[derive(Clone, Debug)]
pub struct Campaign {
    /// Seed of the mutations (default: `1`).
    pub seed: u64,
    /// Cases to run (default: `2000`); the campaign also stops at `duration`.
    pub cases: u64,
    /// Wall time after which no new case starts (default: none).
    pub duration: Option<Duration>,
    /// A case still running after this is a hang (default: 60 s: a case
    /// takes milliseconds, and a loaded machine must not make one a hang).
    pub case_limit: Duration,
    /// A case whose live heap peaks past this is a defect (default: 512 MiB).
    pub memory_limit: usize,
    /// A case that uses more CPU time than this (parse, build and its
    /// steps, on all threads; see [`process_cpu_time`]) is a defect named
    /// `over budget` (default: none). For full-scale cases, where work that
    /// grows faster than the particles shows; CPU time, so a busy machine
    /// does not make a case over budget.
    pub case_budget: Option<Duration>,
    /// The texts mutated (default: none; see [`shipped_seeds`]).
    pub seeds: Vec<String>,
    /// What a case runs (default: [`run_case`], scenes; or
    /// [`run_recording_case`](crate::recording::run_recording_case)).
    pub target: fn(&str) -> Result<Outcome, String>,
}

impl Default for Campaign {
    fn default() -> Self {
        Self {
            seed: 1,
            cases: 2000,
            duration: None,
            case_limit: Duration::from_secs(60),
            memory_limit: 512 << 20,
            case_budget: None,
            seeds: Vec::new(),
            target: run_case,
        }
    }
}

/// A defect: the case, what went wrong, its text and its minimised text.
#[derive(Clone, Debug)]
pub struct Defect {
    /// The case's number in the campaign.
    pub case: u64,
    /// `panicked: ...`, `memory: ...` or the case's own defect.
    pub what: String,
    /// The mutated text.
    pub text: String,
    /// The smallest text found that shows the same kind of defect.
    pub minimised: String,
}

/// What a campaign found.
#[derive(Clone, Debug, Default)]
pub struct Report {
    /// Cases run.
    pub cases: u64,
    /// Cases refused at parse, build and step.
    pub refused: [u64; 3],
    /// Cases that stepped.
    pub stepped: u64,
    /// Defects, in the order found.
    pub defects: Vec<Defect>,
    /// The largest heap peak of a case above what was live before it, bytes.
    pub peak_bytes: usize,
}

static PANIC_MESSAGE: Mutex<Option<String>> = Mutex::new(None);

/// The `.ron` files of a directory, sorted (the shipped recordings).
///
/// # Errors
/// An unreadable directory or file.
pub fn ron_files(dir: &Path) -> std::io::Result<Vec<String>> {
    files_ending(dir, ".ron")
}

/// The texts of the files of `dir` whose names end in `suffix` (`.tmx`),
/// in name order.
///
/// # Errors
/// An unreadable directory or file.
pub fn files_ending(dir: &Path, suffix: &str) -> std::io::Result<Vec<String>> {
    let mut paths: Vec<_> = std::fs::read_dir(dir)?
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.to_str().is_some_and(|name| name.ends_with(suffix)))
        .collect();
    paths.sort();
    paths.iter().map(std::fs::read_to_string).collect()
}

/// The shipped scenes under `scenes`, plus copies of those with lattices
/// shrunk to 6 x 6 x 6 (the full lattices are past a case's particle
/// limit, so without the copies their forces and colliders would never be
/// stepped).
///
/// # Errors
/// An unreadable directory or file.
pub fn shipped_seeds(scenes: &Path) -> std::io::Result<Vec<String>> {
    let mut seeds = Vec::new();
    for text in ron_files(scenes)? {
        if text.contains("count: (") {
            seeds.push(shrink_lattices(&text));
        }
        seeds.push(text);
    }
    Ok(seeds)
}

fn shrink_lattices(text: &str) -> String {
    let mut out = String::new();
    let mut rest = text;
    while let Some(at) = rest.find("count: (") {
        let open = at + "count: (".len();
        out.push_str(&rest[..open]);
        let close = rest[open..].find(')').map_or(rest.len(), |c| open + c);
        out.push_str("6, 6, 6");
        rest = &rest[close..];
    }
    out.push_str(rest);
    out
}

/// What one case did, as the campaign sees it.
enum Verdict {
    Fine(Outcome),
    Defect(String),
}

/// What a case may use: heap and (if set) CPU time.
#[derive(Clone, Copy)]
struct Limits {
    memory: usize,
    budget: Option<Duration>,
}

/// Runs a case; also returns its heap's peak above what was live before it.
fn judge(target: fn(&str) -> Result<Outcome, String>, case: u64, text: &str, limits: Limits) -> (Verdict, usize) {
    if let Ok(mut slot) = PANIC_MESSAGE.lock() {
        *slot = None;
    }
    let base = crate::limits::live_bytes();
    begin_case(case);
    let started = process_cpu_time();
    let result = catch_unwind(AssertUnwindSafe(|| target(text)));
    let took = process_cpu_time().saturating_sub(started);
    let peak = peak_bytes().saturating_sub(base);
    let memory_limit = limits.memory;
    let verdict = match result {
        Err(_) => {
            let message = PANIC_MESSAGE.lock().ok().and_then(|m| m.clone()).unwrap_or_default();
            Verdict::Defect(format!("panicked: {message}"))
        }
        Ok(Err(defect)) => Verdict::Defect(defect),
        Ok(Ok(_)) if peak > memory_limit => Verdict::Defect(format!(
            "memory: the case's heap peaked at {peak} bytes, past the limit of {memory_limit}"
        )),
        Ok(Ok(_)) if limits.budget.is_some_and(|budget| took > budget) => Verdict::Defect(format!(
            "over budget: the case used {:.2} s of CPU time, past its budget of {:.2} s",
            took.as_secs_f64(),
            limits.budget.map_or(0.0, |b| b.as_secs_f64())
        )),
        Ok(Ok(outcome)) => Verdict::Fine(outcome),
    };
    (verdict, peak)
}

/// The kind of a defect (`panicked`, `memory`, `over budget`, or the
/// message up to its first colon), which minimising keeps.
fn kind(what: &str) -> &str {
    what.split(':').next().unwrap_or(what)
}

impl Campaign {
    /// Runs the campaign. Panics are caught, their messages kept; the
    /// panic hook is restored afterwards.
    #[must_use]
    pub fn run(&self) -> Report {
        let hook = std::panic::take_hook();
        std::panic::set_hook(Box::new(|info| {
            let location = info.location().map(|l| format!(" at {}:{}", l.file(), l.line()));
            let payload = info
                .payload()
                .downcast_ref::<&str>()
                .map(|s| (*s).to_owned())
                .or_else(|| info.payload().downcast_ref::<String>().cloned())
                .unwrap_or_default();
            if let Ok(mut slot) = PANIC_MESSAGE.lock() {
                *slot = Some(format!("{payload}{}", location.unwrap_or_default()));
            }
        }));
        let watchdog = Watchdog::start(self.case_limit);
        let mut mutator = Mutator::new(self.seed);
        let mut report = Report::default();
        let start = Instant::now();
        for case in 0..self.cases {
            if self.duration.is_some_and(|d| start.elapsed() >= d) {
                break;
            }
            let text = mutator.mutate(&self.seeds);
            watchdog.begin(case, &text);
            let limits = Limits {
                memory: self.memory_limit,
                budget: self.case_budget,
            };
            let (verdict, peak) = judge(self.target, case, &text, limits);
            report.peak_bytes = report.peak_bytes.max(peak);
            report.cases += 1;
            match verdict {
                Verdict::Fine(Outcome::Stepped) => report.stepped += 1,
                Verdict::Fine(Outcome::Refused(stage, _)) => {
                    report.refused[match stage {
                        Stage::Parse => 0,
                        Stage::Build => 1,
                        Stage::Step => 2,
                    }] += 1;
                }
                Verdict::Defect(what) => {
                    let wanted = kind(&what).to_owned();
                    // A slow case is slow to try again: fewer tries.
                    let tries = if wanted == "over budget" { 20 } else { 2000 };
                    // Each try is a case of its own to the watchdog: the
                    // minimising as a whole may take longer than one case.
                    let minimised = minimise(
                        &text,
                        &mut |t| {
                            watchdog.begin(case, t);
                            matches!(judge(self.target, case, t, limits).0, Verdict::Defect(w) if kind(&w) == wanted)
                        },
                        tries,
                    );
                    report.defects.push(Defect {
                        case,
                        what,
                        text,
                        minimised,
                    });
                }
            }
            watchdog.end();
        }
        std::panic::set_hook(hook);
        report
    }
}

impl Report {
    /// One paragraph: cases, outcomes, defects, the heap's peak.
    #[must_use]
    pub fn summary(&self) -> String {
        format!(
            "{} cases: {} refused while parsed, {} at build, {} by a step, {} stepped; {} defects; \
             largest heap {:.1} MiB",
            self.cases,
            self.refused[0],
            self.refused[1],
            self.refused[2],
            self.stepped,
            self.defects.len(),
            self.peak_bytes as f64 / f64::from(1 << 20)
        )
    }
}

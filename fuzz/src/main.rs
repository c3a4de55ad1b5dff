//! `tickwork-fuzz`: a long local fuzzing run over the shipped scenes.
//!
//! `cargo run --release -p tickwork-fuzz -- --minutes 30` runs cases until
//! the time is up; defects are printed and their minimised inputs written
//! to `--save` (default `target/fuzz-found/`), to become regression tests
//! in `fuzz/regressions/`. `--recordings assets/recordings` fuzzes the
//! input recordings instead.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use clap::Parser;
use tickwork_fuzz::campaign::{files_ending, ron_files, shipped_seeds};
use tickwork_fuzz::{Campaign, LimitedAlloc, run_case, run_map_case, run_recording_case};

#[global_allocator]
static ALLOC: LimitedAlloc = LimitedAlloc;

/// Fuzz the scene parser, builder and step with mutated shipped scenes.
#[derive(Debug, Parser)]
#[command(name = "tickwork-fuzz")]
struct Args {
    /// Minutes to run (default: until --cases are done).
    #[arg(long, allow_hyphen_values = true)]
    minutes: Option<f64>,
    /// Most cases to run.
    #[arg(long, default_value_t = u64::MAX)]
    cases: u64,
    /// Seed of the mutations (a run is reproducible from it).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Directory for the minimised inputs of defects.
    #[arg(long, default_value = "target/fuzz-found")]
    save: PathBuf,
    /// The scenes to mutate.
    #[arg(long, default_value = "assets/scenes")]
    scenes: PathBuf,
    /// Fuzz the input recordings of this directory (replayed by the lander)
    /// instead of the scenes.
    #[arg(long)]
    recordings: Option<PathBuf>,
    /// Fuzz the Tiled maps (`.tmx`) of this directory (read, built and
    /// stepped) instead of the scenes.
    #[arg(long)]
    maps: Option<PathBuf>,
}

fn main() -> ExitCode {
    let args = Args::parse();
    let duration = match args.minutes {
        Some(m) => match Duration::try_from_secs_f64(m * 60.0) {
            Ok(d) if !d.is_zero() => Some(d),
            _ => {
                eprintln!("error: --minutes: {m} is not a positive, finite number of minutes");
                return ExitCode::from(2);
            }
        },
        None => None,
    };
    if duration.is_none() && args.cases == u64::MAX {
        eprintln!("error: give --minutes or --cases");
        return ExitCode::from(2);
    }
    let (dir, seeds, target) = match (&args.recordings, &args.maps) {
        (Some(dir), _) => (dir, ron_files(dir), run_recording_case as fn(&str) -> _),
        (None, Some(dir)) => (dir, files_ending(dir, ".tmx"), run_map_case as fn(&str) -> _),
        (None, None) => (&args.scenes, shipped_seeds(&args.scenes), run_case as fn(&str) -> _),
    };
    let seeds = match seeds {
        Ok(seeds) if !seeds.is_empty() => seeds,
        Ok(_) => {
            eprintln!("error: {}: no .ron files", dir.display());
            return ExitCode::FAILURE;
        }
        Err(e) => {
            eprintln!("error: {}: {e}", dir.display());
            return ExitCode::FAILURE;
        }
    };
    // 8 GiB of live heap is past anything a case may need: refused, the
    // case named, the process aborted.
    tickwork_fuzz::limits::set_hard_limit(8 << 30);
    let campaign = Campaign {
        seed: args.seed,
        cases: args.cases,
        duration,
        seeds,
        target,
        ..Campaign::default()
    };
    let report = campaign.run();
    println!("{}", report.summary());
    if report.defects.is_empty() {
        return ExitCode::SUCCESS;
    }
    if let Err(e) = std::fs::create_dir_all(&args.save) {
        eprintln!("error: {}: {e}", args.save.display());
    }
    for defect in &report.defects {
        let path = args.save.join(format!("seed{}-case{}.ron", args.seed, defect.case));
        if path.exists() {
            println!(
                "case {}: {}\n  already saved: {}",
                defect.case,
                defect.what,
                path.display()
            );
            continue;
        }
        let text = format!("// expect: FILL IN\n// found: {}\n{}\n", defect.what, defect.minimised);
        match std::fs::write(&path, text) {
            Ok(()) => println!("case {}: {}\n  minimised: {}", defect.case, defect.what, path.display()),
            Err(e) => eprintln!("error: {}: {e}", path.display()),
        }
    }
    ExitCode::FAILURE
}

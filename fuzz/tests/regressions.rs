//! Every input in `fuzz/regressions/` (minimised from a bug the fuzzer or
//! a hostile user found) must now have the outcome its header states:
//! `// expect: stepped`, or `// expect: <parse|build|step> <text>` for a
//! refusal at that stage whose message contains the text. An input marked
//! `// scale: full` runs as a full-scale case (the world may hold
//! 250 000 particles), within the full-scale campaign's time budget.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;

use std::time::Duration;

use tickwork_fuzz::{Outcome, Stage, process_cpu_time, run_case, run_full_scale_case};

/// A full-scale input's budget of CPU time: the full-scale campaign's (a
/// 100 000-grain crowd parses, builds and steps four times in a few tenths
/// of a second on CI's two cores; quadratic work takes minutes).
const FULL_SCALE_BUDGET: Duration = Duration::from_secs(2);

#[test]
fn every_regression_input_has_the_outcome_it_states() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("regressions");
    let mut paths: Vec<_> = std::fs::read_dir(&dir)
        .expect("the regressions directory")
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "ron"))
        .collect();
    paths.sort();
    assert!(paths.len() >= 20, "the regression inputs are there: {}", paths.len());
    let mut wrong = Vec::new();
    for path in &paths {
        let text = std::fs::read_to_string(path).expect("readable");
        let name = path
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into());
        let Some(expect) = text.lines().find_map(|l| l.strip_prefix("// expect: ")) else {
            wrong.push(format!("{name}: no `// expect:` line"));
            continue;
        };
        let (stage, contains) = expect.split_once(' ').unwrap_or((expect, ""));
        let full_scale = text.lines().any(|l| l.trim() == "// scale: full");
        let started = process_cpu_time();
        let run = || {
            if full_scale {
                run_full_scale_case(&text)
            } else {
                run_case(&text)
            }
        };
        let result = catch_unwind(AssertUnwindSafe(run));
        let took = process_cpu_time().saturating_sub(started);
        if full_scale && took > FULL_SCALE_BUDGET {
            wrong.push(format!(
                "{name}: over budget: used {:.2} s of CPU time, past {:.2} s",
                took.as_secs_f64(),
                FULL_SCALE_BUDGET.as_secs_f64()
            ));
        }
        let outcome = match result {
            Ok(Ok(outcome)) => outcome,
            Ok(Err(defect)) => {
                wrong.push(format!("{name}: {defect}"));
                continue;
            }
            Err(_) => {
                wrong.push(format!("{name}: panicked"));
                continue;
            }
        };
        let fine = match (stage, &outcome) {
            ("stepped", Outcome::Stepped) => true,
            ("parse", Outcome::Refused(Stage::Parse, m))
            | ("build", Outcome::Refused(Stage::Build, m))
            | ("step", Outcome::Refused(Stage::Step, m)) => m.contains(contains),
            _ => false,
        };
        if !fine {
            wrong.push(format!("{name}: expected {expect:?}, got {outcome:?}"));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

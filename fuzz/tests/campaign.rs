//! The bounded campaign CI runs: a fixed seed, a fixed number of cases
//! (about 15 s on CI's two cores), failing on any panic, hang or
//! case whose heap passes the limit, and showing each minimised input.

use std::path::Path;

use tickwork_fuzz::campaign::shipped_seeds;
use tickwork_fuzz::{Campaign, LimitedAlloc};

#[global_allocator]
static ALLOC: LimitedAlloc = LimitedAlloc;

/// Fails with every defect's case, what went wrong and its minimised input.
fn assert_no_defect(report: &tickwork_fuzz::Report) {
    println!("{}", report.summary());
    let defects: Vec<String> = report
        .defects
        .iter()
        .map(|d| format!("case {}: {}\nminimised:\n{}", d.case, d.what, d.minimised))
        .collect();
    assert!(defects.is_empty(), "{}", defects.join("\n\n"));
}

/// Campaigns share the panic hook and the allocator's counters.
static ONE_CAMPAIGN: std::sync::Mutex<()> = std::sync::Mutex::new(());

#[test]
fn a_fixed_seed_campaign_over_every_shipped_scene_finds_no_defect() {
    let _one_at_a_time = ONE_CAMPAIGN.lock();
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/scenes");
    let seeds = shipped_seeds(&scenes).expect("the shipped scenes");
    assert!(seeds.len() >= 8, "every shipped scene is a seed: {}", seeds.len());
    tickwork_fuzz::limits::set_hard_limit(4 << 30);
    let report = Campaign {
        seed: 20261201,
        cases: 20_000,
        seeds,
        ..Campaign::default()
    }
    .run();
    assert_no_defect(&report);
    assert_eq!(report.cases, 20_000);
    // The mutations reach every stage: a campaign refused only by the
    // parser would test nothing past it.
    assert!(report.refused.iter().all(|&n| n > 0), "{}", report.summary());
    assert!(report.stepped > 0, "{}", report.summary());
}

#[test]
fn a_fixed_seed_full_scale_campaign_over_the_shipped_scenes_finds_no_defect() {
    // The shipped scenes as they ship (100 000 particles), mutated: work
    // that grows faster than the particles (n-body, a sphere grid gone
    // coarse) shows only here, as a case over its budget, named.
    let _one_at_a_time = ONE_CAMPAIGN.lock();
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/scenes");
    let seeds = tickwork_fuzz::campaign::ron_files(&scenes).expect("the shipped scenes");
    assert!(
        seeds.iter().any(|s| s.contains("count: (100, 10, 100)")),
        "a 100 000-particle scene is among the seeds"
    );
    tickwork_fuzz::limits::set_hard_limit(4 << 30);
    let report = Campaign {
        seed: 20261204,
        cases: 600,
        seeds,
        target: tickwork_fuzz::run_full_scale_case,
        case_budget: Some(std::time::Duration::from_secs(2)),
        ..Campaign::default()
    }
    .run();
    assert_no_defect(&report);
    assert_eq!(report.cases, 600);
    assert!(report.stepped > 0, "{}", report.summary());
}

#[test]
fn a_fixed_seed_campaign_over_the_shipped_recordings_finds_no_defect() {
    // In the same process as the scene campaign, but not at the same time:
    // the panic hook and the allocator's counters are the process's.
    let _one_at_a_time = ONE_CAMPAIGN.lock();
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/recordings");
    let seeds = tickwork_fuzz::campaign::ron_files(&dir).expect("the shipped recordings");
    assert!(!seeds.is_empty(), "a shipped recording");
    let report = Campaign {
        seed: 20261202,
        cases: 1_500,
        seeds,
        target: tickwork_fuzz::run_recording_case,
        ..Campaign::default()
    }
    .run();
    assert_no_defect(&report);
    assert!(report.refused[0] > 0 && report.stepped > 0, "{}", report.summary());
}

#[test]
fn a_fixed_seed_campaign_over_the_shipped_map_finds_no_defect() {
    let _one_at_a_time = ONE_CAMPAIGN.lock();
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/maps");
    let seeds = tickwork_fuzz::campaign::files_ending(&dir, ".tmx").expect("the shipped level");
    assert!(!seeds.is_empty(), "a shipped map");
    let report = Campaign {
        seed: 20261207,
        cases: 1_500,
        seeds,
        target: tickwork_fuzz::run_map_case,
        ..Campaign::default()
    }
    .run();
    assert_no_defect(&report);
    // The mutations reach the reader's refusals and worlds that step.
    assert!(report.refused[0] > 0 && report.stepped > 0, "{}", report.summary());
}

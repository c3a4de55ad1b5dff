//! The bounded campaign CI runs: a fixed seed, a fixed number of cases
//! (about 15 s on CI's two cores), failing on any panic, hang or
//! case whose heap passes the limit, and showing each minimised input.

use std::path::Path;

use tickwork_fuzz::campaign::shipped_seeds;
use tickwork_fuzz::{Campaign, LimitedAlloc};

#[global_allocator]
static ALLOC: LimitedAlloc = LimitedAlloc;

#[test]
fn a_fixed_seed_campaign_over_every_shipped_scene_finds_no_defect() {
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
    println!("{}", report.summary());
    let defects: Vec<String> = report
        .defects
        .iter()
        .map(|d| format!("case {}: {}\nminimised:\n{}", d.case, d.what, d.minimised))
        .collect();
    assert!(defects.is_empty(), "{}", defects.join("\n\n"));
    assert_eq!(report.cases, 20_000);
    // The mutations reach every stage: a campaign refused only by the
    // parser would test nothing past it.
    assert!(report.refused.iter().all(|&n| n > 0), "{}", report.summary());
    assert!(report.stepped > 0, "{}", report.summary());
}

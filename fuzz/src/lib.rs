//! The scene fuzzer, on stable Rust: shipped scenes mutated (tokens, bytes,
//! special numbers, misspelt and duplicated fields, deep nesting, long
//! strings), each parsed, built and stepped inside `catch_unwind`, under an
//! allocation limit and a hang watchdog; and the shipped input recordings,
//! mutated the same way, parsed and replayed by their game; and the shipped
//! Tiled level, mutated, read as a map and made into a stepping world.
//!
//! CI runs a bounded campaign (a fixed seed, `tests/campaign.rs`), and a
//! full-scale one over the shipped 100 000-particle scenes where a case
//! over its budget of CPU time is a defect (quadratic work shows only at scale); a long
//! run is `cargo run --release -p tickwork-fuzz -- --minutes 30`. Inputs that
//! found bugs, minimised, live in `fuzz/regressions/` with the outcome each
//! must now have (`tests/regressions.rs`).

pub mod campaign;
pub mod case;
pub mod cpu_time;
pub mod limits;
pub mod map;
pub mod minimise;
pub mod mutate;
pub mod recording;

pub use campaign::{Campaign, Defect, Report};
pub use case::{Outcome, Stage, run_case, run_full_scale_case};
pub use cpu_time::process_cpu_time;
pub use limits::LimitedAlloc;
pub use map::run_map_case;
pub use mutate::Mutator;
pub use recording::run_recording_case;

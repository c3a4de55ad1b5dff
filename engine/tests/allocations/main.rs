//! Steady-state steps allocate nothing, counted on the stepping thread:
//! one test binary with a counting global allocator
//! (`tests/support/counting_alloc.rs`), apart from the engine's other
//! tests, whose allocations it would count. (Every thread's allocations,
//! rayon's included, are counted in `tests/allocations_on_every_thread.rs`.)

#[path = "../../../tests/support/counting_alloc.rs"]
mod counting;

#[global_allocator]
static GLOBAL: counting::Counting = counting::Counting;

mod steps;

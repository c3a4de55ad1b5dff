//! The threads a parallel step runs on.
//!
//! A step of more than [`WorldConfig::parallel_threshold`](crate::WorldConfig)
//! particles spreads its lanes over rayon's global pool. Sent from a thread
//! outside the pool, each step's job goes through the pool's injector queue,
//! which allocates a block (about 1.5 KB) every 63 jobs: a steady-state
//! allocation, if a small one. Sent from one of the pool's own threads, it
//! goes to that thread's deque, whose buffer is reused: nothing is
//! allocated. So the thread that steps joins the pool as its thread 0.

/// Makes the calling thread (the one that will step worlds) thread 0 of
/// rayon's global pool, of as many threads as the machine has cores. Call it
/// once, first thing, before anything uses rayon; [`run`](crate::app::run)
/// and the `tickwork` command line do.
///
/// # Errors
/// rayon's, when the global pool exists already (something used rayon
/// first): steps still run in parallel, each then sending its job through
/// the pool's injector.
pub fn join_thread_pool() -> Result<(), rayon::ThreadPoolBuildError> {
    rayon::ThreadPoolBuilder::new().use_current_thread().build_global()
}

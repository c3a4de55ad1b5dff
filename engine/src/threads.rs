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
    // Thread 0 runs jobs only while it waits inside rayon itself: a pool of
    // one (one core, or RAYON_NUM_THREADS=1, read as rayon reads it) would
    // leave work sent from any other thread to no one. Then the default
    // pool, and no parallel lanes.
    // One in the browser, which has no threads (rayon then runs every job
    // on the calling thread).
    let threads = crate::platform::parallel_threads();
    if threads < 2 {
        return Ok(());
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .use_current_thread()
        .build_global()?;
    // Every thread runs one job now, so the per-thread state its first
    // steal allocates (crossbeam's epoch handle) is not allocated by a
    // step later, whenever a loaded machine first lets that thread steal.
    rayon::broadcast(|_| ());
    Ok(())
}

/// The rows of one rayon job in the passes over whole columns of a
/// parallel step (gathers and scatters between blocks and rows, the
/// finiteness check, pointwise colliders on rows, the sphere grid's
/// passes): pieces of this many (the last takes what is left), or at
/// least this many where rayon splits an iterator itself. 4 096 rows, 64 KB
/// of one `Vec3A` column: enough work that handing it to another thread
/// pays.
pub(crate) const ROWS_PER_JOB: usize = 4_096;

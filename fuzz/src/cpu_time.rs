//! The process's CPU time, which a case's budget is measured in: a machine
//! busy with other work (a build, other tests) slows a case's wall time but
//! not the work it does, so only work that grows too fast (quadratic at
//! full scale) makes a case over budget. It counts every thread of the
//! process, so a parallel step's work on rayon's threads counts too.

use std::time::Duration;

/// The CPU time this process has used so far, on all of its threads.
#[cfg(unix)]
#[must_use]
pub fn process_cpu_time() -> Duration {
    let mut t = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: `t` is a valid, writable timespec, and the clock id is one
    // POSIX defines; the call writes only `t`.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut t) };
    if rc != 0 {
        return Duration::ZERO;
    }
    Duration::new(
        u64::try_from(t.tv_sec).unwrap_or(0),
        u32::try_from(t.tv_nsec).unwrap_or(0),
    )
}

/// Elsewhere the wall time since the first call: an upper bound on the
/// CPU time of a single-threaded case (the fuzzer runs on CI's Linux).
#[cfg(not(unix))]
#[must_use]
pub fn process_cpu_time() -> Duration {
    static START: std::sync::OnceLock<std::time::Instant> = std::sync::OnceLock::new();
    START.get_or_init(std::time::Instant::now).elapsed()
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;

    /// This thread's CPU time alone (other tests run beside this one, in
    /// the same process, and add to the process's).
    fn thread_cpu_time() -> Duration {
        let mut t = libc::timespec { tv_sec: 0, tv_nsec: 0 };
        // SAFETY: as in `process_cpu_time`.
        let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut t) };
        assert_eq!(rc, 0, "the thread's clock");
        Duration::new(t.tv_sec as u64, t.tv_nsec as u32)
    }

    #[test]
    fn work_on_every_thread_of_the_process_counts() {
        let spin = || {
            let mut x = 1u64;
            for k in 0..20_000_000u64 {
                x = std::hint::black_box(x.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(k));
            }
            x
        };
        let before = thread_cpu_time();
        std::hint::black_box(spin());
        let one = thread_cpu_time() - before;
        assert!(one > Duration::ZERO, "a busy loop used CPU time");
        let before = process_cpu_time();
        std::thread::scope(|s| {
            let handles: Vec<_> = (0..2).map(|_| s.spawn(spin)).collect();
            for h in handles {
                std::hint::black_box(h.join().expect("no panic"));
            }
        });
        let two = process_cpu_time() - before;
        // Two other threads' loops count twice, however they were
        // scheduled (a loaded machine stretches the wall time, not this).
        assert!(
            two > one + one / 2,
            "two threads' work counts: {two:?} after {one:?} for one"
        );
    }
}

//! What keeps a campaign from taking the machine: an allocator that counts
//! live bytes (a case's peak is reported against a soft limit, and an
//! allocation past the hard limit is refused, which aborts the process with
//! the case named) and a watchdog that names a case that never ends.

use std::alloc::{GlobalAlloc, Layout, System};
use std::io::Write;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError, Sender};
use std::sync::{Arc, Mutex};
use std::time::Duration;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);
static HARD_LIMIT: AtomicUsize = AtomicUsize::new(usize::MAX);
static CASE: AtomicU64 = AtomicU64::new(0);

/// The system allocator, counting live bytes. Install it in the binary or
/// test that runs a campaign:
/// `#[global_allocator] static ALLOC: LimitedAlloc = LimitedAlloc;`.
#[derive(Debug)]
pub struct LimitedAlloc;

// SAFETY: every call is forwarded to `System` unchanged, or refused with a
// null pointer (which `GlobalAlloc` allows); the counters are atomics.
unsafe impl GlobalAlloc for LimitedAlloc {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if !reserve(layout.size()) {
            return core::ptr::null_mut();
        }
        // SAFETY: forwarded with the caller's layout.
        let p = unsafe { System.alloc(layout) };
        if p.is_null() {
            LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        }
        p
    }

    unsafe fn dealloc(&self, p: *mut u8, layout: Layout) {
        // SAFETY: `p` was allocated by `System` with `layout`.
        unsafe { System.dealloc(p, layout) };
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
    }

    unsafe fn realloc(&self, p: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let old = layout.size();
        if new_size > old && !reserve(new_size - old) {
            return core::ptr::null_mut();
        }
        // SAFETY: forwarded with the caller's pointer, layout and size.
        let q = unsafe { System.realloc(p, layout, new_size) };
        if q.is_null() {
            if new_size > old {
                LIVE.fetch_sub(new_size - old, Ordering::Relaxed);
            }
        } else if new_size < old {
            LIVE.fetch_sub(old - new_size, Ordering::Relaxed);
        }
        q
    }
}

/// Counts `bytes` more as live, unless that passes the hard limit (then
/// says so on standard error, without allocating, and refuses).
fn reserve(bytes: usize) -> bool {
    let live = LIVE.fetch_add(bytes, Ordering::Relaxed) + bytes;
    if live > HARD_LIMIT.load(Ordering::Relaxed) {
        LIVE.fetch_sub(bytes, Ordering::Relaxed);
        let mut message = [0u8; 96];
        let mut cursor = std::io::Cursor::new(&mut message[..]);
        let _ = writeln!(
            cursor,
            "tickwork-fuzz: case {} asked for {} bytes past the hard limit",
            CASE.load(Ordering::Relaxed),
            bytes
        );
        let written = cursor.position() as usize;
        let _ = std::io::stderr().write_all(&message[..written]);
        return false;
    }
    PEAK.fetch_max(live, Ordering::Relaxed);
    true
}

/// Sets the hard limit of live bytes (the whole process's).
pub fn set_hard_limit(bytes: usize) {
    HARD_LIMIT.store(bytes, Ordering::Relaxed);
}

/// Live bytes now.
#[must_use]
pub fn live_bytes() -> usize {
    LIVE.load(Ordering::Relaxed)
}

/// Starts measuring a case's peak from the bytes live now; `case` is named
/// if an allocation is refused.
pub fn begin_case(case: u64) {
    CASE.store(case, Ordering::Relaxed);
    PEAK.store(LIVE.load(Ordering::Relaxed), Ordering::Relaxed);
}

/// The peak of live bytes since [`begin_case`].
#[must_use]
pub fn peak_bytes() -> usize {
    PEAK.load(Ordering::Relaxed)
}

/// A thread that aborts the process, naming the case and its text, when a
/// case has not ended `limit` after it began: a hang would otherwise stall
/// CI until its own timeout, with nothing said. It waits on the campaign's
/// messages, so a case ending is what it wakes on.
#[derive(Debug)]
pub struct Watchdog {
    started: Sender<Option<u64>>,
    text: Arc<Mutex<String>>,
}

impl Watchdog {
    /// Starts the watchdog with a per-case `limit`.
    #[must_use]
    pub fn start(limit: Duration) -> Self {
        let (started, cases) = mpsc::channel::<Option<u64>>();
        let text = Arc::new(Mutex::new(String::new()));
        let shared = Arc::clone(&text);
        std::thread::spawn(move || {
            let mut current = None;
            loop {
                let message = match current {
                    // A case is running: wait for the next message, or time out.
                    Some(case) => match cases.recv_timeout(limit) {
                        Ok(message) => message,
                        Err(RecvTimeoutError::Timeout) => {
                            let text = shared.lock().map(|t| t.clone()).unwrap_or_default();
                            eprintln!(
                                "tickwork-fuzz: case {case} ran past the limit of {} s (a hang); its text:\n{text}",
                                limit.as_secs_f64()
                            );
                            std::process::abort();
                        }
                        Err(RecvTimeoutError::Disconnected) => return,
                    },
                    None => match cases.recv() {
                        Ok(message) => message,
                        Err(_) => return,
                    },
                };
                current = message;
            }
        });
        Self { started, text }
    }

    /// A case begins.
    pub fn begin(&self, case: u64, text: &str) {
        if let Ok(mut shared) = self.text.lock() {
            shared.clear();
            shared.push_str(text);
        }
        let _ = self.started.send(Some(case));
    }

    /// The case ended.
    pub fn end(&self) {
        let _ = self.started.send(None);
    }
}

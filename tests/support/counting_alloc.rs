//! A counting global allocator for the tests that check a steady step
//! allocates nothing, shared by the crates' allocation test binaries
//! (`#[path]`-included: each binary installs it with
//! `#[global_allocator] static GLOBAL: Counting = Counting;`).
//!
//! It counts allocations and reallocations twice: on the allocating thread
//! ([`this_thread`]), for tests that may run beside others, and for the
//! whole process ([`process`]), for a test that steps on rayon's threads
//! too, alone in its binary so that nothing else allocates meanwhile.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicUsize, Ordering};

/// The allocator: the system's, counted.
pub struct Counting;

thread_local! {
    static THIS_THREAD: Cell<usize> = const { Cell::new(0) };
}

static PROCESS: AtomicUsize = AtomicUsize::new(0);

fn count() {
    THIS_THREAD.with(|count| count.set(count.get() + 1));
    PROCESS.fetch_add(1, Ordering::Relaxed);
}

// SAFETY: forwards to the system allocator; the counters are a
// thread-local cell and an atomic.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

/// Allocations made on this thread so far.
#[allow(dead_code)] // not every binary counts both ways
pub fn this_thread() -> usize {
    THIS_THREAD.with(Cell::get)
}

/// Allocations made on any thread so far.
#[allow(dead_code)] // not every binary counts both ways
pub fn process() -> usize {
    PROCESS.load(Ordering::Relaxed)
}

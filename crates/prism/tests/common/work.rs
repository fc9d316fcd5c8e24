//! Bounding a parser's work without a clock: an allocator that counts the bytes each thread
//! allocates, so a test can assert that refusing a hostile file cost little memory, or that
//! a damaged file cost no more than a constant times its size. Unlike a time limit, the
//! count does not depend on the machine or its load, so such a test cannot flake.
//!
//! A test binary opts in with `#[global_allocator] static COUNTING: Counting = Counting;`
//! (prism-io's tests/suites.rs does, for all its suites).

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

thread_local! {
    static ALLOCATED: Cell<usize> = const { Cell::new(0) };
}

fn count(bytes: usize) {
    // `try_with`: allocations while a thread is being torn down are not counted.
    let _ = ALLOCATED.try_with(|a| a.set(a.get().saturating_add(bytes)));
}

/// The system allocator, counting every byte requested per thread (a reallocation counts
/// its new size, the bytes that may be touched).
pub(crate) struct Counting;

#[allow(unsafe_code)] // a global allocator cannot be written without it
                      // SAFETY: every method forwards to `System` with the caller's arguments unchanged; the
                      // counting touches only a const-initialised thread-local `Cell`, which never allocates.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count(layout.size());
        // SAFETY: forwarded as received (see above).
        unsafe { System.alloc(layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        count(layout.size());
        // SAFETY: forwarded as received.
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count(new_size);
        // SAFETY: forwarded as received.
        unsafe { System.realloc(ptr, layout, new_size) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: forwarded as received.
        unsafe { System.dealloc(ptr, layout) }
    }
}

/// Runs `f` on this thread and returns its result with the bytes it allocated (only
/// meaningful in a test binary that installed `Counting`).
pub(crate) fn allocated_by<T>(f: impl FnOnce() -> T) -> (T, usize) {
    let before = ALLOCATED.with(Cell::get);
    let result = f();
    (result, ALLOCATED.with(Cell::get) - before)
}

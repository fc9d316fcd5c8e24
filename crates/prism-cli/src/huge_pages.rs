//! The process's allocator: the system's, and on request (`PRISM_HUGE_PAGES=1` in the
//! environment) every block of 4 MiB or more advised to the kernel as transparent huge
//! pages (`madvise(MADV_HUGEPAGE)`), as Embree's allocator does for its blocks. Where the
//! kernel gives huge pages only on request (Debian's default, `madvise`), a large scene's
//! BVH build otherwise faults in its arrays 4 KiB at a time: on a Zen 4 machine the hint
//! made builds 7-13 % faster (docs/journal/performance.md, the tenth step). It is off by default
//! because on a virtual machine whose host backs a guest's huge pages on first touch, a
//! huge page can take a millisecond or more to fault in: on the Xeon VM of the sixteenth
//! step, half of eight 1080p renders ran 1.5-1.7x slower with it and a million-triangle
//! build once 2.8x slower, SPD renders were level in medians of three, and builds gained
//! nothing. The advice changes
//! how memory is backed, never what it holds, and a kernel that refuses it leaves the
//! block as it was. `bench/embree` compiles this same file, so that it times the build as
//! `prism` runs it.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicBool, Ordering};

pub(crate) struct HugePages;

/// Whether large blocks are advised; set once, early in `main`, by `enable_if_asked`.
static ENABLED: AtomicBool = AtomicBool::new(false);

/// The environment variable that turns the advice on (`1`).
pub(crate) const VARIABLE: &str = "PRISM_HUGE_PAGES";

/// Turns the advice on when the environment asks for it. Read here rather than in the
/// allocator, which must not allocate (reading the environment does).
pub(crate) fn enable_if_asked() {
    let asked = std::env::var_os(VARIABLE).is_some_and(|v| v == "1");
    ENABLED.store(asked, Ordering::Relaxed);
}

/// The huge page size on x86-64 and most ARM64 kernels.
const HUGE_PAGE: usize = 1 << 21;

/// Blocks smaller than two huge pages hold at most one whole one: not worth the call.
const ADVISED: usize = 2 * HUGE_PAGE;

/// The whole huge pages inside a block of `size` bytes at address `at`, as (start, end),
/// for blocks worth advising: the partial pages at the ends may be shared with other
/// blocks and stay as they are.
#[cfg_attr(not(target_os = "linux"), allow(dead_code))]
fn huge_pages_within(at: usize, size: usize) -> Option<(usize, usize)> {
    if size < ADVISED || at == 0 {
        return None;
    }
    let start = at.next_multiple_of(HUGE_PAGE);
    let end = (at + size) & !(HUGE_PAGE - 1);
    (end > start).then_some((start, end))
}

/// Advises the whole huge pages inside `[ptr, ptr + size)`.
#[cfg(target_os = "linux")]
#[allow(unsafe_code)]
fn advise(ptr: *mut u8, size: usize) {
    if !ENABLED.load(Ordering::Relaxed) {
        return;
    }
    if let Some((start, end)) = huge_pages_within(ptr as usize, size) {
        // SAFETY: the range lies inside a block this allocator just handed out; the advice
        // neither moves nor changes its contents. A failure (an old kernel, THP disabled)
        // leaves the pages as they were, so the result is ignored.
        unsafe {
            libc::madvise(start as *mut libc::c_void, end - start, libc::MADV_HUGEPAGE);
        }
    }
}

#[cfg(not(target_os = "linux"))]
fn advise(_ptr: *mut u8, _size: usize) {}

// SAFETY: every call is passed to `System` unchanged; `advise` only adds a hint on the
// block `System` returned.
#[allow(unsafe_code)]
unsafe impl GlobalAlloc for HugePages {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let ptr = System.alloc(layout);
        advise(ptr, layout.size());
        ptr
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let ptr = System.alloc_zeroed(layout);
        advise(ptr, layout.size());
        ptr
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let ptr = System.realloc(ptr, layout, new_size);
        advise(ptr, new_size);
        ptr
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_whole_huge_pages_inside_large_blocks_are_advised() {
        let h = HUGE_PAGE;
        // Too small, or null.
        assert_eq!(huge_pages_within(h, ADVISED - 1), None);
        assert_eq!(huge_pages_within(0, 8 * h), None);
        // Aligned: every page.
        assert_eq!(huge_pages_within(4 * h, 3 * h), Some((4 * h, 7 * h)));
        // Unaligned at both ends: the pages strictly inside.
        assert_eq!(huge_pages_within(4 * h + 64, 3 * h), Some((5 * h, 7 * h)));
        assert_eq!(huge_pages_within(4 * h + 64, 2 * h), Some((5 * h, 6 * h)));
        // The smallest block advised holds one whole page wherever it starts.
        assert_eq!(huge_pages_within(4 * h + 1, ADVISED), Some((5 * h, 6 * h)));
    }

    #[test]
    #[allow(unsafe_code)]
    fn blocks_keep_their_contents_through_growth() {
        // The advice's path, as `PRISM_HUGE_PAGES=1` turns it on.
        ENABLED.store(true, Ordering::Relaxed);
        let alloc = HugePages;
        let small = Layout::from_size_align(64, 8).unwrap();
        let size = 3 * HUGE_PAGE + 12_345;
        unsafe {
            let ptr = alloc.alloc_zeroed(Layout::from_size_align(size, 16).unwrap());
            assert!(!ptr.is_null());
            assert!((0..size).step_by(4093).all(|i| *ptr.add(i) == 0));
            for i in (0..size).step_by(4093) {
                *ptr.add(i) = (i % 251) as u8;
            }
            let layout = Layout::from_size_align(size, 16).unwrap();
            let grown = alloc.realloc(ptr, layout, 2 * size);
            assert!(!grown.is_null());
            assert!((0..size)
                .step_by(4093)
                .all(|i| *grown.add(i) == (i % 251) as u8));
            alloc.dealloc(grown, Layout::from_size_align(2 * size, 16).unwrap());
            let p = alloc.alloc(small);
            assert!(!p.is_null());
            alloc.dealloc(p, small);
        }
    }
}

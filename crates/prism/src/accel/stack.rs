//! The traversal stack every hierarchy walks with: deferred nodes (with whatever each
//! method needs to resume them, e.g. an entry distance) in a fixed-capacity array on the
//! query's own stack.
//!
//! Fixed capacity because each build bounds its depth, so the bound is known at compile
//! time and no query allocates. Uninitialised until pushed (`ArrayVec`), because zeroing
//! a 2 KiB array for every ray costs as much as a whole traversal of a small scene; the
//! capacity check of a push is one compare that the depth bound keeps false.

use arrayvec::ArrayVec;

/// A stack of at most `N` deferred entries.
pub(crate) struct TraversalStack<T, const N: usize>(ArrayVec<T, N>);

impl<T, const N: usize> TraversalStack<T, N> {
    #[inline(always)]
    pub(crate) fn new() -> Self {
        TraversalStack(ArrayVec::new())
    }

    /// Defers `entry`. Panics if the build broke its depth bound (a bug, not an input).
    #[inline(always)]
    pub(crate) fn push(&mut self, entry: T) {
        self.0.push(entry);
    }

    /// The most recently deferred entry.
    #[inline(always)]
    pub(crate) fn pop(&mut self) -> Option<T> {
        self.0.pop()
    }
}

//! A mutable slice shared by the team's threads, each writing its own disjoint part
//! between two barriers while the others only read what no thread writes in that phase.
//! The borrow checker cannot see a partition that changes from phase to phase (solve:
//! blocks of constraints; apply: blocks of nodes), so the accessors are `unsafe` and the
//! callers state which phase makes them sound.

use std::marker::PhantomData;
use std::ops::Range;

/// `&mut [T]` handed to several threads at once (see the module docs).
#[derive(Debug)]
pub(super) struct SharedSlice<'a, T> {
    ptr: *mut T,
    len: usize,
    _borrow: PhantomData<&'a mut [T]>,
}

// SAFETY: a `SharedSlice` is only a way to reach a `&'a mut [T]` from several threads; the
// `unsafe` accessors make each caller promise that no two threads touch the same element
// at once unless both only read it. Sending `T`s between threads needs `T: Send`, reading
// them from several threads needs `T: Sync`.
unsafe impl<T: Send + Sync> Sync for SharedSlice<'_, T> {}
// SAFETY: as for `Sync` above.
unsafe impl<T: Send + Sync> Send for SharedSlice<'_, T> {}

impl<'a, T> SharedSlice<'a, T> {
    /// Shares `slice` for the lifetime of its borrow.
    pub(super) fn new(slice: &'a mut [T]) -> Self {
        SharedSlice {
            ptr: slice.as_mut_ptr(),
            len: slice.len(),
            _borrow: PhantomData,
        }
    }

    /// The elements in `range`, to write.
    ///
    /// # Safety
    /// Until the returned borrow ends, no other thread may read or write any element in
    /// `range`. Panics if `range` is out of bounds.
    #[allow(clippy::mut_from_ref)]
    pub(super) unsafe fn part(&self, range: Range<usize>) -> &mut [T] {
        assert!(range.start <= range.end && range.end <= self.len);
        // SAFETY: in bounds (checked above) of the slice borrowed for 'a; the caller
        // promises exclusive access to these elements while the borrow lives.
        unsafe { std::slice::from_raw_parts_mut(self.ptr.add(range.start), range.len()) }
    }

    /// Its length.
    pub(super) fn len(&self) -> usize {
        self.len
    }

    /// Whether it has no elements.
    pub(super) fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The whole slice, to read.
    ///
    /// # Safety
    /// Until the returned borrow ends, no thread may write any element.
    pub(super) unsafe fn whole(&self) -> &[T] {
        // SAFETY: the slice borrowed for 'a; the caller promises no writes while the
        // borrow lives.
        unsafe { std::slice::from_raw_parts(self.ptr, self.len) }
    }
}

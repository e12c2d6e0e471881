//! Transparent huge pages for the large arrays a query walks: the hierarchy's nodes and its
//! packed leaves.
//!
//! On Linux kernels whose transparent huge pages are set to `madvise` (the common default, and
//! this project's machines), memory is backed by 4 KiB pages unless asked otherwise, and an
//! incoherent walk over a 1.1M-triangle hierarchy (about 100 MB) misses the TLB on most node
//! and leaf visits. [`vec_with_capacity`] asks for 2 MiB pages over the part of a new vector's
//! allocation that covers whole huge pages, before it is first written (pages already faulted
//! in are not merged until the kernel's background scan gets to them). It is advice: where the
//! kernel declines, nothing changes, and nothing else depends on it.

/// Bytes of one transparent huge page on x86-64 (and aarch64 with 4 KiB base pages).
const HUGE_PAGE: usize = 2 << 20;

/// A vector with room for `capacity` elements whose allocation is advised to use huge pages
/// where it holds whole ones. Room never written costs address space only.
pub(crate) fn vec_with_capacity<T>(capacity: usize) -> Vec<T> {
    let v = Vec::with_capacity(capacity);
    let start = v.as_ptr() as usize;
    let end = start + v.capacity() * size_of::<T>();
    let first = start.next_multiple_of(HUGE_PAGE);
    if end >= first + HUGE_PAGE {
        let len = (end - first) / HUGE_PAGE * HUGE_PAGE;
        #[cfg(target_os = "linux")]
        // SAFETY: the range lies inside `v`'s allocation; MADV_HUGEPAGE changes no contents and
        // no mapping, only how the kernel backs the pages (an error is harmless and ignored).
        unsafe {
            libc::madvise(first as *mut libc::c_void, len, libc::MADV_HUGEPAGE);
        }
        #[cfg(not(target_os = "linux"))]
        let _ = len;
    }
    v
}

//! How many worker threads to start, one rule for every caller that takes a count (the
//! command line's `--threads`, the Python package's `threads=`): 0 or none means one worker
//! per core, as in pbrt-v4, and a count far beyond the machine is capped (with a warning for
//! the caller to show) rather than starting that many threads.

use std::num::NonZeroUsize;

/// Worker threads per core at most: enough to oversubscribe on purpose (tests of
/// determinism, hyper-threading experiments), far from the thousands that would exhaust
/// memory for stacks.
pub const MAX_THREADS_PER_CORE: usize = 4;

/// The worker count to start for `requested` on this machine: `None` (unset or 0) is rayon's
/// pool of one per core; a request above [`MAX_THREADS_PER_CORE`] x the cores is capped, and
/// the second value says so.
pub fn worker_threads(requested: Option<usize>) -> (Option<usize>, Option<String>) {
    let cores = std::thread::available_parallelism().map_or(1, NonZeroUsize::get);
    cap(requested, cores)
}

/// [`worker_threads`] for a machine of `cores`.
fn cap(requested: Option<usize>, cores: usize) -> (Option<usize>, Option<String>) {
    let limit = MAX_THREADS_PER_CORE * cores;
    match requested {
        None | Some(0) => (None, None),
        Some(n) if n > limit => (
            Some(limit),
            Some(format!(
                "--threads {n}: capped at {limit} ({MAX_THREADS_PER_CORE} x {cores} cores)"
            )),
        ),
        Some(n) => (Some(n), None),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_is_every_core_and_absurd_counts_are_capped() {
        assert_eq!(cap(None, 8), (None, None));
        assert_eq!(cap(Some(0), 8), (None, None));
        assert_eq!(cap(Some(3), 8), (Some(3), None));
        assert_eq!(cap(Some(32), 8), (Some(32), None));
        let (count, warning) = cap(Some(100_000), 8);
        assert_eq!(count, Some(32));
        assert_eq!(
            warning.as_deref(),
            Some("--threads 100000: capped at 32 (4 x 8 cores)")
        );
    }
}

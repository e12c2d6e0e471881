//! `--threads`, one rule for every subcommand that takes it (render, hits): the core's
//! [`worker_threads`], its warning printed on stderr.

use lumis_core::render::worker_threads;

/// The worker count to start: `None` (unset or 0) is rayon's pool of one per core; a request
/// far beyond the machine is capped, with a warning on stderr unless `quiet`.
pub fn resolve(requested: Option<usize>, quiet: bool) -> Option<usize> {
    let (count, warning) = worker_threads(requested);
    if let Some(w) = warning
        && !quiet
    {
        eprintln!("warning: {w}");
    }
    count
}

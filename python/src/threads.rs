//! `threads=`: `None` (or 0) runs on rayon's global pool, one worker per core; a count runs on
//! a pool of that size (capped as `--threads` is, [`worker_threads`]), started once per count
//! and kept for the process.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use lumis_core::render::worker_threads;
use pyo3::PyResult;
use pyo3::exceptions::PyRuntimeError;
use rayon::ThreadPool;

static POOLS: Mutex<Option<HashMap<usize, Arc<ThreadPool>>>> = Mutex::new(None);

/// Runs `f` on the pool `threads` asks for (see the module docs).
pub fn run<T: Send>(threads: Option<usize>, f: impl FnOnce() -> T + Send) -> PyResult<T> {
    let (count, _warning) = worker_threads(threads);
    let Some(n) = count else {
        return Ok(f());
    };
    let pool = {
        let mut pools = POOLS.lock().unwrap_or_else(|p| p.into_inner());
        let pools = pools.get_or_insert_with(HashMap::new);
        match pools.get(&n) {
            Some(p) => p.clone(),
            None => {
                let p = rayon::ThreadPoolBuilder::new()
                    .num_threads(n)
                    .build()
                    .map_err(|e| {
                        PyRuntimeError::new_err(format!("could not start {n} worker threads: {e}"))
                    })?;
                let p = Arc::new(p);
                pools.insert(n, p.clone());
                p
            }
        }
    };
    Ok(pool.install(f))
}

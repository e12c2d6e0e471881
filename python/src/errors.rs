//! The Python exceptions: a scene that cannot be loaded or rendered raises [`SceneError`] with
//! the message `lumis` prints after `error: ` (the whole cause chain, `: `-separated); a ray
//! outside the query domain raises [`RayError`] naming its index.

use pyo3::create_exception;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

create_exception!(
    lumis,
    SceneError,
    PyValueError,
    "A scene file (or a file it references, or a -D override) could not be loaded; the \
     message is the one the lumis command prints."
);
create_exception!(
    lumis,
    RayError,
    PyValueError,
    "A ray is outside the query domain (non-finite origin, zero or non-finite direction, NaN \
     t_min or t_max); the message names the ray's index, as `lumis hits` names its row."
);

/// `e` and its causes as `lumis` prints them (anyhow's `{:#}`: `outer: inner: innermost`).
pub fn chain(e: &dyn std::error::Error) -> String {
    let mut message = e.to_string();
    let mut source = e.source();
    while let Some(s) = source {
        message.push_str(": ");
        message.push_str(&s.to_string());
        source = s.source();
    }
    message
}

/// A [`SceneError`] carrying `e`'s whole chain.
pub fn scene_error(e: &dyn std::error::Error) -> PyErr {
    SceneError::new_err(chain(e))
}

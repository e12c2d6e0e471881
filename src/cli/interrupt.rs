//! Ctrl-C during a render: the first press stops the render between tiles so that the finished
//! ones are written (a valid, partial EXR); a second press quits at once, deleting the
//! temporary files of outputs not yet renamed into place (a quit skips destructors). The
//! process then exits with 130, the shell's code for "terminated by SIGINT".

use lumis_core::render::CancelFlag;

/// The exit code after an interrupt (128 + SIGINT).
pub const EXIT_INTERRUPTED: i32 = 130;

/// The error a run returns after writing a partial image; `main` turns it into exit code 130.
#[derive(Debug, thiserror::Error)]
#[error("interrupted: wrote the {done} of {total} tiles finished (lumis/partial = 1 in the EXR)")]
pub struct Interrupted {
    /// Tiles rendered.
    pub done: usize,
    /// Tiles in the render.
    pub total: usize,
}

/// Installs the Ctrl-C handler that raises `flag`, or on a second press exits at once.
/// Fails only if a handler is already installed (then Ctrl-C keeps its default: quit).
pub fn on_ctrl_c(flag: CancelFlag) -> Result<(), ctrlc::Error> {
    ctrlc::set_handler(move || {
        if flag.is_raised() {
            lumis_io::output::remove_staged_temps();
            std::process::exit(EXIT_INTERRUPTED);
        }
        flag.raise();
        eprintln!(
            "\ninterrupted: finishing the tiles in flight, then writing the image \
             (Ctrl-C again to quit now)"
        );
    })
}

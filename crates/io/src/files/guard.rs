//! The last line of defence around calls into parser crates: a panic there (a bug the checks
//! before the call missed) becomes an error, and prints nothing.
//!
//! The panic hook is process-wide, so it cannot be swapped around each call without racing
//! other threads. Instead [`install`] puts in, once, a hook that stays quiet for panics on a
//! thread that is inside [`guarded`] and hands every other panic to the hook it replaced.

use std::cell::{Cell, RefCell};
use std::panic::{AssertUnwindSafe, PanicHookInfo};
use std::sync::Once;

thread_local! {
    /// Depth of [`guarded`] calls on this thread (they may nest).
    static SILENCED: Cell<u32> = const { Cell::new(0) };
    /// Where the last silenced panic happened, for the error.
    static LAST: RefCell<Option<String>> = const { RefCell::new(None) };
}

static INSTALL: Once = Once::new();

/// Installs the quiet hook (idempotent). [`guarded`] calls it; a program that wants its own
/// hook for every panic, silenced or not (the fuzz targets abort on any), calls this first and
/// sets its hook after.
pub fn install() {
    INSTALL.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info: &PanicHookInfo<'_>| {
            if SILENCED.with(Cell::get) > 0 {
                let at = info
                    .location()
                    .map(|l| format!("{}:{}", l.file(), l.line()));
                LAST.with(|last| *last.borrow_mut() = at);
            } else {
                previous(info);
            }
        }));
    });
}

/// Runs `f`; a panic inside it is caught without printing and returned as `Err` with where it
/// happened (the crate's source location), for the caller to name its file and element.
pub fn guarded<T>(f: impl FnOnce() -> T) -> Result<T, String> {
    install();
    SILENCED.with(|s| s.set(s.get() + 1));
    let result = std::panic::catch_unwind(AssertUnwindSafe(f));
    SILENCED.with(|s| s.set(s.get() - 1));
    result.map_err(|_| {
        let at = LAST.with(|last| last.borrow_mut().take());
        format!(
            "internal error in {} (a lumis bug: please report this file)",
            at.as_deref().unwrap_or("a parser")
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_guarded_panic_is_an_error_naming_its_location() {
        let e = guarded(|| -> u32 { panic!("boom") }).unwrap_err();
        assert!(e.contains("guard.rs"), "{e}");
        assert_eq!(guarded(|| 7), Ok(7));
        // Nested calls leave the flag balanced.
        assert!(guarded(|| guarded(|| -> u32 { panic!() }).is_err()).unwrap());
        assert_eq!(SILENCED.with(Cell::get), 0);
    }
}

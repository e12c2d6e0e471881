//! The integration tests of `lumis-lab`, as one test binary; the helpers are the root
//! package's (tests/it/common), which run whichever binary the test belongs to.

#[path = "../../../../tests/it/common/mod.rs"]
mod common;
#[cfg(unix)]
#[path = "../../../../tests/it/support_io/mod.rs"]
mod support_io;

mod accuracy;
mod outputs;

//! A live view: the render streamed into an image viewer that speaks tev's protocol (tev,
//! HDRView), as pbrt-v4's `--display-server` does. Tiles go out as they finish; when the render
//! ends, the whole image once more as the EXR holds it, so the viewer ends on the file's pixels.
//!
//! The viewer never slows or breaks the render: tiles are copied into an image the sender
//! thread owns, which sends those finished every 40 ms, a row of tiles per update (a slow
//! viewer gets the tiles that piled up in fewer, larger updates), the connection is
//! made on that thread, a refused or dropped connection is a warning (retried a few times,
//! then given up), writes time out, and [`LiveView::finish`] waits at most about a second.
//! Nothing here touches the outputs, so they are the same bytes with or without a viewer.

mod packets;
mod sender;
mod view;

pub use view::{LiveView, Warn};

use std::fmt;

/// tev's default port.
pub const DEFAULT_PORT: u16 = 14158;

/// Where the viewer listens: `[HOST:]PORT` (the host defaults to 127.0.0.1, tev's).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DisplayServer {
    host: String,
    port: u16,
}

/// A `--display-server` value that is not `[HOST:]PORT`.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
#[error(
    "display server `{given}`: expected [HOST:]PORT with PORT a number from 1 to 65535 (tev listens on {DEFAULT_PORT})"
)]
pub struct DisplayServerError {
    given: String,
}

impl DisplayServer {
    /// Parses `[HOST:]PORT`; an IPv6 host is written in brackets (`[::1]:14158`).
    ///
    /// # Errors
    /// When the port is missing, zero or not a number, or the host is empty.
    pub fn parse(s: &str) -> Result<Self, DisplayServerError> {
        let err = || DisplayServerError {
            given: s.to_string(),
        };
        let (host, port) = match s.rsplit_once(':') {
            Some((host, port)) => (host.trim_start_matches('[').trim_end_matches(']'), port),
            None => ("127.0.0.1", s),
        };
        let port: u16 = port.parse().map_err(|_| err())?;
        if port == 0 || host.is_empty() || host.contains(char::is_whitespace) {
            return Err(err());
        }
        Ok(Self {
            host: host.to_string(),
            port,
        })
    }

    /// The host part.
    pub fn host(&self) -> &str {
        &self.host
    }

    /// The port.
    pub fn port(&self) -> u16 {
        self.port
    }
}

impl fmt::Display for DisplayServer {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.host.contains(':') {
            write!(f, "[{}]:{}", self.host, self.port)
        } else {
            write!(f, "{}:{}", self.host, self.port)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn addresses() {
        let s = DisplayServer::parse("14158").unwrap();
        assert_eq!((s.host(), s.port()), ("127.0.0.1", 14158));
        let s = DisplayServer::parse("viewer.local:9000").unwrap();
        assert_eq!((s.host(), s.port()), ("viewer.local", 9000));
        let s = DisplayServer::parse("[::1]:14158").unwrap();
        assert_eq!(
            (s.host(), s.port(), s.to_string().as_str()),
            ("::1", 14158, "[::1]:14158")
        );
        for bad in ["", "host:", ":14158", "0", "70000", "host:port", "a b:1"] {
            let e = DisplayServer::parse(bad).unwrap_err().to_string();
            assert!(e.contains("[HOST:]PORT"), "{bad}: {e}");
        }
    }
}

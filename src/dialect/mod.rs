//! The dialects. Each lives in its own folder (front end and/or emitter plus its rules) and
//! meets the others only in the IR.

pub mod czech;
pub mod iso;

use std::fmt;

/// A program dialect.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Dialect {
    /// The Czech lathe control (manual chapter 5).
    Czech,
    /// ISO/RS274-NGC as LinuxCNC reads it.
    Iso,
}

impl Dialect {
    pub fn id(self) -> &'static str {
        match self {
            Dialect::Czech => "czech",
            Dialect::Iso => "iso",
        }
    }
}

impl fmt::Display for Dialect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.id())
    }
}

//! The `ncthread` binary's commands, one module each, and what they share.

pub(crate) mod args;
pub(crate) mod batch;
pub(crate) mod check;
pub(crate) mod colour;
pub(crate) mod commands;
pub(crate) mod examples;
pub(crate) mod io;
pub(crate) mod man;
pub(crate) mod verify;

/// A failure that is the user's invocation or the file system, not the program's content.
pub(crate) enum Fatal {
    /// A usage or I/O problem (exit 2), said on stderr.
    Usage(String),
    /// The input was refused and its diagnostics printed (exit 1).
    Refused,
}

//! Dialect `iso`: RS274/NGC as LinuxCNC reads it. A target checked against LinuxCNC's
//! `rs274`, and a source (hand conversions to check, CAM programs to move to old machines).

mod emit;
mod front;
mod syntax;

pub use emit::emit;
pub use front::{Options, parse};

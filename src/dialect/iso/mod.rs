//! Target `iso`: RS274/NGC as LinuxCNC reads it. Checked against LinuxCNC's `rs274`.

mod emit;

pub use emit::emit;

//! Dialect `czech`: the Czech lathe control of manual chapter 5 (G33 with F, I, J, E,
//! R-parameter angles, `FRnn`).

mod emit;
mod front;
pub mod syntax;

pub use emit::{Renumber, emit};
pub use front::{Options, parse};

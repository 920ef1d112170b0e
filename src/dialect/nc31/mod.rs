//! Dialect `nc31`: the Электроника НЦ-31 (scaled integer words, one word per frame, `*`
//! groups, `~` rapid, `@` incremental, G31 multi-pass cycle, G32 single pass, G33 tapping).

mod emit;
mod front;
pub mod syntax;

pub use emit::{Options as EmitOptions, emit};
pub use front::{Options, parse};

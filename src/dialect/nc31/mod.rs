//! Dialect `nc31`: the Электроника НЦ-31 (scaled integer words, one word per frame, `*`
//! groups, `~` rapid, `@` incremental, G31 multi-pass cycle, G32 single pass, G33 tapping).

mod front;
pub mod syntax;

pub use front::{Options, parse};

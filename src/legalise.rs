//! Rules every target shares, checked once on the IR before an emitter runs: whatever the
//! target, a program that breaks them cannot be written.
//!
//! - A thread pass, thread cycle or tap needs the spindle turning (M3/M4 before it, no M5 or
//!   program end between). Every control in scope refuses a synchronised move otherwise.

use crate::diag::{Diagnostic, codes};
use crate::ir::{ItemKind, Program};
use crate::source::SourceFile;

/// The diagnostics of the shared rules (errors).
pub fn check(program: &Program, src: &SourceFile) -> Vec<Diagnostic> {
    let mut diags = Vec::new();
    let mut turning = false;
    for item in &program.items {
        match &item.kind {
            ItemKind::Spindle {
                direction: Some(_), ..
            } => turning = true,
            ItemKind::SpindleStop | ItemKind::ProgramEnd(_) => turning = false,
            ItemKind::ThreadPass(_) | ItemKind::ThreadCycle(_) | ItemKind::TapCycle(_)
                if !turning =>
            {
                let what = match item.kind {
                    ItemKind::TapCycle(_) => "tap",
                    ItemKind::ThreadCycle(_) => "thread cycle",
                    _ => "thread pass",
                };
                diags.push(
                    Diagnostic::new(
                        codes::SPINDLE_OFF,
                        format!("{what} while the spindle is not turning"),
                    )
                    .at(src, item.span)
                    .help("start the spindle (M3/M4 with S) before the thread; a synchronised move follows the turning spindle"),
                );
            }
            _ => {}
        }
    }
    diags
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixed::Length;
    use crate::ir::{EndCode, Item, Pos, SpindleDirection, TapCycle};
    use crate::source::Span;

    fn check_kinds(kinds: Vec<ItemKind>) -> Vec<String> {
        let program = Program {
            items: kinds
                .into_iter()
                .map(|k| Item::new(k, Span::default()))
                .collect(),
        };
        check(&program, &SourceFile::new("t", ""))
            .into_iter()
            .map(|d| d.message)
            .collect()
    }

    #[test]
    fn a_thread_needs_the_spindle_turning() {
        let tap = ItemKind::TapCycle(TapCycle {
            end_z: Length::from_mm(-10),
            lead: crate::fixed::Lead::from_length(Length(15_000)),
            then_x: None,
        });
        let start = ItemKind::Spindle {
            speed: Some(100),
            direction: Some(SpindleDirection::Clockwise),
        };
        let speed_only = ItemKind::Spindle {
            speed: Some(100),
            direction: None,
        };
        assert_eq!(
            check_kinds(vec![speed_only, tap.clone()]),
            ["tap while the spindle is not turning"]
        );
        assert!(check_kinds(vec![start.clone(), tap.clone()]).is_empty());
        assert_eq!(
            check_kinds(vec![
                start.clone(),
                ItemKind::SpindleStop,
                ItemKind::Rapid { to: Pos::UNKNOWN },
                tap.clone()
            ])
            .len(),
            1
        );
        assert_eq!(
            check_kinds(vec![start, ItemKind::ProgramEnd(EndCode::M30), tap]).len(),
            1
        );
    }
}

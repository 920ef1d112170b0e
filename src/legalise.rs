//! Rules every target shares, checked once on the IR before an emitter runs: whatever the
//! target, a program that breaks them cannot be written.
//!
//! - A thread pass, thread cycle or tap needs the spindle turning (M3/M4 before it, no M5 or
//!   program end between). Every control in scope refuses a synchronised move otherwise.
//! - A feed per revolution needs the spindle turning at a known, non-zero speed (LinuxCNC
//!   refuses it; on any control the axis would wait for ever).
//! - A block kept as written (`--unsupported warn`) may move the machine: it stands in the
//!   output only when the output is in its own dialect and in the modes it was written under
//!   (millimetres, diameters, absolute coordinates, the same feed mode). Otherwise its meaning
//!   would change, so it is refused in every mode.

use crate::diag::{Diagnostic, codes};
use crate::dialect::{self, DialectId};
use crate::ir::{FeedMode, Item, ItemKind, Program};
use crate::source::SourceFile;

/// The diagnostics of the shared rules (errors). `to` is the target, when the program is to
/// be written (`None`: `check`).
pub fn check(program: &Program, src: &SourceFile, to: Option<DialectId>) -> Vec<Diagnostic> {
    let mut rules = Shared::new(src, to, output_in_inches(program, to));
    for item in &program.items {
        rules.item(item);
    }
    rules.finish()
}

/// The shared rules over a program's items one at a time, in order ([`check`], and `check`'s
/// streaming read): the spindle and feed mode they leave, and the run of blocks kept as a
/// cycle being read (a refusal is said once per run, at the blocks [`said_in_run`] names).
pub struct Shared<'s> {
    src: &'s SourceFile,
    /// The target, and whether its output is in inches.
    to: (Option<DialectId>, bool),
    turning: bool,
    speed: Option<u32>,
    feed_mode: Option<FeedMode>,
    /// The cycle blocks kept as written (and comments between them) since the last item
    /// that closes their run, with the feed mode each was read under.
    run: Vec<(Item, Option<FeedMode>)>,
    fold: crate::diag::Fold,
    diags: Vec<Diagnostic>,
    /// An error has been found.
    errored: bool,
}

impl<'s> Shared<'s> {
    /// For `to` (`None`: `check`), whose output is in inches when `inch`.
    pub fn new(src: &'s SourceFile, to: Option<DialectId>, inch: bool) -> Self {
        Shared {
            src,
            to: (to, inch),
            turning: false,
            speed: None,
            feed_mode: None,
            run: Vec::new(),
            fold: Default::default(),
            diags: Vec::new(),
            errored: false,
        }
    }

    /// Whether an error has been found so far (a run of kept cycle blocks still open is
    /// said at its end).
    pub fn errored(&self) -> bool {
        self.errored
    }

    /// The program's next item.
    pub fn item(&mut self, item: &Item) {
        match &item.kind {
            ItemKind::Opaque { block: Some(c), .. } if c.cycle => {
                self.run.push((item.clone(), self.feed_mode));
                return;
            }
            ItemKind::Comment(_) if !self.run.is_empty() => return,
            _ => self.close_run(),
        }
        self.rules(item, self.feed_mode, false);
    }

    /// Every diagnostic, once the last item is in.
    pub fn finish(mut self) -> Vec<Diagnostic> {
        self.close_run();
        self.diags.extend(self.fold.finish());
        self.diags
    }

    /// The run of kept cycle blocks is over: each is checked, said where the run says it.
    fn close_run(&mut self) {
        if self.run.is_empty() {
            return;
        }
        let run = std::mem::take(&mut self.run);
        let said = said_in_run(&run);
        for (i, (item, feed_mode)) in run.iter().enumerate() {
            self.rules(item, *feed_mode, said.contains(&i));
        }
    }

    /// The rules at one item, read under `feed_mode`; `said`: a kept cycle block at which
    /// its run's refusal is said.
    fn rules(&mut self, item: &Item, feed_mode: Option<FeedMode>, said: bool) {
        let (turning, speed) = (self.turning, self.speed);
        let refusal = match &item.kind {
            ItemKind::Spindle {
                speed: s,
                direction,
            } => {
                if s.is_some() {
                    self.speed = *s;
                }
                if direction.is_some() {
                    self.turning = true;
                }
                None
            }
            ItemKind::SpindleStop | ItemKind::ProgramEnd(_) => {
                self.turning = false;
                None
            }
            ItemKind::FeedMode(mode) => {
                self.feed_mode = Some(*mode);
                None
            }
            ItemKind::ThreadPass(_) | ItemKind::ThreadCycle(_) | ItemKind::TapCycle(_)
                if !turning =>
            {
                Some(thread_without_spindle(&item.kind))
            }
            ItemKind::Feed { .. } | ItemKind::Arc { .. }
                if feed_mode != Some(FeedMode::PerMin) && (!turning || speed.unwrap_or(0) == 0) =>
            {
                Some(feed_without_spindle(turning, speed))
            }
            ItemKind::Opaque {
                dialect,
                text,
                block: Some(context),
            } => kept_block_moves(text, *dialect, context, self.to, feed_mode, said),
            // A cycle kept whole for its own dialect: the same rules over its moves, and
            // copied where it means the same (`lower::unroll`).
            ItemKind::ModelCycle(c) => {
                cycle_without_spindle(c, turning, speed, feed_mode).or_else(|| {
                    kept_block_moves(&c.text, c.dialect, &c.context, self.to, feed_mode, true)
                })
            }
            _ => None,
        };
        if let Some(d) = refusal.map(|d| d.at(self.src, item.span)) {
            self.errored |= d.is_error();
            if self.fold.admit(&d) {
                self.diags.push(d);
            }
        }
    }
}

/// LG001/LG002 inside a cycle kept whole: a thread pass while the spindle is not turning, or
/// a feed per revolution without a turning spindle with a speed.
fn cycle_without_spindle(
    c: &crate::ir::ModelCycle,
    turning: bool,
    speed: Option<u32>,
    feed_mode: Option<FeedMode>,
) -> Option<Diagnostic> {
    let thread = c
        .moves
        .iter()
        .find(|m| matches!(m, ItemKind::ThreadPass(_)));
    if let Some(pass) = thread.filter(|_| !turning) {
        return Some(thread_without_spindle(pass));
    }
    let feeds = c
        .moves
        .iter()
        .any(|m| matches!(m, ItemKind::Feed { .. } | ItemKind::Arc { .. }));
    (feeds && feed_mode != Some(FeedMode::PerMin) && (!turning || speed.unwrap_or(0) == 0))
        .then(|| feed_without_spindle(turning, speed))
}

/// LG001: a thread pass, thread cycle or tap while the spindle is not turning.
fn thread_without_spindle(kind: &ItemKind) -> Diagnostic {
    let what = match kind {
        ItemKind::TapCycle(_) => "tap",
        ItemKind::ThreadCycle(_) => "thread cycle",
        _ => "thread pass",
    };
    Diagnostic::new(
        codes::SPINDLE_OFF,
        format!("{what} while the spindle is not turning"),
    )
    .help("start the spindle (M3/M4 with S) before the thread; a synchronised move follows the turning spindle")
}

/// LG002: a feed per revolution while the spindle is not turning, or turns at no speed.
fn feed_without_spindle(turning: bool, speed: Option<u32>) -> Diagnostic {
    let why = if !turning {
        "the spindle is not turning"
    } else if speed.is_none() {
        "no spindle speed (S) is set"
    } else {
        "the spindle speed is S0"
    };
    Diagnostic::new(
        codes::FEED_SPINDLE_OFF,
        format!("a feed per revolution while {why}: the axis would not move"),
    )
    .help(
        "start the spindle with S and M3/M4 before the feed, or program the feed per minute (G94)",
    )
}

/// The output's unit: inches for an inch program whose target can say them.
pub fn output_in_inches(program: &Program, to: Option<DialectId>) -> bool {
    program.inch && to.is_some_and(|t| dialect::get(t).says_inches())
}

/// The blocks of a run kept as a cycle at which another target's refusal is said (indices
/// into the run, which holds them and the comments between them): every block that moves (a
/// G71's second block, a G70), or the run's first block when none does (a first block alone).
fn said_in_run(run: &[(Item, Option<FeedMode>)]) -> Vec<usize> {
    let blocks = run
        .iter()
        .enumerate()
        .filter_map(|(i, (item, _))| match &item.kind {
            ItemKind::Opaque { block: Some(c), .. } => Some((i, c.moves)),
            _ => None,
        });
    let moving: Vec<usize> = blocks.clone().filter(|&(_, m)| m).map(|(i, _)| i).collect();
    if moving.is_empty() {
        blocks.map(|(i, _)| i).take(1).collect()
    } else {
        moving
    }
}

/// LG003: a block kept as written that would mean something else in the output: another
/// dialect's, or written in modes (or a feed mode) the output does not have there.
fn kept_block_moves(
    text: &str,
    dialect: DialectId,
    context: &crate::ir::ModalContext,
    (to, inch): (Option<DialectId>, bool),
    feed_mode: Option<FeedMode>,
    said: bool,
) -> Option<Diagnostic> {
    if context.cycle
        && let Some(to) = to.filter(|&to| to != dialect)
    {
        // Said once per cycle (`cycle_blocks_said`): a G71's first block and its contour's
        // blocks belong to its second.
        if !said {
            return None;
        }
        return Some(
            Diagnostic::new(
                codes::OPAQUE_MEANING,
                format!(
                    "`{text}`: a {dialect} canned cycle (or a move to the reference point), kept as written: its moves are the control's, and ncthread writes them for another control only where the machine model declared in the profile's [{dialect}] section expands it (G70, G71 and G72 type I, G73, G74, G75, G76, G90, G94 as FANUC's G-code system A numbers them, G28 with the reference point, G53); the output is {to}"
                ),
            )
            .help(format!(
                "if the machine runs its cycles as the GSK 980TDi does, set `cycle_model = \"gsk-980tdi\"` in the profile's [{dialect}] section (the reader says why a cycle stays kept); else convert to {dialect} (the same control runs the cycle), or write the cycle's moves in the source"
            )),
        );
    }
    let why = match to {
        Some(to) if to != dialect => Some(format!(
            "{}only the {dialect} control can say it; the output is {to}",
            if context.moves {
                "it may move the machine and "
            } else {
                ""
            }
        )),
        Some(_) => context
            .differs_from_output(inch)
            .map(|modes| format!("it was written in {modes}"))
            .or_else(|| {
                let mode =
                    feed_mode.or_else(|| to.and_then(|t| dialect::get(t).output_feed_mode()))?;
                let per_minute = mode == FeedMode::PerMin;
                (context.per_minute.is_some_and(|p| p != per_minute)).then(|| {
                    "it was written in another feed mode than the output has there".to_string()
                })
            }),
        None => None,
    }?;
    Some(
        Diagnostic::new(
            codes::OPAQUE_MEANING,
            format!("the block `{text}`, kept as written, would mean something else in the output: {why}"),
        )
        .help("a block ncthread does not read can only be copied where it means the same; rewrite it in what ncthread reads (or convert to the same dialect without changing its modes)"),
    )
}

/// The one legalisation of a program for a target: every construct that the target's table
/// ([`crate::dialect::Dialect::capabilities`]) does not write is refused, in the target's
/// words and with its code. (A target that refuses a construct while it writes it, as the
/// НЦ-31 refuses what G32 cannot cut pass by pass, gives no words here.)
pub fn for_target(
    program: &Program,
    src: &SourceFile,
    target: &dyn crate::dialect::Dialect,
    profile: &crate::profile::Profile,
) -> Vec<Diagnostic> {
    let mut rules = ForTarget::new(src, target, profile);
    for item in &program.items {
        rules.item(item);
    }
    rules.finish()
}

/// [`for_target`] over a program's items one at a time, in order.
pub struct ForTarget<'s> {
    src: &'s SourceFile,
    target: &'s dyn crate::dialect::Dialect,
    caps: crate::dialect::capabilities::Capabilities,
    finder: crate::dialect::capabilities::Occurrences,
    found: Vec<crate::dialect::capabilities::Occurrence>,
    fold: crate::diag::Fold,
    diags: Vec<Diagnostic>,
    /// A refusal has been found.
    errored: bool,
}

impl<'s> ForTarget<'s> {
    pub fn new(
        src: &'s SourceFile,
        target: &'s dyn crate::dialect::Dialect,
        profile: &crate::profile::Profile,
    ) -> Self {
        ForTarget {
            src,
            target,
            caps: target.capabilities(profile),
            finder: Default::default(),
            found: Vec::new(),
            fold: Default::default(),
            diags: Vec::new(),
            errored: false,
        }
    }

    /// Whether a refusal has been found so far.
    pub fn errored(&self) -> bool {
        self.errored
    }

    /// The program's next item.
    pub fn item(&mut self, item: &Item) {
        self.finder.item(item, &mut self.found);
        for o in self.found.drain(..) {
            if self.caps.writes(o.construct) {
                continue;
            }
            if let Some(d) = self.target.refusal(o, self.src) {
                self.errored |= d.is_error();
                if self.fold.admit_once(&self.diags, &d) {
                    self.diags.push(d);
                }
            }
        }
    }

    pub fn finish(mut self) -> Vec<Diagnostic> {
        self.diags.extend(self.fold.finish());
        self.diags
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixed::Length;
    use crate::ir::{EndCode, Item, Pos, SpindleDirection, TapCycle};
    use crate::source::Span;

    fn check_kinds(kinds: Vec<ItemKind>) -> Vec<String> {
        let program = Program {
            dialect: crate::dialect::iso::ID,
            library: Vec::new(),
            number: None,
            inch: false,
            name: None,
            items: kinds
                .into_iter()
                .map(|k| Item::new(k, Span::default()))
                .collect(),
        };
        check(&program, &SourceFile::new("t", ""), None)
            .into_iter()
            .map(|d| d.message)
            .collect()
    }

    #[test]
    fn a_thread_needs_the_spindle_turning() {
        let tap = ItemKind::TapCycle(TapCycle {
            end_z: Length::from_mm(-10),
            lead: crate::fixed::Lead::from_length(Length::from_steps(15_000)),
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

//! FANUC's canned cycles under the machine model the profile declares (`[fanuc] cycle_model`
//! or the open points one by one, spec fanuc.md): the cycles this version expands (G70, G71
//! and G72 type I, G73, G74, G75, G76, G90, G94, G28 with the reference point, G53) become [`ItemKind::ModelCycle`] items, each block kept as written
//! for FANUC with the moves the one implementation (`lower::fanuc`) gives it for every other
//! target. A cycle the model does not expand stays kept as written (`front/cycles.rs`), and a
//! warning says why when it is one the model covers: another target then refuses it (LG003).
//!
//! A G71/G72's moves need its contour, which follows it: its item is pushed without moves and
//! given them when the block Q names has been read. The contour's blocks are read as moves by
//! the block interpreter itself, from the cycle's start, into a capture of their own; the
//! reader's state is put back after each.

use super::block::Words;
use super::{FRegister, FrontEnd, Motion, Unit};
use crate::diag::Diagnostic;
use crate::dialect::fanuc::codes;
use crate::dialect::fanuc::profile::{G73Divisor, LayersFrom, MinCut, PassEnd, Retract};
use crate::dialect::fanuc::syntax::Block;
use crate::fixed::Length;
use crate::ir::{Compensation, ItemKind, ModalContext, ModelCycle, Pos};
use crate::lower::fanuc::{
    self as lowering, Element, Pattern, Pecking, Point, Roughing, Threading,
};
use crate::source::{Line, Span};

/// The feed of a contour move whose F the contour does not write: G71/G72 rough at their own
/// feed; G70 takes its block's F, else it is not expanded.
const UNSET_FEED: Length = Length::from_steps(-1);

/// A G71/G72's depth and retract, or a G73's relief and passes (its first block), and the F
/// written there.
#[derive(Clone, Copy, Debug)]
pub(in crate::dialect::fanuc) struct Setup {
    g: i64,
    depth: Length,
    retract: Length,
    relief: Point,
    passes: u32,
    feed: Option<Length>,
}

/// A G76's first block: P's mm rr aa, Q (Δdmin) and R (d).
#[derive(Clone, Copy, Debug)]
pub(in crate::dialect::fanuc) struct ThreadSetup {
    finishing: u32,
    chamfer: u32,
    angle: u32,
    min_cut: Length,
    finish: Length,
}

/// What a cycle waiting for its contour makes of it.
#[derive(Clone, Copy, Debug)]
enum Waiting {
    Rough(Roughing),
    Pattern(Pattern),
}

/// A G71/G72 whose moves wait for its contour: its item, its words.
#[derive(Clone, Copy, Debug)]
pub(in crate::dialect::fanuc) struct Pending {
    item: usize,
    /// The cycle's block, where a refusal is said.
    span: Span,
    p: u32,
    q: u32,
    start: Point,
    cycle: Waiting,
}

impl Pending {
    /// The index of the cycle's item, whose moves the contour's end fills in.
    pub(in crate::dialect::fanuc) fn item(&self) -> usize {
        self.item
    }
}

/// A contour read as moves: its elements so far and the reader's state at its point, or why
/// it cannot be.
#[derive(Clone, Debug)]
pub(in crate::dialect::fanuc) struct Capture {
    elements: Vec<Element>,
    pos: Pos,
    motion: Motion,
    f: Option<FRegister>,
    refused: Option<String>,
}

impl Capture {
    /// Ends the capture with `reason` (the first reason stays).
    pub(super) fn refuse(&mut self, reason: &str) {
        self.refused.get_or_insert_with(|| reason.to_string());
    }
}

/// The contours read as moves, by their P and Q (G70 finishes them).
pub(in crate::dialect::fanuc) type Contours =
    std::collections::HashMap<(u32, u32), Result<Vec<Element>, String>>;

/// What the model gives a cycle's block.
enum Expansion {
    /// Its moves (none for a first block or a G71/G72 whose contour is still to come).
    Moves(Vec<ItemKind>),
    /// Kept as written; the reason when the model covers the cycle.
    Kept(Option<String>),
}

impl From<Result<Vec<ItemKind>, String>> for Expansion {
    /// A cycle's moves, or the reason the model cannot give them.
    fn from(moves: Result<Vec<ItemKind>, String>) -> Expansion {
        match moves {
            Ok(m) => Expansion::Moves(m),
            Err(reason) => Expansion::Kept(Some(reason)),
        }
    }
}

impl FrontEnd<'_> {
    /// Whether the profile declares a machine model.
    pub(super) fn model(&self) -> bool {
        self.profile.cycle_model.declared.is_some()
    }

    /// A cycle's block under the model: pushed with its moves (true), or left to be kept as
    /// written (false; a warning says why when the model covers the cycle).
    pub(super) fn model_block(
        &mut self,
        line: Line<'_>,
        block: &Block,
        words: &Words<'_>,
        g: i64,
        second: bool,
    ) -> bool {
        if !self.model() {
            return false;
        }
        let expansion = match (g, second) {
            (90 | 94, _) => self.turning(line, words, g),
            (70, _) => self.finishing(line, words),
            (71..=73, false) => self.setup(line, words, g),
            (71..=73, true) => self.roughing(line, words, g),
            (74 | 75, false) => self.peck_setup(line, words),
            (74 | 75, true) => self.pecking(line, words, g),
            (76, false) => self.thread_setup(line, words),
            (76, true) => self.threading(line, words),
            (28 | 53, _) => self.machine(line, words, g),
            _ => Expansion::Kept(None),
        };
        match expansion {
            Expansion::Moves(moves) => {
                let span = self.span(line, block.code_range.clone());
                if let Some(p) = self
                    .pending
                    .as_mut()
                    .filter(|p| p.item == self.r.items.len())
                {
                    p.span = span;
                }
                let facing = matches!(g, 72 | 94);
                self.push_model(line, block, g, facing, moves);
                true
            }
            Expansion::Kept(reason) => {
                if let Some(reason) = reason {
                    self.not_expanded(self.span(line, block.code_range.clone()), g, &reason);
                }
                if (71..=73).contains(&g) && second {
                    self.pending = None;
                }
                false
            }
        }
    }

    /// The warning that a cycle the model covers stays kept as written, and why.
    fn not_expanded(&mut self, span: Span, g: i64, reason: &str) {
        self.r.diags.push(
            Diagnostic::new(
                codes::FANR_NOT_EXPANDED,
                format!("the G{:02} cycle is kept as written, not expanded under the machine model: {reason}; converting it to another control is refused", self.profile.gcode_system.code(g)),
            )
            .at(self.r.src, span)
            .help("the FANUC output keeps it as it is; for another control, change the cycle so that the model can expand it, or write its moves"),
        );
    }

    /// Pushes a cycle's block as written with its moves (a contour's block, a first block: none).
    pub(super) fn push_model(
        &mut self,
        line: Line<'_>,
        block: &Block,
        g: i64,
        facing: bool,
        moves: Vec<ItemKind>,
    ) {
        let text = self.cycle_text(line, block);
        let span = self.span(line, block.code_range.clone());
        let cycle = ModelCycle {
            dialect: crate::dialect::fanuc::ID,
            text,
            context: ModalContext {
                inch: self.inch,
                diameter: true,
                incremental: self.incremental,
                per_minute: Some(self.per_minute),
                moves: !moves.is_empty(),
                cycle: true,
                compensation: super::cycles::turns_compensation_on(block),
            },
            code: format!("G{}", self.profile.gcode_system.code(g)),
            facing,
            finishing: g == 70,
            moves,
        };
        self.push(ItemKind::ModelCycle(Box::new(cycle)), span);
        self.sync_end = None;
    }

    /// The cycle's start: where the tool stands, which must be known.
    fn start(&self) -> Result<Point, String> {
        self.r
            .pos
            .known()
            .ok_or_else(|| "the tool's position before it is not known".to_string())
    }

    /// A feed: the block's F, else the one in force.
    fn cycle_feed(&mut self, line: Line<'_>, words: &Words<'_>) -> Result<Length, String> {
        match (words.get('F'), self.f) {
            (Some(w), _) => self
                .length(line, w, Unit::Feed)
                .ok_or_else(|| "its F cannot be read".to_string()),
            (None, Some(FRegister::Feed(f))) => Ok(f),
            _ => Err("no feed is in force and its block has no F".into()),
        }
    }

    /// A word's length, 0 without it.
    fn axis(&mut self, line: Line<'_>, words: &Words<'_>, c: char) -> Result<Length, String> {
        match words.get(c) {
            Some(w) => self
                .length(line, w, Unit::Axis)
                .ok_or_else(|| format!("its {c} cannot be read")),
            None => Ok(Length::ZERO),
        }
    }

    /// G90 / G94, or a block repeating one: the cut's end from X/U and Z/W (a repeat keeps
    /// the last cycle's), its taper R.
    fn turning(&mut self, line: Line<'_>, words: &Words<'_>, g: i64) -> Expansion {
        // The cycle's words are modal while it is in force (FANUC: X, Z and R need not be
        // said again); a cycle the model could not expand leaves none (`take` below).
        if self.kept_modal != Some(g) {
            self.turning = None;
        }
        let moves = (|| {
            let start = self.start()?;
            let last = self.turning.take();
            let get = |c: char| words.get(c);
            let to = self
                .target(line, &get, Pos::new(start.0, start.1))
                .ok_or("its end cannot be read")?;
            let x = to.x.or(last.map(|l| l.0.0)).ok_or("it has no X or U")?;
            let z = to.z.or(last.map(|l| l.0.1)).ok_or("it has no Z or W")?;
            let taper = self.axis(line, words, 'R')?;
            if words.get('R').is_none() && last.is_some_and(|l| l.1 != Length::ZERO) {
                return Err(
                    "it repeats a taper cycle without R: whether the taper stays is the control's"
                        .into(),
                );
            }
            let feed = self.cycle_feed(line, words)?;
            self.turning = Some(((x, z), taper));
            Ok(lowering::turning(start, (x, z), taper, g == 94, feed))
        })();
        moves.into()
    }

    /// A word of G74–G76 written in least input increments (0.001 mm, or 0.0001 in under
    /// G20), without a decimal point.
    fn microns(&mut self, line: Line<'_>, words: &Words<'_>, c: char) -> Result<Length, String> {
        let Some(w) = words.get(c) else {
            return Ok(Length::ZERO);
        };
        if w.value.has_point {
            return Err(format!(
                "its {c} has a decimal point: the cycle's P and Q are in least input increments (0.001 mm, 0.0001 in)"
            ));
        }
        let n = self
            .whole(line, w)
            .ok_or_else(|| format!("its {c} cannot be read"))?;
        Ok(if self.inch {
            Length(n.saturating_mul(Length::INCH_STEP))
        } else {
            Length::from_steps(n.saturating_mul(10))
        })
    }

    /// G74/G75's first block: `R e`, the retract after each peck.
    fn peck_setup(&mut self, line: Line<'_>, words: &Words<'_>) -> Expansion {
        match self.axis(line, words, 'R') {
            Ok(e) => {
                self.peck_retract = Some(e);
                Expansion::Moves(Vec::new())
            }
            Err(reason) => {
                self.peck_retract = None;
                Expansion::Kept(Some(reason))
            }
        }
    }

    /// G74/G75's second block: `X(U) Z(W) P Δi Q Δk R Δd F`, after its first.
    fn pecking(&mut self, line: Line<'_>, words: &Words<'_>, g: i64) -> Expansion {
        let moves = (|| {
            if ['I', 'K', 'D'].iter().any(|&c| words.get(c).is_some()) {
                return Err("Haas's one-block form takes its retract from the machine's Settings, which the model does not hold".to_string());
            }
            let retract = self
                .peck_retract
                .take()
                .ok_or("its first block (R, the retract) is not right before it")?;
            let start = self.start()?;
            let get = |c: char| words.get(c);
            let to = self
                .target(line, &get, Pos::new(start.0, start.1))
                .ok_or("its end cannot be read")?;
            let end = (to.x.unwrap_or(start.0), to.z.unwrap_or(start.1));
            let relief = match words.get('R') {
                Some(w) if !w.value.has_point => {
                    return Err("its R (the relief) has no decimal point: whether R500 is 0.5 mm or 500 mm, the sources ncthread holds disagree".into());
                }
                _ => self.axis(line, words, 'R')?,
            };
            let (i, k) = (
                self.microns(line, words, 'P')?,
                self.microns(line, words, 'Q')?,
            );
            let facing = g == 74;
            let p = Pecking {
                facing,
                end,
                peck: if facing { k } else { i },
                shift: if facing { i } else { k },
                relief,
                retract,
                feed: self.cycle_feed(line, words)?,
            };
            lowering::pecking(start, &p)
        })();
        moves.into()
    }

    /// G76's first block: `P mmrraa Q Δdmin R d`.
    fn thread_setup(&mut self, line: Line<'_>, words: &Words<'_>) -> Expansion {
        let setup = (|| {
            let p = match words.get('P') {
                Some(w) => self.whole(line, w).ok_or("its P cannot be read")?,
                None => return Err("it has no P (mm rr aa)".into()),
            };
            Ok(ThreadSetup {
                finishing: (p / 10_000) as u32,
                chamfer: (p / 100 % 100) as u32,
                angle: (p % 100) as u32,
                min_cut: self.microns(line, words, 'Q')?,
                finish: self.axis(line, words, 'R')?,
            })
        })();
        match setup {
            Ok(s) => {
                self.thread_setup = Some(s);
                Expansion::Moves(Vec::new())
            }
            Err(reason) => {
                self.thread_setup = None;
                Expansion::Kept(Some(reason))
            }
        }
    }

    /// G76's second block: `X(U) Z(W) R i P k Q Δd F L`, after its first.
    fn threading(&mut self, line: Line<'_>, words: &Words<'_>) -> Expansion {
        let moves = (|| {
            if ['K', 'D', 'A', 'I'].iter().any(|&c| words.get(c).is_some()) {
                return Err("Haas's one-block form takes its settings from the machine, which the model does not hold".to_string());
            }
            let setup = self
                .thread_setup
                .take()
                .ok_or("its first block (P mm rr aa, Q, R) is not right before it")?;
            let start = self.start()?;
            let get = |c: char| words.get(c);
            let to = self
                .target(line, &get, Pos::new(start.0, start.1))
                .ok_or("its end cannot be read")?;
            let end = to.known().ok_or("it has no X (U) or Z (W)")?;
            let lead = match words.get('F') {
                Some(w) => self.lead(line, w).ok_or("its F cannot be read")?,
                None => return Err("it has no F, the lead".into()),
            };
            let m = &self.profile.cycle_model;
            let min_cut = m.g76_min_cut.ok_or(
                "the profile's model does not say where Δdmin counts from (`g76_min_cut`)",
            )?;
            let pass_end = m
                .g76_pass_end
                .ok_or("the profile's model does not say where each pass ends (`g76_pass_end`)")?;
            let t = Threading {
                end,
                taper: self.axis(line, words, 'R')?,
                height: self.microns(line, words, 'P')?,
                first: self.microns(line, words, 'Q')?,
                min_cut: setup.min_cut,
                finish: setup.finish,
                finishing: setup.finishing,
                chamfer: setup.chamfer,
                angle: setup.angle,
                lead,
                min_from_actual: min_cut == MinCut::Accumulated,
                end_shifts: pass_end == PassEnd::Shifted,
            };
            lowering::threading(start, &t)
        })();
        moves.into()
    }

    /// G28 (through X/U Z/W to the profile's reference point, the named axes; a bare G28
    /// all), or G53 (a rapid to X Z in machine coordinates).
    fn machine(&mut self, line: Line<'_>, words: &Words<'_>, g: i64) -> Expansion {
        let moves = (|| {
            let from = self.r.pos;
            if g == 53 {
                if self.incremental {
                    return Err("G53 under G91: a move in machine coordinates in incremental mode is not read".to_string());
                }
                if words.get('U').is_some() || words.get('W').is_some() {
                    return Err("G53 takes X and Z in machine coordinates, not U and W".to_string());
                }
                let to = Pos {
                    x: words
                        .get('X')
                        .and_then(|w| self.length(line, w, Unit::Axis)),
                    z: words
                        .get('Z')
                        .and_then(|w| self.length(line, w, Unit::Axis)),
                };
                return Ok(vec![ItemKind::MachineMove(
                    crate::ir::MachineMove::Machine { to, feed: None },
                )]);
            }
            let reference = self.profile.cycle_model.reference_point.ok_or(
                "the profile does not give the reference point in machine coordinates (`reference_point = { x = …, z = … }`)",
            )?;
            // The intermediate point: X/Z, or U/W from where the tool stands (U0 is none).
            let mut via = from;
            let mut named = (false, false);
            for (abs, inc, axis) in [('X', 'U', 0), ('Z', 'W', 1)] {
                let (here, slot) = if axis == 0 {
                    (from.x, &mut via.x)
                } else {
                    (from.z, &mut via.z)
                };
                let value = match (words.get(abs), words.get(inc)) {
                    (Some(w), _) => Some(
                        self.length(line, w, Unit::Axis)
                            .ok_or("its axes cannot be read")?,
                    ),
                    (None, Some(w)) => {
                        let d = self
                            .length(line, w, Unit::Axis)
                            .ok_or("its axes cannot be read")?;
                        match here {
                            _ if d == Length::ZERO => here,
                            Some(h) => Some(h + d),
                            None => return Err("its intermediate point is not known: the tool's position before it is not".into()),
                        }
                    }
                    (None, None) => continue,
                };
                *slot = value;
                if axis == 0 {
                    named.0 = true
                } else {
                    named.1 = true
                }
            }
            let axes = if named == (false, false) {
                (true, true)
            } else {
                named
            };
            Ok(lowering::home(from, via, reference, axes))
        })();
        moves.into()
    }

    /// G70: the contour P–Q read before, with its own feeds (the G70's F where the contour
    /// writes none), then back to the start.
    fn finishing(&mut self, line: Line<'_>, words: &Words<'_>) -> Expansion {
        let at_call = self.comp;
        let moves = (|| {
            let (p, q) = self.p_q(line, words).ok_or("its P or Q cannot be read")?;
            let contour = self
                .contours
                .get(&(p, q))
                .ok_or("its contour was not read before it as a G71 or G72 contour")?
                .clone()?;
            // G70 runs the contour's G40–G42 as any block (a `G42 G00 X42. Z2.` before it
            // compensates its moves, as textbooks write it): the mode after it is the last,
            // whether or not the model expands it.
            if let Some(c) = contour.iter().rev().find_map(|e| e.comp) {
                self.comp = c;
            }
            let start = self.start()?;
            let f = words
                .get('F')
                .and_then(|w| self.length(line, w, Unit::Feed));
            let mut elements = contour;
            for e in &mut elements {
                if !e.rapid && e.feed == UNSET_FEED {
                    e.feed = f.ok_or(
                        "a move of its contour has no F of its own (the contour's F words, or the G70's, are the feed)",
                    )?;
                }
            }
            Ok(lowering::finishing(start, &elements, at_call))
        })();
        moves.into()
    }

    /// The P and Q of a cycle's block.
    fn p_q(&mut self, line: Line<'_>, words: &Words<'_>) -> Option<(u32, u32)> {
        let p = self.whole(line, words.get('P')?)?;
        let q = self.whole(line, words.get('Q')?)?;
        Some((u32::try_from(p).ok()?, u32::try_from(q).ok()?))
    }

    /// A G71/G72's first block: its depth (U for G71, W for G72), retract R and F; a G73's:
    /// its relief U W, passes R and F.
    fn setup(&mut self, line: Line<'_>, words: &Words<'_>, g: i64) -> Expansion {
        let setup = (|| {
            let (mut depth, mut retract, mut relief, mut passes) =
                (Length::ZERO, Length::ZERO, (Length::ZERO, Length::ZERO), 0);
            if g == 73 {
                relief = (self.axis(line, words, 'U')?, self.axis(line, words, 'W')?);
                let r = words.get('R').ok_or("it has no R, the number of passes")?;
                passes = self
                    .whole(line, r)
                    .and_then(|n| u32::try_from(n).ok())
                    .ok_or("its R cannot be read")?;
            } else {
                depth = self.axis(line, words, if g == 71 { 'U' } else { 'W' })?;
                retract = self.axis(line, words, 'R')?;
            }
            let feed = match words.get('F') {
                Some(w) => Some(
                    self.length(line, w, Unit::Feed)
                        .ok_or("its F cannot be read")?,
                ),
                None => None,
            };
            Ok::<_, String>(Setup {
                g,
                depth,
                retract,
                relief,
                passes,
                feed,
            })
        })();
        match setup {
            Ok(s) => {
                self.setup = Some(s);
                Expansion::Moves(Vec::new())
            }
            Err(reason) => Expansion::Kept(Some(reason)),
        }
    }

    /// Haas's one-block forms: G71/G72 (`G71 P Q U W D F`), D the depth of cut (a radius
    /// for G71), the retract the machine's Setting 73 (`haas_setting_73`), its I and K (a
    /// rough pass allowance) not expanded; G73 (`G73 P Q U W I K D F`), I and K the relief
    /// from the first pass to the last (I a radius), D the number of passes.
    fn haas_setup(&mut self, line: Line<'_>, words: &Words<'_>, g: i64) -> Result<Setup, String> {
        self.setup = None;
        if g == 73 {
            let d = words.get('D').ok_or("it has no D, the number of passes")?;
            let passes = (!d.value.has_point)
                .then(|| d.value.to_whole().ok())
                .flatten()
                .and_then(|n| u32::try_from(n).ok())
                .ok_or("its D (the number of passes) is not a whole number")?;
            return Ok(Setup {
                g,
                depth: Length::ZERO,
                retract: Length::ZERO,
                relief: (self.axis(line, words, 'I')?, self.axis(line, words, 'K')?),
                passes,
                feed: None,
            });
        }
        if words.get('I').is_some() || words.get('K').is_some() {
            return Err(
                "Haas's rough pass allowance (I, K) is not expanded by this version".into(),
            );
        }
        let retract = self.profile.cycle_model.haas_setting_73.ok_or(
            "Haas's one-block form takes its retract after each layer from the machine's Setting 73 (287 on the NGC), which the profile does not give (`haas_setting_73`)",
        )?;
        let depth = self.axis(line, words, 'D')?;
        if depth <= Length::ZERO {
            return Err("its D, the depth of cut, is not positive".into());
        }
        Ok(Setup {
            g,
            depth,
            retract,
            relief: (Length::ZERO, Length::ZERO),
            passes: 0,
            feed: None,
        })
    }

    /// A G71/G72's second block: its words now, its moves when its contour has been read.
    fn roughing(&mut self, line: Line<'_>, words: &Words<'_>, g: i64) -> Expansion {
        let pending = (|| {
            let setup = match words.get('D') {
                Some(_) => self.haas_setup(line, words, g)?,
                None => self.setup.take().filter(|s| s.g == g).ok_or(
                    "its first block (the depth of cut and the retract) is not right before it",
                )?,
            };
            // The contour's own G40–G42 are not run in roughing (GSK 980TDi).
            roughing_compensation(self.comp != Compensation::Off)?;
            let start = self.start()?;
            let (p, q) = self.p_q(line, words).ok_or("its P or Q cannot be read")?;
            let allowance = (self.axis(line, words, 'U')?, self.axis(line, words, 'W')?);
            let feed = match (words.get('F'), setup.feed) {
                (None, Some(f)) => f,
                _ => self.cycle_feed(line, words)?,
            };
            if g == 73 {
                match self.profile.cycle_model.g73_divisor {
                    Some(G73Divisor::PassesMinusOne) => {}
                    Some(G73Divisor::Passes) => return Err("a relief spread by the passes (`g73_divisor = \"passes\"`) is not expanded by this version".into()),
                    None => return Err("the profile's model does not say how the relief is spread over the passes (`g73_divisor`)".into()),
                }
                let cycle = Waiting::Pattern(Pattern {
                    relief: setup.relief,
                    passes: setup.passes,
                    allowance,
                    feed,
                });
                return Ok(Pending {
                    item: self.r.items.len(),
                    span: Span::default(),
                    p,
                    q,
                    start,
                    cycle,
                });
            }
            let m = &self.profile.cycle_model;
            let open = |what: &str, key: &str| {
                format!("the profile's model does not say {what} (`{key}`)")
            };
            let retract_rapid = m
                .g71_retract
                .ok_or_else(|| open("how the retract after a layer moves", "g71_retract"))?
                == Retract::Rapid;
            let from_shifted = m
                .g71_layers_from
                .ok_or_else(|| open("where the layers are counted from", "g71_layers_from"))?
                == LayersFrom::ShiftedStart;
            let semi_finish = m.g71_semi_finish.ok_or_else(|| {
                open(
                    "whether a semi-finish pass follows the layers",
                    "g71_semi_finish",
                )
            })?;
            Ok(Pending {
                item: self.r.items.len(),
                span: Span::default(),
                p,
                q,
                start,
                cycle: Waiting::Rough(Roughing {
                    facing: g == 72,
                    depth: setup.depth,
                    retract: setup.retract,
                    allowance,
                    feed,
                    retract_rapid,
                    from_shifted,
                    semi_finish,
                }),
            })
        })();
        match pending {
            Ok(p) => {
                self.pending = Some(p);
                Expansion::Moves(Vec::new())
            }
            Err(reason) => Expansion::Kept(Some(reason)),
        }
    }

    /// A new contour's capture, from the cycle's start.
    pub(super) fn capture(&self) -> Option<Capture> {
        self.model().then(|| Capture {
            elements: Vec::new(),
            pos: self.r.pos,
            motion: Motion::Rapid,
            f: Some(FRegister::Feed(UNSET_FEED)),
            refused: None,
        })
    }

    /// A contour's block read as moves into its capture: by the block interpreter, from the
    /// contour's point, the reader's state put back after. A word the capture does not take
    /// (S, T, M, a mode, a corner), or any error, ends it with the reason.
    pub(super) fn capture_block(&mut self, line: Line<'_>, block: &Block) {
        let Some(mut cap) = self.capturing.take() else {
            return;
        };
        if cap.refused.is_none() {
            self.capture_words(line, block, &mut cap);
        }
        self.capturing = Some(cap);
    }

    /// [`Self::capture_block`]'s reading of one block into `cap`.
    fn capture_words(&mut self, line: Line<'_>, block: &Block, cap: &mut Capture) {
        // G40–G42: the GSK 980TDi runs them in G70 and not in G71–G73 (its manual, G71's and
        // G73's notes).
        if let Some(w) = block.words.iter().find(|w| match w.letter {
            'G' => !matches!(w.value.to_whole(), Ok(0..=3 | 40..=42)) || w.value.has_point,
            l => !"XZUWIKRF".contains(l),
        }) {
            let text = &line.text[w.range.clone()];
            cap.refused = Some(format!(
                "its contour's `{text}` is not expanded by this version (a contour of G00–G03 moves with X Z U W I K R F, and G40–G42, is)"
            ));
            return;
        }
        if block.words.is_empty() {
            return;
        }
        let saved = (
            self.r.pos,
            self.motion,
            self.f,
            self.motion_after_cycle.take(),
            self.kept_modal.take(),
            self.cycle_mode_only.take(),
            self.sync_end,
            self.moved,
            self.comp,
        );
        (self.r.pos, self.motion, self.f) = (cap.pos, cap.motion, cap.f);
        let at = cap.pos;
        let (first, diags) = (self.r.items.len(), self.r.diags.len());
        let span = self.span(line, block.code_range.clone());
        let _ = self.read_block(line, block, span);
        let items = self.r.items.split_off(first);
        let errors: Vec<Diagnostic> = self.r.diags.split_off(diags);
        (cap.pos, cap.motion, cap.f) = (self.r.pos, self.motion, self.f);
        (
            self.r.pos,
            self.motion,
            self.f,
            self.motion_after_cycle,
            self.kept_modal,
            self.cycle_mode_only,
            self.sync_end,
            self.moved,
            self.comp,
        ) = saved;
        if let Some(e) = errors.iter().find(|d| d.is_error()) {
            cap.refused = Some(format!(
                "its contour's block cannot be read as a move: {}",
                e.message
            ));
            return;
        }
        match elements_of(items, at) {
            Ok(elements) => cap.elements.extend(elements),
            Err(reason) => cap.refused = Some(reason),
        }
    }

    /// The contour's last block has been read: its moves kept for G70, and the G71/G72 that
    /// waits for it given its moves (or kept as written, with the reason).
    pub(super) fn contour_done(&mut self, (p, q): (u32, u32), type_one: bool) {
        let Some(cap) = self.capturing.take() else {
            return;
        };
        let contour = match cap.refused {
            Some(reason) => Err(reason),
            None => Ok(cap.elements),
        };
        self.contours.insert((p, q), contour.clone());
        let Some(p) = self.pending.take().filter(|w| (w.p, w.q) == (p, q)) else {
            return;
        };
        let (g, moves) = match p.cycle {
            Waiting::Pattern(pattern) => (
                73,
                contour.and_then(|e| lowering::pattern(p.start, &e, &pattern)),
            ),
            Waiting::Rough(rough) => (
                if rough.facing { 72 } else { 71 },
                contour
                    .and_then(|e| match type_one {
                        true => Ok(e),
                        false => Err("its contour is not type I (monotone, its first block moving across the cut only)".to_string()),
                    })
                    .and_then(|e| lowering::roughing(p.start, &e, &rough)),
            ),
        };
        if let Err(reason) = &moves {
            self.r.pos = Pos::UNKNOWN;
            self.not_expanded(p.span, g, reason);
        }
        // The item: held while the cycle waits for its contour ([`FrontEnd::line_read`]).
        let Some(item) = self.r.items.held_mut(p.item) else {
            return;
        };
        let ItemKind::ModelCycle(cycle) = &mut item.kind else {
            return;
        };
        match moves {
            Ok(moves) => {
                cycle.context.moves = true;
                cycle.moves = moves;
            }
            Err(_) => {
                item.kind = ItemKind::Opaque {
                    dialect: crate::dialect::fanuc::ID,
                    text: cycle.text.clone(),
                    block: Some(ModalContext {
                        moves: true,
                        ..cycle.context
                    }),
                };
            }
        }
    }
}

/// A roughing cycle (G71–G73) under the model: no compensation in force at it (the GSK
/// 980TDi manual's section on a roughing cycle under compensation was not reached; its
/// contour's own G40–G42 are not run in roughing).
fn roughing_compensation(on_at_call: bool) -> Result<(), String> {
    if on_at_call {
        return Err("tool nose radius compensation (G41/G42) is in force at the roughing cycle: how the model roughs under it is not documented".into());
    }
    Ok(())
}

/// A contour block's items as elements, from `at`: its moves (an end as written may name one
/// axis; an F alone is no move). Anything else, or a point not known, is the reason it is not.
fn elements_of(items: Vec<crate::ir::Item>, mut at: Pos) -> Result<Vec<Element>, String> {
    let mut elements = Vec::new();
    // A G40–G42 before the block's move.
    let mut comp = None;
    for item in items {
        let to = item.kind.end_position(at);
        at = to;
        let element = match item.kind {
            ItemKind::Compensation(c) => {
                comp = Some(c);
                continue;
            }
            ItemKind::Rapid { .. } => to.known().map(|to| Element {
                to,
                arc: None,
                rapid: true,
                feed: UNSET_FEED,
                comp: comp.take(),
            }),
            ItemKind::Feed { feed, .. } => to.known().map(|to| Element {
                to,
                arc: None,
                rapid: false,
                feed,
                comp: comp.take(),
            }),
            ItemKind::Arc {
                centre,
                clockwise,
                feed,
                ..
            } => to.known().zip(centre.known()).map(|(to, c)| Element {
                to,
                arc: Some((c, clockwise)),
                rapid: false,
                feed,
                comp: comp.take(),
            }),
            ItemKind::FeedRate(_) => continue,
            _ => None,
        };
        elements.push(element.ok_or("its contour's points are not all known")?);
    }
    if comp.is_some() {
        return Err("its contour switches compensation (G40–G42) in a block without a move".into());
    }
    Ok(elements)
}

#[cfg(test)]
mod tests {
    use crate::diag::Diagnostic;
    use crate::dialect::Unsupported;
    use crate::ir::{Compensation, Item, ItemKind, Pos};
    use crate::profile::Profile;
    use crate::source::SourceFile;

    const GSK: &str = "[fanuc]\ncycle_model = \"gsk-980tdi\"\n";

    fn read(profile: &str, body: &str) -> (Vec<Item>, Vec<Diagnostic>) {
        let text = format!("G21 G99\nT0101\nG97 S800 M03\nG00 X52. Z2.\n{body}M30\n");
        let profile = Profile::from_toml(&SourceFile::new("p.toml", profile)).unwrap();
        let (p, d) = super::super::parse(
            &SourceFile::new("t", &text),
            &profile.fanuc,
            Unsupported::Error,
        );
        (p.items, d)
    }

    /// Each diagnostic's code, line and whether it is an error.
    fn said(d: &[Diagnostic]) -> Vec<(&str, u32, bool)> {
        d.iter()
            .map(|d| {
                let line = d.location.as_ref().map_or(0, |l| l.line);
                (d.code.id, line, d.is_error())
            })
            .collect()
    }

    /// The blocks with moves under the model, and how many each has.
    fn expanded(items: &[Item]) -> Vec<(String, usize)> {
        items
            .iter()
            .filter_map(|i| match &i.kind {
                ItemKind::ModelCycle(c) if !c.moves.is_empty() => {
                    Some((c.text.clone(), c.moves.len()))
                }
                _ => None,
            })
            .collect()
    }

    /// Under the model a G90, its repeat, a G71 (once its contour is read) and a G70 have
    /// their moves; each ends where it started, so the position stays known.
    #[test]
    fn the_model_gives_the_cycles_their_moves() {
        let (items, d) = read(
            GSK,
            "G90 X48. Z-30. F0.25\nG90 X44.\nG00 X52. Z2.\nG71 U2. R0.5\nG71 P80 Q100 U0.4 W0.1 F0.25\nN80 G00 X30.\nN90 G01 Z-20. F0.15\nN100 X52.\nG70 P80 Q100\n",
        );
        assert_eq!(said(&d), [], "{d:?}");
        // G71: A', 4 moves for each of the layers Ø48.4 … Ø32.4 (5), the infeed to B',
        // 2 contour moves, the rapid back. G70: 3 contour moves and the rapid back.
        let want = [
            ("G90 X48. Z-30. F0.25", 4),
            ("G90 X44.", 4),
            ("G71 P80 Q100 U0.4 W0.1 F0.25", 1 + 5 * 4 + 1 + 2 + 1),
            ("G70 P80 Q100", 4),
        ]
        .map(|(t, n)| (t.to_string(), n));
        assert_eq!(expanded(&items), want);
        let end = items
            .iter()
            .fold(Pos::UNKNOWN, |at, i| i.kind.end_position(at));
        assert_eq!(
            end.known().map(|(x, z)| (
                x.0 / crate::fixed::Length::STEP,
                z.0 / crate::fixed::Length::STEP
            )),
            Some((520_000, 20_000))
        );
    }

    /// What the model does not expand is kept as written, with a warning that says why; the
    /// program still reads.
    #[test]
    fn what_the_model_cannot_expand_is_kept_with_its_reason() {
        let contour = "N80 G00 X30.\nN90 G01 Z-20. F0.15\nN100 X52.\n";
        let cases: Vec<(String, u32, &str)> = vec![
            (
                "G90 X40. Z-20. R-2. F0.2\nX38.\n".into(),
                6,
                "without R",
            ),
            // After a G90 the model could not expand, the position is not known.
            (
                "G90 X40. Z-20. R-1. F0.2\nG90 X36. Z-15.\nX38.\n".into(),
                7,
                "not known",
            ),
            (
                format!("G71 P80 Q100 U0.4 W0.1 D2. F0.25\n{contour}"),
                5,
                "Haas's one-block form",
            ),
            (
                format!("G71 P80 Q100 U0.4 W0.1 F0.25\n{contour}"),
                5,
                "its first block",
            ),
            (
                "G71 U2. R0.5\nG71 P80 Q100 U0.4 W0.1 F0.25\nN80 G00 X30. Z1.\nN90 G01 Z-20. F0.15\nN100 X52.\n".into(),
                6,
                "not type I",
            ),
            (
                "G71 U2. R0.5\nG71 P80 Q100 U-0.4 W0.1 F0.25\nN80 G00 X30.\nN90 G01 Z-20. F0.15\nN100 X52.\n".into(),
                6,
                "into the part",
            ),
            (
                "G71 U2. R0.5\nG71 P80 Q100 U0.4 W0.1 F0.25\nN80 G00 X30.\nN90 G01 Z-20.\nN100 X52.\nG70 P80 Q100\n".into(),
                10,
                "no F of its own",
            ),
            (
                "G71 U2. R0.5\nG71 P80 Q100 U0.4 W0.1 F0.25\nN80 G00 X30.\nN90 G01 Z-20. F0.15 S900\nN100 X52.\n".into(),
                6,
                "`S900` is not expanded",
            ),
        ];
        for (body, line, why) in cases {
            let (_, d) = read(GSK, &body);
            let warnings: Vec<_> = d.iter().filter(|d| d.code.id == "FANR021").collect();
            assert!(
                warnings.iter().any(|w| w.message.contains(why)
                    && w.location.as_ref().is_some_and(|l| l.line == line)
                    && !w.is_error()),
                "{body:?}: {d:?}"
            );
            assert!(!d.iter().any(|d| d.is_error()), "{body:?}: {d:?}");
        }
    }

    /// G73 passes and G28 to the profile's reference point: its intermediate point only
    /// where it moves, the named axes only; without the point, G28 is kept with the reason.
    #[test]
    fn g73_and_g28_under_the_model() {
        let with_point = format!("{GSK}reference_point = {{ x = 250.0, z = 300.0 }}\n");
        let (items, d) = read(
            &with_point,
            "G73 U3. W0. R3\nG73 P80 Q90 U0.4 W0.1 F0.2\nN80 G00 X20. Z1.\nN90 G01 Z-10.\nG28 U0. W0.\nG28 U0.\nG28 X60. W0.\n",
        );
        assert_eq!(said(&d), [], "{d:?}");
        let machine = |m: &ItemKind| match m {
            ItemKind::MachineMove(crate::ir::MachineMove::Machine { to, .. }) => Some((
                to.x.map(|x| x.0 / crate::fixed::Length::STEP),
                to.z.map(|z| z.0 / crate::fixed::Length::STEP),
            )),
            _ => None,
        };
        let cycles: Vec<_> = items
            .iter()
            .filter_map(|i| match &i.kind {
                ItemKind::ModelCycle(c) if !c.moves.is_empty() => Some(c),
                _ => None,
            })
            .collect();
        // G73: 3 passes of a rapid to the moved start and the 2 contour moves, a rapid back.
        assert_eq!(cycles[0].moves.len(), 3 * 3 + 1);
        assert_eq!(
            machine(&cycles[1].moves[0]),
            Some((Some(2_500_000), Some(3_000_000)))
        );
        // After the first G28 the position is not known: U0. still names X alone.
        assert_eq!(cycles[2].moves.len(), 1);
        assert_eq!(machine(&cycles[2].moves[0]), Some((Some(2_500_000), None)));
        // X60.: a rapid there first, then both axes home.
        assert!(
            matches!(&cycles[3].moves[0], ItemKind::Rapid { to } if to.x.unwrap().0 == 600_000 * crate::fixed::Length::STEP)
        );
        assert_eq!(
            machine(&cycles[3].moves[1]),
            Some((Some(2_500_000), Some(3_000_000)))
        );
        let (_, d) = read(GSK, "G28 U0. W0.\n");
        assert!(
            d.iter()
                .any(|d| d.code.id == "FANR021" && d.message.contains("`reference_point")),
            "{d:?}"
        );
        let (_, d) = read(
            GSK,
            "G73 U3. W0. R1\nG73 P80 Q90 U0.4 W0.1 F0.2\nN80 G00 X20. Z1.\nN90 G01 Z-10.\n",
        );
        assert!(d.iter().any(|d| d.message.contains("R1")), "{d:?}");
    }

    /// A cycle kept whole for FANUC still needs the spindle for its moves (LG001), as its
    /// moves do for any other target.
    #[test]
    fn a_cycle_kept_for_fanuc_is_checked_for_the_spindle() {
        let text = "G21 G99\nT0101\nG00 X26. Z5.\nG76 P010060 Q100 R0.05\nG76 X18.16 Z-20. P920 Q400 F1.5\nM30\n";
        let src = SourceFile::new("t", text);
        let profile = Profile::from_toml(&SourceFile::new("p.toml", GSK)).unwrap();
        let (p, d) = super::super::parse(&src, &profile.fanuc, Unsupported::Error);
        assert_eq!(said(&d), [], "{d:?}");
        let fanuc = crate::dialect::fanuc::ID;
        let errors =
            crate::legalise::check(&crate::lower::unroll(&p, Some(fanuc)), &src, Some(fanuc));
        assert_eq!(said(&errors), [("LG001", 5, true)], "{errors:?}");
    }

    /// The open points one by one: a G71 waits for each of its keys, named in the reason.
    #[test]
    fn each_open_point_is_named_when_the_profile_leaves_it() {
        let body = "G71 U2. R0.5\nG71 P80 Q100 U0.4 W0.1 F0.25\nN80 G00 X30.\nN90 G01 Z-20. F0.15\nN100 X52.\n";
        let (_, d) = read("[fanuc]\ng71_retract = \"rapid\"\n", body);
        assert!(
            d.iter().any(|d| d.message.contains("`g71_layers_from`")),
            "{d:?}"
        );
        let all = "[fanuc]\ng71_retract = \"rapid\"\ng71_layers_from = \"start\"\ng71_semi_finish = true\n";
        let (items, d) = read(all, body);
        assert_eq!(said(&d), [], "{d:?}");
        // From the start itself: no move to A' first; each retract a rapid.
        let moves = items
            .iter()
            .find_map(|i| match &i.kind {
                ItemKind::ModelCycle(c) if !c.moves.is_empty() => Some(c.moves.clone()),
                _ => None,
            })
            .unwrap();
        assert!(
            matches!(&moves[0], ItemKind::Rapid { to } if to.x.unwrap().0 == 480_000 * crate::fixed::Length::STEP)
        );
        assert!(matches!(&moves[2], ItemKind::Rapid { .. }), "{moves:?}");
    }

    /// A model the profile names that ncthread does not know, and a bad value, are refused
    /// at their line.
    /// An inch G76 (and G75) cuts what the same cycle in millimetres cuts: its P and Q are in 0.0001 in
    /// (least input increments), the rest in inches. Every value is a multiple of 0.005 in,
    /// exact in 0.001 mm.
    #[test]
    fn inch_g75_and_g76_are_the_millimetre_ones_in_inches() {
        let run = |text: &str| {
            let profile = Profile::from_toml(&SourceFile::new("p.toml", GSK)).unwrap();
            let (p, d) = super::super::parse(
                &SourceFile::new("t", text),
                &profile.fanuc,
                Unsupported::Error,
            );
            assert_eq!(said(&d), [], "{d:?}");
            let moves: Vec<ItemKind> = p
                .items
                .iter()
                .filter_map(|i| match &i.kind {
                    ItemKind::ModelCycle(c) => Some(c.moves.clone()),
                    _ => None,
                })
                .flatten()
                .collect();
            assert!(moves.len() > 4, "{moves:?}");
            moves
        };
        let inch = run(
            "G20 G99\nT0101\nG97 S600 M03\nG00 X1.1 Z0.25\nG76 P010060 Q0050 R0.005\nG76 X0.9 Z-1. P0500 Q0200 F0.125\nM30\n",
        );
        let mm = run(
            "G21 G99\nT0101\nG97 S600 M03\nG00 X27.94 Z6.35\nG76 P010060 Q127 R0.127\nG76 X22.86 Z-25.4 P1270 Q508 F3.175\nM30\n",
        );
        assert_eq!(inch, mm);
        // G75 likewise: P and Q in 0.0001 in, R and the axes in inches.
        let inch = run(
            "G20 G99\nT0101\nG97 S600 M03\nG00 X1.1 Z-1.\nG75 R0.01\nG75 X0.75 Z-1.625 P0500 Q1250 F0.004\nM30\n",
        );
        let mm = run(
            "G21 G99\nT0101\nG97 S600 M03\nG00 X27.94 Z-25.4\nG75 R0.254\nG75 X19.05 Z-41.275 P1270 Q3175 F0.1016\nM30\n",
        );
        assert_eq!(inch, mm);
    }

    #[test]
    fn the_profile_names_a_known_model_and_values() {
        for (toml, key) in [
            ("[fanuc]\ncycle_model = \"fanuc-0i\"\n", "cycle_model"),
            ("[fanuc]\ng71_retract = \"slow\"\n", "g71_retract"),
        ] {
            let e = Profile::from_toml(&SourceFile::new("p.toml", toml)).unwrap_err();
            assert!(e[0].message.contains(key), "{e:?}");
            assert_eq!(e[0].location.as_ref().map(|l| l.line), Some(2));
        }
    }

    /// G41/G42/G40 in a contour (GSK 980TDi: not run in G71–G73, run in G70): the roughing
    /// ignores them, G70 switches them before its moves. A compensation already on at a
    /// roughing cycle keeps it as written, with its reason; a G70 runs under it.
    #[test]
    fn compensation_in_a_contour_runs_in_g70_only() {
        let contour = "N80 G00 G42 X30.\nN90 G01 Z-20. F0.15\nN100 G40 X52.\n";
        let (items, d) = read(
            GSK,
            &format!("G71 U2. R0.5\nG71 P80 Q100 U0.4 W0.1 F0.25\n{contour}G70 P80 Q100\n"),
        );
        assert!(d.is_empty(), "{d:?}");
        let cycles: Vec<&crate::ir::ModelCycle> = items
            .iter()
            .filter_map(|i| match &i.kind {
                ItemKind::ModelCycle(c) if !c.moves.is_empty() => Some(&**c),
                _ => None,
            })
            .collect();
        let comp = |c: &crate::ir::ModelCycle| {
            c.moves
                .iter()
                .filter(|m| matches!(m, ItemKind::Compensation(_)))
                .count()
        };
        assert_eq!(cycles.len(), 2);
        assert_eq!((comp(cycles[0]), comp(cycles[1])), (0, 2));
        assert!(matches!(
            cycles[1].moves[0],
            ItemKind::Compensation(crate::ir::Compensation::FromTool { right: true, .. })
        ));
        // A roughing cycle under a compensation switched on before it is kept as written.
        let body = format!("G42 G00 X52.\nG71 U2. R0.5\nG71 P80 Q100 U0.4 W0.1 F0.25\n{contour}");
        let (_, d) = read(GSK, &body);
        assert!(
            d.iter()
                .any(|d| d.code.id == "FANR021"
                    && d.message.contains("in force at the roughing cycle")),
            "{d:?}"
        );
        // A G70 under a compensation switched on before it (the textbooks' `G42 G00 X42. Z2.`,
        // `G70 P Q`, `G40`): its moves run under it.
        let (items, d) = read(
            GSK,
            "G71 U2. R0.5\nG71 P80 Q100 U0.4 W0.1 F0.25\nN80 G00 X30.\nN90 G01 Z-20. F0.15\nN100 X52.\nG42 G00 X52. Z2.\nG70 P80 Q100\nG40 G00 X60.\n",
        );
        assert!(d.is_empty(), "{d:?}");
        assert_eq!(expanded(&items).len(), 2);
        // Its contour's own G42 then changes nothing (modal; LinuxCNC refuses a second one),
        // its G40 switches it off.
        let (items, d) = read(
            GSK,
            &format!(
                "G71 U2. R0.5\nG71 P80 Q100 U0.4 W0.1 F0.25\n{contour}G42 G00 X52. Z2.\nG70 P80 Q100\n"
            ),
        );
        assert!(d.is_empty(), "{d:?}");
        let switches: Vec<&ItemKind> = items
            .iter()
            .flat_map(|i| match &i.kind {
                ItemKind::ModelCycle(c) => c.moves.iter().collect::<Vec<_>>(),
                k => vec![k],
            })
            .filter(|k| matches!(k, ItemKind::Compensation(_)))
            .collect();
        assert_eq!(switches.len(), 2, "{switches:?}");
        assert_eq!(switches[1], &ItemKind::Compensation(Compensation::Off));
        // Outside a cycle too.
        let (items, _) = read(GSK, "G42 G00 X30. Z2.\nG42 G01 Z-10. F0.2\nG40 G00 X52.\n");
        let n = items
            .iter()
            .filter(|i| matches!(i.kind, ItemKind::Compensation(_)))
            .count();
        assert_eq!(n, 2);
    }
}

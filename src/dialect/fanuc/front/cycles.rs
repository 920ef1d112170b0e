//! FANUC's canned cycles and its moves to the reference point, kept as written.
//!
//! Real FANUC lathe programs rough with `G71`/`G72`/`G73` and finish with `G70`, groove and
//! peck with `G74`/`G75`, thread with `G76`, turn and face with `G90`/`G94`, and go home with
//! `G28 U0 W0`. Their moves depend on points FANUC does not publish (spec fanuc.md, "Canned
//! cycles under a declared machine model"), so without a model the reader does not say them:
//! it reads each cycle, checks what is known without a model (the words each form takes, P and
//! Q naming blocks that exist once, a roughing contour that follows its cycle and holds
//! G00–G03 moves only, monotone for type I, G76's P in range) and keeps its blocks as written.
//! The FANUC writer writes them back; every other target refuses them by name (legalise,
//! [`crate::ir::ModalContext::cycle`]). After a cycle that moves, the position is unknown, and
//! so is the feed after G70–G73 (the contour's F words run in G70).

use super::block::Words;
use super::{FRegister, FrontEnd, Unit};
use crate::dialect::fanuc::codes;
use crate::dialect::fanuc::profile::GcodeSystem;
use crate::dialect::fanuc::syntax::{Block, Word};
use crate::fixed::Length;
use crate::ir::ModalContext;
use crate::source::{Line, Span};

/// The words a cycle's form takes (`second`: the block that runs it, not a two-block form's
/// first).
fn form(g: i64, second: bool) -> &'static str {
    match g {
        // U, W and D as Haas's own example programs write them; S the speed it runs at.
        70 => "PQFUWDS",
        // Haas's one-block forms: G71/G72 D the depth, I K a rough pass allowance; G73 I K
        // the relief, D the passes.
        71..=73 if second => "PQUWDFSIK",
        // The first block: the depth of cut (U for G71, W for G72) and the retract; F there
        // too in real programs.
        71 => "URF",
        72 => "WRF",
        73 => "UWRF",
        // I and K: Haas's one-block form (the peck and the step).
        74 | 75 if second => "XZUWPQRFIKDS",
        74 | 75 => "R",
        76 if second => "XZUWRPQFKDAIS",
        76 => "PQR",
        90 | 94 => "XZUWRFS",
        30 => "XZUWP",
        28 => "XZUW",
        _ => "XZ",
    }
}

/// A value a cycle's word must have, known without a model.
#[derive(Clone, Copy)]
enum Check {
    /// A block number, N1 to N99999.
    Block,
    /// A depth of cut, more than 0.
    Depth,
    /// A number of passes, 1 or more.
    Passes,
    /// G76's P: mm rr aa.
    G76P,
}

impl Check {
    /// Why a value fails, and the help.
    fn words(self) -> (&'static str, &'static str) {
        match self {
            Check::Block => ("not a block number", "block numbers are N1 to N99999"),
            Check::Depth => (
                "the depth of cut must be more than 0",
                "`G71 U2. R0.5` (`G72 W2. R0.5`): the depth of each cut, then the retract",
            ),
            Check::Passes => (
                "the number of passes must be 1 or more",
                "`G73 U3. W0. R3`: R the number of passes",
            ),
            Check::G76P => (
                "P is six digits mm rr aa: the finishing passes mm (01–99), the chamfer rr (00–99, in 0.1 lead) and the tool angle aa (80, 60, 55, 30, 29 or 00)",
                "`G76 P020060 Q100 R0.05`: 2 finishing passes, no chamfer, a 60° tool",
            ),
        }
    }
}

/// The words of cycle `g` whose values are checked.
fn value_checks(g: i64, second: bool) -> &'static [(char, Check)] {
    match (g, second) {
        (71 | 72, true) => &[
            ('P', Check::Block),
            ('Q', Check::Block),
            ('D', Check::Depth),
        ],
        (73, true) => &[
            ('P', Check::Block),
            ('Q', Check::Block),
            ('D', Check::Passes),
        ],
        (70, true) => &[('P', Check::Block), ('Q', Check::Block)],
        (71, false) => &[('U', Check::Depth)],
        (72, false) => &[('W', Check::Depth)],
        (73, false) => &[('R', Check::Passes)],
        (76, false) => &[('P', Check::G76P)],
        _ => &[],
    }
}

/// What each cycle is, for messages.
fn name(g: i64, system: GcodeSystem) -> String {
    let what = match g {
        70 => "finishing cycle",
        71 => "turning cycle",
        72 => "facing cycle",
        73 => "pattern repeating cycle",
        74 => "face grooving (peck drilling) cycle",
        75 => "grooving cycle",
        76 => "threading cycle",
        90 => "turning cycle",
        94 => "facing cycle",
        28 => "return to the reference point",
        30 => "return to a reference point",
        _ => "move in machine coordinates",
    };
    format!("G{:02} {what}", system.code(g))
}

/// The contour of a G71, G72 or G73 (the blocks P to Q that follow it): read block by block
/// until the block numbered Q.
pub(super) struct Contour {
    g: i64,
    p: u32,
    q: u32,
    /// The cycle's block, where a contour that never ends is reported.
    span: Span,
    /// No block of the contour read yet (the first must be numbered P).
    numbered: bool,
    /// No block with words read yet (the first must say G00 or G01).
    first: bool,
    /// The contour's point (X a diameter), while known.
    at: (Option<Length>, Option<Length>),
    /// The sign of the X and Z steps seen after the first block (0: none yet).
    dir: (i64, i64),
    /// G71/G72 type I (its first block moves only across the cut): monotone in X and Z.
    type_one: bool,
    /// The contour's own G00–G03.
    motion: i64,
    /// An F word in the contour.
    feeds: bool,
    /// The F in force after the cycle when its contour has no F word: the cycle's own, else
    /// the one before it.
    f_after: Option<FRegister>,
}

/// A P or Q that names a block, checked when the whole program has been read.
pub(super) struct Reference {
    n: u32,
    span: Span,
    text: String,
    g: i64,
}

impl FrontEnd<'_> {
    /// A block with a kept cycle code (`code`, with its word `at` when the block writes it; a
    /// G90/G94 repeat block has none): checked and kept as written. The steps after it do
    /// not run.
    pub(super) fn kept_cycle(
        &mut self,
        line: Line<'_>,
        block: &Block,
        words: &Words<'_>,
        g: i64,
        at: Option<&Word>,
    ) {
        // A cycle given: a mode set without one (`gives_no_cycle`) is over.
        self.cycle_mode_only = None;
        // The block that runs the cycle (a two-block form's first block only sets it up).
        let second = match g {
            70 => true,
            71..=73 => words.get('P').is_some() || words.get('Q').is_some(),
            74..=76 => words.moves(),
            _ => true,
        };
        let what = name(g, self.profile.gcode_system);
        let at = at.map_or(block.code_range.clone(), |w| w.range.clone());
        if !self.cycle_words(line, words, g, form(g, second), &what)
            || !self.cycle_needs(line, words, g, second, at)
            || !self.cycle_values(line, words, g, second, &what)
        {
            return;
        }
        if g == 76
            && !second
            && let Some(p) = words.get('P').and_then(|w| w.value.to_whole().ok())
        {
            self.g76_chamfer = Some((p / 100 % 100) as u32);
        }
        let start = self.r.pos;
        let f_before = self.f;
        let code_span = self.span(line, block.code_range.clone());
        // S (the speed the cycle runs at) and coolant act before the cycle, as items.
        let Some(speed) = self.speed(line, words) else {
            return;
        };
        let sw = crate::dialect::machine::Switches {
            coolant: words.coolant_on(code_span),
            spindle: Some((speed, None, code_span)),
            ..Default::default()
        };
        sw.spindle(&mut self.r, None);
        sw.coolant_on(&mut self.r, None);
        if !self.model_block(line, block, words, g, second) {
            self.keep_cycle_block(line, block, second);
        }
        self.stops(words, code_span);
        self.after_cycle(line, words, g, second);
        if (70..=73).contains(&g) && second {
            let f_after = match words.get('F') {
                Some(f) => self.length(line, f, Unit::Feed).map(FRegister::Feed),
                None => f_before,
            };
            self.cycle_references(line, words, g, start, f_after);
        }
    }

    /// The words a cycle cannot be without: P and Q naming its contour, an axis where it goes
    /// (a bare G28, Haas's, sends every axis home directly). False when one is missing (said,
    /// at `at`).
    fn cycle_needs(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        g: i64,
        second: bool,
        at: std::ops::Range<usize>,
    ) -> bool {
        let what = name(g, self.profile.gcode_system);
        if matches!(g, 70..=73)
            && second
            && let Some(c) = ['P', 'Q'].into_iter().find(|&c| words.get(c).is_none())
        {
            self.error(
                codes::FANR_CYCLE,
                line,
                at,
                format!("{what} without {c}"),
                "P and Q name the first and the last block of the contour: `G71 P100 Q200 U0.4 W0.1 F0.25`",
            );
            return false;
        }
        if second && matches!(g, 53 | 74..=76 | 90 | 94) && !words.moves() {
            self.error(
                codes::FANR_CYCLE,
                line,
                at,
                format!("{what} without an axis word (X, Z, U or W)"),
                "write where the cycle goes: `G90 X38. Z-30. F0.25`, `G28 U0. W0.`",
            );
            return false;
        }
        true
    }

    /// What a cycle leaves in force: a move done (G20/G21 no longer allowed), the F register
    /// (a G90/G94/G74/G75's feed, a G76's lead, unknown after G70–G73), which motion code
    /// (unknown after G70–G76: the next move names its own, spec fanuc.md; a G00 beside a
    /// G28 stays), and a G90/G94 repeated by the blocks after it.
    fn after_cycle(&mut self, line: Line<'_>, words: &Words<'_>, g: i64, second: bool) {
        if second {
            self.moved = true;
            self.f = match (g, words.get('F')) {
                (90 | 94 | 74 | 75, Some(f)) => {
                    self.length(line, f, Unit::Feed).map(FRegister::Feed)
                }
                (76, Some(f)) => self.lead(line, f).map(FRegister::Lead),
                (70..=73, _) => Some(FRegister::AfterCycle(g)),
                _ => self.f,
            };
            if (70..=76).contains(&g) {
                self.motion_after_cycle = Some(g);
            }
        } else if words.get('F').is_some() {
            self.f = Some(FRegister::AfterCycle(g));
        }
        if let Some((m, _)) = words.motion {
            self.motion = m;
            self.motion_after_cycle = None;
        }
        if matches!(g, 90 | 94) {
            self.kept_modal = Some(g);
        }
    }

    /// Every word of a cycle block is one its form takes (`allowed`), and no other code
    /// shares its block. False when one is not (said).
    fn cycle_words(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        g: i64,
        allowed: &str,
        what: &str,
    ) -> bool {
        let homing = matches!(g, 28 | 30 | 53);
        // Coolant may stand beside a cycle (M07/M08 act before it, M09 after), and a
        // spindle stop beside a move home (after it, as in any block: `G53 G00 Z0 M05`).
        let other = words
            .m_codes
            .iter()
            .filter(|(m, _)| !(matches!(m, 7..=9) || homing && *m == 5))
            .map(|(_, w)| *w)
            .chain(
                words
                    .motion
                    .filter(|(m, _)| !(homing && *m == super::Motion::Rapid))
                    .map(|(_, w)| w),
            )
            .chain(words.dwell)
            .chain(words.limit)
            .chain(words.units.map(|(_, w)| w))
            .chain(words.feed_mode.map(|(_, w)| w))
            .chain(words.speed_mode.map(|(_, w)| w))
            .chain(words.comp.map(|(_, w)| w))
            .chain(words.offset.map(|(_, w)| w))
            .next();
        if let Some(w) = other {
            let text = &line.text[w.range.clone()];
            self.error(
                codes::FANR_CYCLE,
                line,
                w.range.clone(),
                format!("`{text}` in the block of a {what}, which ncthread keeps as written"),
                "write it in a block of its own, before or after the cycle",
            );
            return false;
        }
        if let Some(w) = words.letters.iter().find(|w| !allowed.contains(w.letter)) {
            let text = &line.text[w.range.clone()];
            self.error(
                codes::FANR_CYCLE,
                line,
                w.range.clone(),
                format!(
                    "`{text}` is not a word of the {what} (its words: {})",
                    allowed
                        .chars()
                        .map(String::from)
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
                "check the cycle's form in the control's manual",
            );
            return false;
        }
        true
    }

    /// The values known without a model: P and Q are block numbers, a G71/G72 depth is more
    /// than 0, a G73's passes a whole number of at least 1, a G76's P the six digits mm rr aa
    /// with a tool angle FANUC has (80, 60, 55, 30, 29, 0). False when one is not (said).
    fn cycle_values(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        g: i64,
        second: bool,
        what: &str,
    ) -> bool {
        for &(letter, check) in value_checks(g, second) {
            let Some(w) = words.get(letter) else {
                continue;
            };
            let fits = match check {
                Check::Depth => self.length(line, w, Unit::Axis).map(|d| d.0 > 0),
                Check::Block => self.whole(line, w).map(|n| (1..=99_999).contains(&n)),
                Check::Passes => self.whole(line, w).map(|n| n >= 1),
                Check::G76P => self.whole(line, w).map(|p| {
                    (0..=999_999).contains(&p)
                        && p / 10_000 >= 1
                        && matches!(p % 100, 80 | 60 | 55 | 30 | 29 | 0)
                }),
            };
            match fits {
                Some(true) => {}
                // Its number could not be read (said).
                None => return false,
                Some(false) => {
                    let (why, help) = check.words();
                    let text = &line.text[w.range.clone()];
                    self.error(
                        codes::FANR_CYCLE,
                        line,
                        w.range.clone(),
                        format!("`{text}` in the {what}: {why}"),
                        help,
                    );
                    return false;
                }
            }
        }
        true
    }

    /// The cycle's P and Q, checked at the program's end; after a G71, G72 or G73 its
    /// contour (from `start`, the cycle's start point) is read next.
    fn cycle_references(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        g: i64,
        start: crate::ir::Pos,
        f_after: Option<FRegister>,
    ) {
        let (Some(p), Some(q)) = (words.get('P'), words.get('Q')) else {
            return;
        };
        let (Ok(pn), Ok(qn)) = (p.value.to_whole(), q.value.to_whole()) else {
            return;
        };
        for (w, n) in [(p, pn), (q, qn)] {
            self.references.push(Reference {
                n: n as u32,
                span: self.span(line, w.range.clone()),
                text: line.text[w.range.clone()].to_string(),
                g,
            });
        }
        if g != 70 {
            self.contour = Some(Contour {
                g,
                p: pn as u32,
                q: qn as u32,
                span: self.span(line, p.range.clone()),
                numbered: true,
                first: true,
                at: (start.x, start.z),
                dir: (0, 0),
                type_one: g != 73,
                motion: 0,
                feeds: false,
                f_after,
            });
            self.capturing = self.capture();
        }
    }

    /// A block kept as written, as a cycle: only the FANUC writer writes it back.
    fn keep_cycle_block(&mut self, line: Line<'_>, block: &Block, moves: bool) {
        let code = self.cycle_text(line, block);
        let span = self.span(line, block.code_range.clone());
        self.r.keep_opaque(
            code,
            span,
            None,
            ModalContext {
                inch: self.inch,
                diameter: true,
                // System B's G91: the block's X and Z are increments.
                incremental: self.incremental,
                per_minute: Some(self.per_minute),
                moves,
                cycle: true,
                compensation: turns_compensation_on(block),
            },
        );
        self.sync_end = None;
    }

    /// A cycle block's code as written, but for its coolant words, a spindle stop and S
    /// (read, and written, as items of their own).
    pub(super) fn cycle_text(&self, line: Line<'_>, block: &Block) -> String {
        let mut code = self.kept_text(line, block);
        for w in block.words.iter().rev() {
            if (w.letter == 'M' && matches!(w.value.to_whole(), Ok(5 | 7..=9))) || w.letter == 'S' {
                let text = &line.text[w.range.clone()];
                if let Some(at) = code.rfind(text) {
                    code.replace_range(at..at + text.len(), "");
                }
            }
        }
        code.split_whitespace().collect::<Vec<_>>().join(" ")
    }

    /// A block of the contour that follows a G71, G72 or G73: checked (the first is the block
    /// P names, moves are G00–G03 only, a type I contour does not turn back) and kept as
    /// written. The control does not run it here (G70 runs it); the block numbered Q ends it.
    pub(super) fn contour_block(&mut self, line: Line<'_>, block: &Block) {
        let Some(mut c) = self.contour.take() else {
            return;
        };
        let what = name(c.g, self.profile.gcode_system);
        let code_range = block.code_range.clone();
        if std::mem::take(&mut c.numbered) && block.number != Some(c.p) {
            let n = block
                .number
                .map_or("no number".to_string(), |n| format!("N{n}"));
            self.error(
                codes::FANR_CYCLE,
                line,
                code_range.clone(),
                format!("the contour of the {what} (P{}) must start on the block after it, which has {n}", c.p),
                "put the contour's blocks, numbered P to Q, right after the cycle's block",
            );
        }
        if let Some(range) = block.block_delete.clone() {
            self.error(
                codes::FANR_CYCLE,
                line,
                range,
                format!("a `/` block in the contour of the {what}"),
                "a contour's blocks run in the cycle: remove the block skip",
            );
        }
        if !block.words.is_empty() {
            let errors = self.r.diags.len();
            self.contour_words(line, block, &mut c);
            if self.r.diags[errors..].iter().any(|d| d.is_error())
                && let Some(cap) = self.capturing.as_mut()
            {
                cap.refuse("its contour has an error");
            }
            self.capture_block(line, block);
            c.first = false;
        }
        if self.model() {
            self.push_model(line, block, c.g, false, Vec::new());
        } else {
            self.keep_cycle_block(line, block, false);
        }
        if block.number == Some(c.q) {
            // A contour without F leaves the F the cycle left: its own, else the one before
            // it (with one, which F is in force after the cycle is the control's).
            // **[decided]**
            if !c.feeds && matches!(self.f, Some(FRegister::AfterCycle(g)) if g == c.g) {
                self.f = c.f_after;
            }
            self.contour_done((c.p, c.q), c.type_one);
        } else {
            self.contour = Some(c);
        }
    }

    /// The words of a contour block: G00–G03, X Z U W I K R, F S T (which G70 runs).
    fn contour_words(&mut self, line: Line<'_>, block: &Block, c: &mut Contour) {
        let what = name(c.g, self.profile.gcode_system);
        let mut to = c.at;
        for w in &block.words {
            let text = &line.text[w.range.clone()];
            let refuse = match w.letter {
                'G' => match w.value.to_whole() {
                    Ok(g @ 0..=3) if !w.value.has_point => {
                        c.motion = g;
                        None
                    }
                    // Tool nose radius compensation, on and off along the contour.
                    Ok(40..=42) if !w.value.has_point => None,
                    _ => Some("the contour holds G00–G03 moves (and G40–G42) only"),
                },
                'X' | 'Z' | 'U' | 'W' => {
                    let v = self.length(line, w, Unit::Axis);
                    match w.letter {
                        'X' => to.0 = v,
                        'Z' => to.1 = v,
                        'U' => to.0 = to.0.zip(v).map(|(a, b)| a + b),
                        _ => to.1 = to.1.zip(v).map(|(a, b)| a + b),
                    }
                    None
                }
                'F' => {
                    c.feeds = true;
                    None
                }
                'I' | 'K' | 'R' | 'S' | 'T' | 'C' => None,
                // A direction angle: the block's end is the control's to find.
                'A' => {
                    to = (None, None);
                    None
                }
                _ => Some("a contour's blocks hold G00–G03, X Z U W I K R, C and A, and F S T"),
            };
            if let Some(why) = refuse {
                // Its words are not a move: the contour's points are not followed further.
                c.type_one = false;
                self.error(
                    codes::FANR_CYCLE,
                    line,
                    w.range.clone(),
                    format!("`{text}` in the contour of the {what}: {why}"),
                    "write the finished shape with G00, G01, G02 and G03 moves",
                );
            }
        }
        self.contour_shape(line, block, c, to);
        c.at = to;
    }

    /// The contour's shape where it is known: the first block says G00 or G01 (and decides
    /// type I or II), a type I contour's points change X and Z one way each.
    fn contour_shape(
        &mut self,
        line: Line<'_>,
        block: &Block,
        c: &mut Contour,
        to: (Option<Length>, Option<Length>),
    ) {
        let what = name(c.g, self.profile.gcode_system);
        let has = |l: char| block.words.iter().any(|w| w.letter == l);
        if c.first {
            if !matches!(c.motion, 0 | 1) || !block.words.iter().any(|w| w.letter == 'G') {
                self.error(
                    codes::FANR_CYCLE,
                    line,
                    block.code_range.clone(),
                    format!("the first block of the contour of the {what} must say G00 or G01"),
                    "start the contour with `G00 X…` or `G01 X…`",
                );
            }
            // Type II: the first block moves along the cut too (a pocket).
            c.type_one &= match c.g {
                71 => !has('Z') && !has('W'),
                72 => !has('X') && !has('U'),
                _ => false,
            };
        } else if c.type_one
            && let ((Some(x0), Some(z0)), (Some(x1), Some(z1))) = (c.at, to)
        {
            let step = ((x1 - x0).0.signum(), (z1 - z0).0.signum());
            let turns = |seen: i64, now: i64| seen != 0 && now != 0 && seen != now;
            if turns(c.dir.0, step.0) || turns(c.dir.1, step.1) {
                self.error(
                    codes::FANR_CYCLE,
                    line,
                    block.code_range.clone(),
                    format!("the contour of the {what} turns back here: a type I contour changes X and Z each one way only"),
                    "a pocket needs type II (its first block moves along Z too for G71), which ncthread keeps as written",
                );
                c.type_one = false;
            }
            if c.dir.0 == 0 {
                c.dir.0 = step.0;
            }
            if c.dir.1 == 0 {
                c.dir.1 = step.1;
            }
        }
    }

    /// At the program's end: a contour still open, and every P and Q that names no block, or
    /// one whose number two blocks have.
    pub(super) fn cycle_closing(&mut self) {
        if let Some(c) = self.contour.take() {
            self.r.error(
                codes::FANR_CYCLE,
                c.span,
                format!(
                    "the contour of the {} never reaches its last block, N{}",
                    name(c.g, self.profile.gcode_system),
                    c.q
                ),
                "end the contour with the block Q names",
            );
        }
        for r in std::mem::take(&mut self.references) {
            let count = self.numbers.get(&r.n).copied().unwrap_or(0);
            if count == 1 {
                continue;
            }
            let message = if count == 0 {
                format!(
                    "`{}` of the {} names no block of the program",
                    r.text,
                    name(r.g, self.profile.gcode_system)
                )
            } else {
                format!(
                    "`{}` of the {}: {count} blocks are numbered N{}, and which one the control finds is its search's",
                    r.text,
                    name(r.g, self.profile.gcode_system),
                    r.n
                )
            };
            self.r.error(
                codes::FANR_CYCLE,
                r.span,
                message,
                "number the contour's blocks once each",
            );
        }
    }
}

/// Whether a kept block says G41 or G42 (tool nose radius compensation on).
pub(super) fn turns_compensation_on(block: &Block) -> bool {
    block
        .words
        .iter()
        .any(|w| w.letter == 'G' && !w.value.has_point && matches!(w.value.to_whole(), Ok(41 | 42)))
}

#[cfg(test)]
mod tests {
    use crate::diag::Diagnostic;
    use crate::dialect::Unsupported;
    use crate::ir::{Item, ItemKind, Pos};
    use crate::source::SourceFile;

    fn read(body: &str) -> (Vec<Item>, Vec<Diagnostic>) {
        let text = format!("G21 G99\nT0101\nG97 S800 M03\nG00 X52. Z2.\n{body}M30\n");
        let (p, d) = super::super::parse(
            &SourceFile::new("t", &text),
            &crate::profile::Profile::default().fanuc,
            Unsupported::Error,
        );
        (p.items, d)
    }

    fn errors(d: &[Diagnostic]) -> Vec<(&str, u32)> {
        d.iter()
            .filter(|d| d.is_error())
            .map(|d| (d.code.id, d.location.as_ref().map_or(0, |l| l.line)))
            .collect()
    }

    /// Each cycle block, and each block of a contour, is kept as written, in order; the
    /// cycles that move leave the position unknown, the first blocks and the contour do not
    /// move.
    #[test]
    fn cycles_and_their_contours_are_kept_as_written() {
        let (items, d) = read(
            "G71 U2. R0.5\nG71 P80 Q130 U0.4 W0.1 F0.25\nN80 G00 X20.\nN90 G01 Z-15.\nN130 X52.\nG70 P80 Q130\nG00 X100. Z100.\nG28 U0. W0.\n",
        );
        assert!(errors(&d).is_empty(), "{d:?}");
        let kept: Vec<(&str, bool)> = items
            .iter()
            .filter_map(|i| match &i.kind {
                ItemKind::Opaque {
                    text,
                    block: Some(c),
                    ..
                } if c.cycle => Some((text.as_str(), c.moves)),
                _ => None,
            })
            .collect();
        assert_eq!(
            kept,
            [
                ("G71 U2. R0.5", false),
                ("G71 P80 Q130 U0.4 W0.1 F0.25", true),
                ("G00 X20.", false),
                ("G01 Z-15.", false),
                ("X52.", false),
                ("G70 P80 Q130", true),
                ("G28 U0. W0.", true),
            ]
        );
        let end = items
            .iter()
            .fold(Pos::UNKNOWN, |at, i| i.kind.end_position(at));
        assert_eq!(end, Pos::UNKNOWN);
    }

    /// What is known without a model is checked, at its line.
    #[test]
    fn what_is_known_without_a_model_is_checked() {
        let cases: [(&str, u32); 8] = [
            ("G71 U0. R0.5\n", 5),
            ("G72 W2. R0.5 U1.\n", 5),
            ("G73 U3. W0. R0\n", 5),
            ("G76 P010070 Q100 R0.05\n", 5),
            ("G70 P80\n", 5),
            ("G90 F0.2\n", 5),
            ("G71 P80 Q90 U0.4 F0.2\nN80 G01 X20. Z-1.\nN90 G04 X1.\n", 7),
            (
                "G70 P10 Q20\nN10 G01 X1. F0.2\nN20 G01 X2.\nN10 G00 X3.\n",
                5,
            ),
        ];
        for (body, line) in cases {
            let (_, d) = read(body);
            assert_eq!(errors(&d), [("FANR018", line)], "{body:?}: {d:?}");
        }
    }

    /// A G90 or G94 with no word of its cycle (a safe-start line's) gives no cycle: nothing
    /// kept, nothing refused, no bare G97's speed used; a block with only axes after it is
    /// refused, but not after a cycle given since; a word no such block takes is refused.
    #[test]
    fn a_g90_without_its_cycles_words_gives_no_cycle() {
        let (items, d) = read("G21 G40 G49 G54 G80 G90\nG00 X40.\n");
        assert!(errors(&d).is_empty(), "{d:?}");
        assert!(
            !items
                .iter()
                .any(|i| matches!(&i.kind, ItemKind::Opaque { .. })),
            "{items:?}"
        );
        let (_, d) = read("G90\nX30.\n");
        assert_eq!(errors(&d), [("FANR018", 6)], "{d:?}");
        let (_, d) = read("G90\nG90 X38. Z-30. F0.25\nX36.\n");
        assert!(errors(&d).is_empty(), "{d:?}");
        let (_, d) = read("G90 A30.\n");
        assert_eq!(errors(&d), [("FANR018", 5)], "{d:?}");
        let (_, d) = read("G97\nG90\nM05\n");
        assert!(errors(&d).is_empty(), "{d:?}");
    }

    /// After a G71–G73 whose contour has no F word, the F in force is the cycle's own (else
    /// the one before it); with an F in the contour, which one is the control's.
    #[test]
    fn a_contour_without_f_leaves_the_cycles_f() {
        let contour =
            |f: &str| format!("G71 P80 Q90 U0.4 W0.1{f}\nN80 G00 X20.\nN90 G01 Z-15.\nG01 X30.\n");
        let (items, d) = read(&contour(" F0.25"));
        assert!(errors(&d).is_empty(), "{d:?}");
        let feed = items.iter().rev().find_map(|i| match i.kind {
            ItemKind::Feed { feed, .. } => Some(feed.0 / crate::fixed::Length::STEP),
            _ => None,
        });
        assert_eq!(feed, Some(2_500));
        let (_, d) = read(&format!("G01 F0.3\n{}", contour("")));
        assert!(errors(&d).is_empty(), "{d:?}");
        let (_, d) = read(&contour(""));
        assert_eq!(errors(&d), [("FANR009", 8)], "{d:?}");
        let (_, d) =
            read("G71 P80 Q90 U0.4 W0.1 F0.25\nN80 G00 X20.\nN90 G01 Z-15. F0.1\nG01 X30.\n");
        assert_eq!(errors(&d), [("FANR009", 8)], "{d:?}");
    }

    /// An S in a cycle's block is the speed the cycle runs at: a spindle item before it, and
    /// not in its kept text.
    #[test]
    fn an_s_beside_a_cycle_acts_before_it() {
        let (items, d) = read("G70 P80 Q90 S1200 M08\nN80 G00 X20.\nN90 G01 Z-10. F0.2\n");
        assert!(errors(&d).is_empty(), "{d:?}");
        let at = items
            .iter()
            .position(|i| matches!(&i.kind, ItemKind::Opaque { text, .. } if text == "G70 P80 Q90"))
            .unwrap();
        assert!(matches!(
            items[..at]
                .iter()
                .rev()
                .find(|i| matches!(i.kind, ItemKind::Spindle { .. }))
                .map(|i| &i.kind),
            Some(ItemKind::Spindle {
                speed: Some(1200),
                direction: None
            })
        ));
    }

    /// A G76's P rr sets the machine's chamfer (parameter 5130): a G92 after it needs no
    /// profile key, and chamfers by it.
    #[test]
    fn a_g76_sets_the_chamfer_of_the_g92_after_it() {
        let (items, d) = read(
            "G76 P011060 Q100 R0.05\nG76 X18.16 Z-20. P920 Q400 F1.5\nG00 X26. Z5.\nG92 X19.4 Z-20. F1.5\n",
        );
        assert!(errors(&d).is_empty(), "{d:?}");
        let exit = items.iter().find_map(|i| match &i.kind {
            ItemKind::ThreadPass(p) => p.exit,
            _ => None,
        });
        assert_eq!(
            exit.map(|e| e.length.0 / crate::fixed::Length::STEP),
            Some(15_000)
        );
        let (_, d) = read("G00 X26. Z5.\nG92 X19.4 Z-20. F1.5\n");
        assert_eq!(errors(&d), [("FANR004", 6)]);
    }

    /// G90 and G94 are modal: a block with only axes repeats the cycle, until a motion code.
    #[test]
    fn a_g90_is_repeated_by_blocks_with_only_axes() {
        let (items, d) = read("G90 X38. Z-30. F0.25\nX36.\nX34.\nG00 X100.\nX110.\n");
        assert!(errors(&d).is_empty(), "{d:?}");
        let kept = items
            .iter()
            .filter(|i| matches!(&i.kind, ItemKind::Opaque { block: Some(c), .. } if c.cycle))
            .count();
        assert_eq!(kept, 3);
        assert!(items.iter().any(
            |i| matches!(i.kind, ItemKind::Rapid { to } if to.x.is_some_and(|x| x.0 == 1_100_000 * crate::fixed::Length::STEP))
        ));
    }
}

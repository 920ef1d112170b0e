//! G33 and G33.1: synchronised moves and rigid tapping.

use super::super::syntax::Word;
use super::{FrontEnd, Words};
use crate::dialect::iso::codes;
use crate::fixed::{Angle, Lead, Length};
use crate::ir::{ItemKind, Pos, SyncInfeed, SyncStart, TapCycle, ThreadPass};
use crate::lower;
use crate::source::{Line, Span};

impl FrontEnd<'_> {
    /// The K word of G33/G33.1 (advance per revolution along the path), positive.
    pub(super) fn k_word<'b>(
        &mut self,
        line: Line<'_>,
        words: &mut Words<'b>,
        at: Option<&Word>,
        what: &str,
    ) -> Option<&'b Word> {
        match words.take('K') {
            Some(k) if k.value.mantissa > 0 => Some(k),
            Some(k) => {
                self.number_error(
                    line,
                    k,
                    "the lead K is not positive".into(),
                    "K is the advance per spindle revolution, more than 0",
                );
                None
            }
            None => {
                // Point at the code, else an axis word (a modal G33 line may have only X).
                let range = at
                    .or(words.other.get(&'Z').copied())
                    .or(words.other.get(&'X').copied())
                    .map_or(0..line.text.len(), |w| w.range.clone());
                self.diag(
                    codes::ISOR_WORD,
                    line,
                    range,
                    format!("{what} without K (the lead): LinuxCNC needs K on every {what} line"),
                    "write the advance per revolution: `K1.5`",
                );
                None
            }
        }
    }

    /// G33: a synchronised move to the line's target, K its advance per revolution along
    /// the path (along X for a move along X only).
    pub(super) fn thread(
        &mut self,
        line: Line<'_>,
        words: &mut Words<'_>,
        at: Option<&Word>,
        span: Span,
    ) {
        let k = self.k_word(line, words, at, "G33");
        let z_word = words.other.get(&'Z').copied();
        let x_word = words.other.get(&'X').copied();
        let Some(to) = self.target(line, words) else {
            return;
        };
        let Some(k) = k else {
            return;
        };
        if !self.spindle_turning(line, at.or(z_word), "G33") {
            return;
        }
        let from = self.r.pos;
        let end = ItemKind::Rapid { to }.end_position(from);
        let word = z_word.or(x_word).or(at).expect("a G33 line has X or Z");
        let Some(start) = self.sync_start(line, from, word) else {
            return;
        };
        let dz = match (from.z, end.z) {
            (Some(a), Some(b)) => Some(b - a),
            _ => None,
        };
        let moves_x = to.x.is_some() && to.x != from.x;
        if dz == Some(Length::ZERO) || z_word.is_none() {
            // A synchronised move along X only: K is the advance along X.
            if !moves_x {
                self.diag(
                    codes::ISOR_THREAD_GEOMETRY,
                    line,
                    word.range.clone(),
                    "G33 that does not move".into(),
                    "give the end of the thread with Z (and X for a taper)",
                );
                return;
            }
            return self.thread_along_x(line, word, k, (from, end), start, span);
        }
        // K is along the path; the IR's lead is along Z.
        let lead = if moves_x {
            let (Some(x0), Some(dz)) = (from.x, dz) else {
                let w = x_word.expect("X moves");
                self.unknown_start(line, w);
                return;
            };
            let dx = end.x.expect("X is given") - x0;
            match self.taper_lead(line, k, dz, dx) {
                Some(l) => l,
                None => return,
            }
        } else {
            match self.lead(line, k) {
                Some(l) => l,
                None => return,
            }
        };
        let pass = ThreadPass {
            to,
            lead,
            start,
            infeed: None,
            entry: None,
            exit: None,
        };
        self.push(ItemKind::pass(pass), span);
        self.r.pos = pass.end_position(from);
        self.sync_end = Some(self.r.pos);
        self.in_cut = Some(self.r.pos);
    }

    /// How a G33 from `from` starts. LinuxCNC continues a G33 that follows another without
    /// waiting for the index pulse; after anything else that empties its motion queue it
    /// would wait, in the cut (reported at `word`: `None`).
    fn sync_start(&mut self, line: Line<'_>, from: Pos, word: &Word) -> Option<SyncStart> {
        if self.sync_end.is_some() && self.sync_end == Some(from) {
            Some(SyncStart::Continue)
        } else if self.in_cut.is_some() && self.in_cut == Some(from) {
            self.diag(
                codes::ISOR_THREAD_GEOMETRY,
                line,
                word.range.clone(),
                "this G33 starts where a thread move ended, after a line that is not a G33: whether LinuxCNC waits for the index pulse here (with the tool in the cut) depends on its motion queue".into(),
                "write the thread moves on consecutive lines (comments between them are fine), or retract before the next pass",
            );
            None
        } else {
            Some(SyncStart::Index(Angle::ZERO))
        }
    }

    /// A G33 that moves along X only (`path`: from, to): K is the advance along X.
    fn thread_along_x(
        &mut self,
        line: Line<'_>,
        word: &Word,
        k: &Word,
        path: (Pos, Pos),
        start: SyncStart,
        span: Span,
    ) {
        let (from, end) = path;
        let (Some(x), Some(z)) = (end.x, from.z) else {
            self.unknown_start(line, word);
            return;
        };
        if from.x.is_none() {
            self.unknown_start(line, word);
            return;
        }
        let Some(advance) = self.lead(line, k) else {
            return;
        };
        let pass = ThreadPass {
            to: Pos::new(x, z),
            lead: advance,
            start,
            infeed: Some(SyncInfeed { x, advance }),
            entry: None,
            exit: None,
        };
        self.push(ItemKind::pass(pass), span);
        self.r.pos = Pos::new(x, z);
        self.sync_end = Some(self.r.pos);
        self.in_cut = Some(self.r.pos);
    }

    /// The lead along Z of a tapered G33 whose K is along the path (`dz`, `dx` its run).
    fn taper_lead(&mut self, line: Line<'_>, k: &Word, dz: Length, dx: Length) -> Option<Lead> {
        let k_mm = k.value.to_f64() * if self.inch { 25.4 } else { 1.0 };
        let lead = lower::z_lead_of_k(k_mm, dz, dx);
        if lead.is_none() {
            self.diag(
                codes::ISOR_NUMBER,
                line,
                k.range.clone(),
                format!(
                    "`{}` gives no usable lead along Z",
                    &line.text[k.range.clone()]
                ),
                "a lead is more than 10⁻¹² mm and at most 1,000,000 mm",
            );
        }
        lead
    }

    pub(super) fn unknown_start(&mut self, line: Line<'_>, w: &Word) {
        self.diag(
            codes::ISOR_UNKNOWN_POSITION,
            line,
            w.range.clone(),
            "the move starts from a position that is not known yet".into(),
            "move to the start with absolute X and Z first",
        );
    }

    pub(super) fn tap(
        &mut self,
        line: Line<'_>,
        words: &mut Words<'_>,
        at: Option<&Word>,
        span: Span,
    ) {
        let k = self.k_word(line, words, at, "G33.1");
        let x_word = words.other.get(&'X').copied();
        let z_word = words.other.get(&'Z').copied();
        let Some(to) = self.target(line, words) else {
            return;
        };
        let (Some(k), Some(z_word)) = (k, z_word) else {
            if let (None, Some(at)) = (z_word, at) {
                self.missing(
                    line,
                    at,
                    "G33.1 without Z (the depth of the hole)".into(),
                    "write `G33.1 Z-20 K1.5`",
                );
            }
            return;
        };
        if let (Some(x), Some(w)) = (to.x, x_word)
            && Some(x) != self.r.pos.x
        {
            self.diag(
                codes::ISOR_THREAD_GEOMETRY,
                line,
                w.range.clone(),
                "G33.1 that also moves X".into(),
                "move to the hole's X first; the tap runs along Z only",
            );
            return;
        }
        if !self.spindle_turning(line, at, "G33.1") {
            return;
        }
        if self.r.pos.z.is_none() {
            self.unknown_start(line, z_word);
            return;
        }
        let Some(lead) = self.lead(line, k) else {
            return;
        };
        self.push(
            ItemKind::TapCycle(TapCycle {
                end_z: to.z.expect("Z is given"),
                lead,
                then_x: None,
            }),
            span,
        );
    }
}

//! IR → FANUC lathe G-code (system A).
//!
//! The frame: `%`, `O0001`, a comment saying where the program came from, `G21 G99`, the
//! program, `%` (an `M30` only where the program has its end: M30 resets the machine's state). Every X Z I K word has a decimal point
//! and at most 3 decimals (X a diameter, I a radius value); F and the dwell's U take 4 and 3.
//! Threads are consecutive `G32` blocks (a pass's entry, thread and runout one chain), `Q` the
//! start angle on a chain's first block; cycles are written as their passes. Comments are
//! upper-case ASCII. Block numbers are kept from a FANUC source, else none.

use std::fmt::Write as _;

use crate::diag::{Code, Diagnostic};
use crate::dialect::fanuc::codes;
use crate::dialect::write::{self, Writer};
use crate::dialect::{Inexact, one_line};
use crate::fixed::{Angle, Decimal, Lead, Length};
use crate::ir::{
    Compensation, Coolant, EndCode, FeedMode, Item, ItemKind, Pos, Program, SpindleDirection,
    SpindleMode, SyncStart, ThreadCycle, ThreadPass,
};
use crate::lower;
use crate::profile::{GcodeSystem, Profile, ToolOffset};
use crate::source::{SourceFile, Span};

/// How the header comment of a program ncthread wrote ends.
pub(crate) const HEADER_END: &str = ", CONVERTED BY NCTHREAD";

#[derive(Default)]
struct Block {
    number: Option<u32>,
    words: Vec<String>,
    comment: Option<String>,
    /// The block holds a motion word (a second motion starts a new block).
    moves: bool,
    /// The comment is ncthread's own text (a cycle's summary and pass headings), not the
    /// program's: its transliteration (`°` → `DEG`) is not reported.
    own_comment: bool,
    /// A kept block with only its number (a contour's first or last, which P and Q name):
    /// written though it has no words.
    number_only: bool,
    /// The index in `words` of a block's text kept as written: the source's, in the
    /// machine's G-code system already, never mapped by [`Emitter::in_system`].
    verbatim: Option<usize>,
}

struct Emitter<'a> {
    w: Writer<'a>,
    profile: &'a Profile,
    keep: bool,
    motion: Option<&'static str>,
    /// The F register: its value and whether it was written as a lead.
    f: Option<(Lead, bool)>,
    /// Where the last G32 block ended, while the next block may continue it.
    sync_end: Option<Pos>,
    /// The speed limit written (G50 S).
    limit: Option<i64>,
    /// G96 is in force in the output.
    surface_speed: bool,
    /// The last S written, and a G96/G97 of this block that still needs its S.
    speed: Option<u32>,
    speed_word: Option<Item>,
    /// The spindle turns in the output (M03/M04 written, no M05 since).
    turning: bool,
    /// A G97 was written without S while the spindle stood: the rpm the control keeps is
    /// its own, so that the next start says its S.
    speed_unsaid: bool,
    /// Comments met inside a G32 chain (with the span of their item), written after it.
    deferred: Vec<(String, Span)>,
    /// The span of the item being written: where a comment's transliteration is reported.
    at: Span,
    /// Comments whose Latin letters lost their accents (or symbols were spelled), and
    /// comments in another script, romanised.
    latin: Transliterated,
    script: Transliterated,
    inexact: Inexact,
    round: bool,
    /// The program is written in inches (G20): lengths to 0.0001 in, leads to 0.000001 in.
    inch: bool,
}

/// The diameter signs a comment may use (`Ø20`, `⌀20`, `∅20`): written `D`, as ncthread's own
/// comments in ASCII say a diameter (`D20`), not `O` (which reads as a zero).
const DIAMETER_SIGNS: [char; 4] = ['Ø', 'ø', '⌀', '∅'];

/// What writing a comment in ASCII changed, beyond the diameter sign, the letter case and the
/// characters a FANUC comment cannot hold.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Transliteration {
    /// A Latin letter lost its accent (`Č` → `C`), or a symbol was spelled in ASCII (`°` →
    /// `deg`) or became `?`.
    latin: bool,
    /// A letter of another script (Cyrillic, Greek, Chinese…) was romanised (`Резьба` →
    /// `Rez'ba`).
    script: bool,
}

/// A letter of the Latin script (ASCII, the Latin-1 letters, Latin Extended, fullwidth
/// Latin): one whose ASCII form is the same letter without its accent.
fn latin(c: char) -> bool {
    matches!(c,
        '\0'..='\u{24F}'
        | '\u{250}'..='\u{2AF}'
        | '\u{1D00}'..='\u{1DBF}'
        | '\u{1E00}'..='\u{1EFF}'
        | '\u{2C60}'..='\u{2C7F}'
        | '\u{A720}'..='\u{A7FF}'
        | '\u{AB30}'..='\u{AB6F}'
        | '\u{FB00}'..='\u{FB06}'
        | '\u{FF21}'..='\u{FF3A}'
        | '\u{FF41}'..='\u{FF5A}')
}

/// Upper-case ASCII comment text without parentheses. **\[decided\]**
pub(crate) fn comment_text(text: &str) -> String {
    transliterate(text).0
}

/// [`comment_text`], and what became ASCII on the way: a diameter sign is `D`; any other
/// character outside ASCII is deunicode's transliteration (`?` where it has none).
fn transliterate(text: &str) -> (String, Transliteration) {
    let mut how = Transliteration::default();
    let mut ascii = String::new();
    for c in one_line(text).chars() {
        if c.is_ascii() {
            ascii.push(c);
        } else if DIAMETER_SIGNS.contains(&c) {
            ascii.push('D');
        } else {
            if c.is_alphabetic() && !latin(c) {
                how.script = true;
            } else {
                how.latin = true;
            }
            ascii.push_str(
                deunicode::deunicode_char(c)
                    .filter(|t| t.is_ascii())
                    .unwrap_or("?"),
            );
        }
    }
    // `%` ends the tape (a control stops reading there, inside a comment too), `;` is the
    // end of block as the control shows it.
    let ascii = ascii
        .to_ascii_uppercase()
        .replace('(', "[")
        .replace(')', "]")
        .replace('%', " PCT")
        .replace(';', ",")
        .chars()
        .map(|c| if c.is_ascii_control() { ' ' } else { c })
        .collect::<String>()
        .trim()
        .to_string();
    (ascii, how)
}

/// How much of a transliterated comment its warning shows, in characters.
const EXAMPLE_CHARS: usize = 80;

/// The comments of one kind of [`Transliteration`] in a program: how many, and the first
/// (where, as written, as the FANUC program has it).
#[derive(Default)]
struct Transliterated {
    count: usize,
    first: Option<(Span, String, String)>,
}

impl Transliterated {
    fn note(&mut self, at: Span, text: &str, ascii: &str) {
        self.count += 1;
        if self.first.is_none() {
            self.first = Some((at, one_line(text), ascii.to_string()));
        }
    }

    /// The one warning of a program: the count and the first example.
    fn diagnostic(&self, src: &SourceFile, what: &str, help: &str) -> Option<Diagnostic> {
        let (at, text, ascii) = self.first.as_ref()?;
        // The comment itself where its line holds it as written, else its item.
        let line = src.line(at.line);
        let at = match line.text.find(text.as_str()) {
            Some(i) if at.line > 0 && !text.is_empty() => src.span_in_line(line, i..i + text.len()),
            _ => *at,
        };
        let many = match self.count {
            1 => String::new(),
            n => format!(" ({n} comments, the first shown)"),
        };
        // A long comment is shown by its start (the marked line holds all of it).
        let short = |s: &str| match s.char_indices().nth(EXAMPLE_CHARS) {
            Some((end, _)) => format!("{}…", &s[..end]),
            None => s.to_string(),
        };
        Some(
            Diagnostic::new(
                codes::FANW_TRANSLITERATED,
                format!("{what}: `{}` → `{}`{many}", short(text), short(ascii)),
            )
            .at(src, at)
            .help(help),
        )
    }
}

/// Where the FANUC writer stands in the program's start.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Start {
    /// Before the first item that is not a `%` line: it may be the header comment.
    Header,
    /// Before the first item that is not a comment: the header's feed mode (G99, which the
    /// header writes) is not written again (its comment stays, as a comment item).
    FeedMode,
    Body,
}

/// The FANUC writer taking a program's items one at a time (a conversion's streaming read),
/// or a whole program ([`Dialect::write`](crate::dialect::Dialect::write)).
pub(crate) struct Items<'a> {
    e: Emitter<'a>,
    /// The program's dialect, number and unit.
    from: crate::ir::DialectId,
    number: Option<u32>,
    inch: bool,
    start: Start,
    groups: write::Grouper,
}

impl<'a> Items<'a> {
    /// For `program`'s dialect, number and unit (its items are not needed).
    pub fn new(program: &Program, src: &'a SourceFile, profile: &'a Profile, round: bool) -> Self {
        let keep = program.dialect == super::ID;
        let e = Emitter {
            w: Writer::new(src),
            profile,
            keep,
            motion: None,
            f: None,
            sync_end: None,
            limit: None,
            surface_speed: false,
            speed: None,
            speed_word: None,
            turning: false,
            speed_unsaid: false,
            deferred: Vec::new(),
            at: Span::default(),
            latin: Transliterated::default(),
            script: Transliterated::default(),
            inexact: Inexact::default(),
            round,
            inch: program.inch,
        };
        Items {
            e,
            from: program.dialect,
            number: program.number,
            inch: program.inch,
            start: Start::Header,
            groups: write::Grouper::new(keep),
        }
    }

    /// The program's start, once its first item that is not a `%` line is known (`None`:
    /// the program has none): `%`, the O number, the header comment, the unit and feed mode.
    /// Whether that item was the header comment.
    fn begin(&mut self, first: Option<&Item>) -> bool {
        let header = self.e.header(self.from, self.number, first);
        self.e
            .w
            .out
            .push_str(match (self.e.profile.fanuc.gcode_system, self.inch) {
                (GcodeSystem::A, true) => "G20 G99\n",
                (GcodeSystem::A, false) => "G21 G99\n",
                (GcodeSystem::B, true) => "G20 G90 G95\n",
                (GcodeSystem::B, false) => "G21 G90 G95\n",
                (GcodeSystem::C, true) => "G70 G90 G95\n",
                (GcodeSystem::C, false) => "G71 G90 G95\n",
            });
        self.start = Start::FeedMode;
        header
    }

    /// An item of the program's body, to its block.
    fn body(&mut self, item: &Item) {
        let e = &mut self.e;
        self.groups.item(item, |group| {
            e.w.spill();
            e.group(group);
        });
    }
}

impl write::ItemWriter for Items<'_> {
    #[cfg(unix)]
    fn follow(&mut self, follow: crate::source::Follow) {
        self.e.w.follow(follow);
    }

    fn refuses(&self) -> bool {
        self.e.inexact.refuses(self.e.round)
    }

    fn item(&mut self, item: &Item) {
        if self.start == Start::Header {
            if item.kind == ItemKind::Delimiter {
                return;
            }
            if self.begin(Some(item)) {
                return;
            }
        }
        if self.start == Start::FeedMode
            && !matches!(item.kind, ItemKind::Comment(_) | ItemKind::Delimiter)
        {
            self.start = Start::Body;
            if item.kind == ItemKind::FeedMode(FeedMode::PerRev) {
                if let Some(c) = &item.comment {
                    self.body(&Item::new(ItemKind::Comment(c.to_string()), item.span));
                }
                return;
            }
        }
        self.body(item);
    }

    fn finish(mut self: Box<Self>) -> (Option<crate::dialect::Output>, Vec<Diagnostic>) {
        if self.start == Start::Header {
            self.begin(None);
        }
        let e = &mut self.e;
        self.groups.finish(|group| {
            e.w.spill();
            e.group(group);
        });
        let mut e = self.e;
        for (text, at) in std::mem::take(&mut e.deferred) {
            e.at = at;
            e.write(Block {
                comment: Some(text),
                ..Block::default()
            });
        }
        e.w.out.push_str("%\n");
        let src = e.w.src;
        e.closing_diagnostics(src);
        e.w.finish()
    }
}

impl Emitter<'_> {
    /// The program's start (`%`, its O number: the source's own for a FANUC program) and its
    /// header comment: the source's own (kept when it ends as ncthread's do: `first`, the
    /// first item that is not a `%` line), or the file's name and dialect. Whether `first`
    /// was the header comment.
    fn header(
        &mut self,
        from: crate::ir::DialectId,
        number: Option<u32>,
        first: Option<&Item>,
    ) -> bool {
        self.w.out.push_str("%\n");
        // The source's own number (a FANUC program's), else the profile's.
        let number = number
            .filter(|_| from == super::ID && self.profile.fanuc.program_number.is_none())
            .or(self.profile.fanuc.program_number)
            .unwrap_or(1);
        let _ = writeln!(self.w.out, "O{number:04}");
        match first.map(|f| &f.kind) {
            Some(ItemKind::Comment(c)) if comment_text(c).ends_with(HEADER_END) => {
                let _ = writeln!(self.w.out, "({})", comment_text(c));
                true
            }
            _ => {
                let src = self.w.src;
                let _ = writeln!(
                    self.w.out,
                    "({}, DIALECT {}{HEADER_END})",
                    comment_text(
                        std::path::Path::new(&src.name)
                            .file_name()
                            .map_or(src.name.as_str(), |n| n.to_str().unwrap_or(&src.name))
                    ),
                    comment_text(from.as_str())
                );
                false
            }
        }
    }

    /// The diagnostics that sum up the program: values rounded (or too fine), comment text
    /// transliterated or romanised.
    fn closing_diagnostics(&mut self, src: &SourceFile) {
        let (grid, decimals) = if self.inch {
            (
                "0.0001 in, leads and feeds 0.000001 in",
                "lengths take 4 decimals of an inch, leads and feeds 6",
            )
        } else {
            (
                "0.001 mm, leads and feeds 0.0001 mm",
                "lengths take 3 decimals, leads and feeds 4",
            )
        };
        // The grid a value missed, as the program says it.
        let unit = |grid: &str| match grid {
            "0.00254" => "0.0001 in".to_string(),
            "0.00508" => "0.0002 in (I as a diameter)".to_string(),
            "0.00001" => "0.000001 in".to_string(),
            g => format!("{g} mm"),
        };
        let summary = self.inexact.diagnostic(
            src,
            self.round,
            |s| {
                Diagnostic::new(
                    codes::FANW_ROUNDED,
                    format!("{} value(s) rounded to the FANUC program's grid ({grid}), the first {}; the largest deviation is {} mm", s.count, s.what, s.largest),
                )
                .help("a thread's rounded start keeps its helix through Q")
            },
            |s| {
                Diagnostic::new(
                    codes::FANW_PRECISION,
                    format!("{} is finer than the FANUC program's {} ({} value(s) in this program are; {decimals})", s.what, unit(&s.grid), s.count),
                )
                .help(format!("pass --round to round them (largest deviation {} mm, for a lead its drift at the thread's end)", s.largest))
            },
        );
        self.w.diags.extend(summary);
        let latin = self.latin.diagnostic(
            src,
            "comment text transliterated to ASCII",
            "a FANUC comment is upper-case ASCII: a letter loses its accent (`Č` → `C`), a symbol is spelled out (`°` → `DEG`) or becomes `?`; the diameter sign is `D`",
        );
        let script = self.script.diagnostic(
            src,
            "comment text in another script romanised to ASCII",
            "a FANUC comment is upper-case ASCII: letters of other scripts are romanised (Cyrillic letter by letter, Chinese characters as pinyin, each as deunicode spells it); read them on the control, or write the comments in Latin letters in the source",
        );
        self.w.diags.extend(latin.into_iter().chain(script));
    }
}

impl Emitter<'_> {
    fn diag(&mut self, code: Code, item: &Item, message: String, help: &str) {
        self.w.error(code, item.span, message, help);
    }

    /// A word as the machine's G-code system spells it: the writer builds system A's words,
    /// and system B says G33 for G32, G92 S for G50 S, G94/G95 for G98/G99, X for a dwell's
    /// U; system C says G70/G71 for G20/G21 too. (A block kept as written is the source's, in
    /// the same system.)
    fn in_system<'w>(&self, word: &'w str) -> std::borrow::Cow<'w, str> {
        let system = self.profile.fanuc.gcode_system;
        if system == GcodeSystem::A {
            return word.into();
        }
        // A G code the writer builds: a word of its own, or `G50 S2000` (a block kept as
        // written, `G71 P100 …`, is the source's and stays).
        let end = word.find(' ').unwrap_or(word.len());
        if end < word.len() && !word.starts_with("G50 S") {
            return word.into();
        }
        match word[..end].strip_prefix('G').and_then(|g| g.parse().ok()) {
            Some(a) if system.code(a) != a => {
                format!("G{:02}{}", system.code(a), &word[end..]).into()
            }
            _ => word.into(),
        }
    }

    fn write(&mut self, block: Block) {
        // Written straight into the output (taken out meanwhile, as the words are mapped by
        // `self`): `start` tells whether the line has a word yet.
        let mut line = std::mem::take(&mut self.w.out);
        let start = line.len();
        if let Some(n) = block.number.filter(|_| self.keep) {
            line.push('N');
            crate::fixed::push_whole(&mut line, n.into());
        }
        for (i, w) in block.words.iter().enumerate() {
            if line.len() > start {
                line.push(' ');
            }
            if block.verbatim == Some(i) {
                line.push_str(w);
            } else {
                line.push_str(&self.in_system(w));
            }
        }
        if let Some(c) = block
            .comment
            .map(|c| {
                if block.own_comment {
                    comment_text(&c)
                } else {
                    self.comment(&c)
                }
            })
            .filter(|c| !c.is_empty())
        {
            if line.len() > start {
                line.push(' ');
            }
            let _ = write!(line, "({c})");
        }
        if line.len() > start {
            line.push('\n');
        }
        self.w.out = line;
    }

    /// A comment's text as the FANUC program has it, its transliteration counted.
    fn comment(&mut self, text: &str) -> String {
        let (ascii, how) = transliterate(text);
        if how.latin {
            self.latin.note(self.at, text, &ascii);
        }
        if how.script {
            self.script.note(self.at, text, &ascii);
        }
        ascii
    }

    fn flush(&mut self, block: &mut Block) {
        if !block.words.is_empty() || block.comment.is_some() || block.number_only {
            let b = std::mem::take(block);
            self.write(b);
        }
    }

    fn group(&mut self, items: &[Item]) {
        self.at = items[0].span;
        let mut block = Block {
            number: items[0].block_number,
            comment: items[0].comment.as_deref().map(str::to_string),
            ..Block::default()
        };
        for item in items {
            self.item(item, &mut block);
        }
        // A G96 or G97 says its speed: what a FANUC keeps without S (the rpm surface speed
        // ran at, the last G97 S) is not the one S register LinuxCNC and the IR have.
        if let Some(item) = self.speed_word.take() {
            match self.speed {
                // Right after its G96/G97, where the reader takes it back with the mode.
                Some(s) => {
                    let mode = block.words.iter().rposition(|w| w == "G96" || w == "G97");
                    let at = mode.map_or(block.words.len(), |m| m + 1);
                    block.words.insert(at, format!("S{s}"));
                    if let Some(v) = block.verbatim.as_mut().filter(|v| **v >= at) {
                        *v += 1;
                    }
                }
                None => self.diag(
                    codes::FANW_NO_EQUIVALENT,
                    &item,
                    "a change of spindle speed mode (G96/G97) before any speed is set: a FANUC block says the speed with it".into(),
                    "give the speed (S) in the source before or with G96/G97",
                ),
            }
        }
        self.flush(&mut block);
    }

    /// `v` with a decimal point and at most 3 decimals (rounded with `--round`, or counted
    /// for one error).
    fn three(&mut self, item: &Item, what: &str, v: Length) -> String {
        let rounded = self.on_grid(item, what, v);
        self.text(rounded)
    }

    /// `v` rounded onto the grid, a value off it noted.
    fn on_grid(&mut self, item: &Item, what: &str, v: Length) -> Length {
        let grid = self.grid();
        let rounded = Length(crate::fixed::div_round(v.0 as i128, grid.0 as i128) as i64 * grid.0);
        if rounded != v {
            self.inexact.note(item.span, what, v, rounded, grid);
        }
        rounded
    }

    /// The least input increment of a length: 0.001 mm, or 0.0001 in.
    fn grid(&self) -> Length {
        if self.inch {
            Length(Length::INCH_STEP)
        } else {
            Length::from_steps(10)
        }
    }

    /// A length on the grid, with a decimal point, in the program's unit.
    fn text(&self, v: Length) -> String {
        let mut text = String::new();
        self.push_text(v, &mut text);
        text
    }

    /// [`Emitter::text`] appended to `out`.
    fn push_text(&self, v: Length, out: &mut String) {
        match self.inch {
            true => out.push_str(&v.inches_with_point().unwrap_or_else(|| v.inches().0)),
            false => v.push_mm_with_point(out),
        }
    }

    /// A lead (or a feed) with a decimal point: mm to 0.0001, or inches to 0.000001.
    fn lead_text(&self, lead: Lead) -> String {
        if self.inch {
            lead.inches_to(6).0
        } else {
            lead.mm_with_point()
        }
    }

    /// The axis words of a move to `to`.
    fn axes(&mut self, item: &Item, to: Pos) -> Vec<String> {
        let mut words = Vec::with_capacity(2);
        if let Some(x) = to.x {
            words.push(self.word('X', item, "X", x));
        }
        if let Some(z) = to.z {
            words.push(self.word('Z', item, "Z", z));
        }
        words
    }

    /// `letter` and [`Emitter::three`]'s text of `v`, in one allocation.
    fn word(&mut self, letter: char, item: &Item, what: &str, v: Length) -> String {
        let mut word = String::with_capacity(12);
        word.push(letter);
        let rounded = self.on_grid(item, what, v);
        self.push_text(rounded, &mut word);
        word
    }

    /// Starts a new block when this one moves already, then puts the motion word.
    fn motion_block(&mut self, block: &mut Block, g: &'static str) {
        if block.moves {
            let number = block.number.take();
            self.flush(block);
            block.number = number.filter(|_| false);
        }
        block.moves = true;
        if self.motion != Some(g) {
            block.words.push(g.to_string());
            self.motion = Some(g);
        }
    }

    fn feed_word(&mut self, feed: Length, block: &mut Block) {
        let lead = Lead::from_length(feed);
        if self.f != Some((lead, false)) {
            let text = if self.inch {
                lead.inches_to(6).0
            } else {
                feed.mm_with_point()
            };
            block.words.push(format!("F{text}"));
            self.f = Some((lead, false));
        }
    }

    fn item(&mut self, item: &Item, block: &mut Block) {
        let continues =
            matches!(&item.kind, ItemKind::ThreadPass(p) if p.start == SyncStart::Continue);
        if !continues && !matches!(item.kind, ItemKind::Comment(_)) && !self.deferred.is_empty() {
            self.flush(block);
            for (text, at) in std::mem::take(&mut self.deferred) {
                self.at = at;
                self.write(Block {
                    comment: Some(text),
                    ..Block::default()
                });
            }
        }
        self.at = item.span;
        if !self.kind(item, block) {
            return;
        }
        if !matches!(
            item.kind,
            ItemKind::ThreadCycle(_) | ItemKind::ThreadPass(_)
        ) {
            self.w.pos = item.kind.end_position(self.w.pos);
        }
    }

    /// Writes an item into `block` (or into blocks of its own): one arm per kind of item.
    /// `false` when it is refused (a diagnostic says why) and the position is not moved.
    fn kind(&mut self, item: &Item, block: &mut Block) -> bool {
        match &item.kind {
            ItemKind::Rapid { to } => {
                self.sync_end = None;
                self.motion_block(block, "G00");
                let words = self.axes(item, *to);
                block.words.extend(words);
            }
            ItemKind::Feed { to, feed } => {
                self.sync_end = None;
                self.motion_block(block, "G01");
                let words = self.axes(item, *to);
                block.words.extend(words);
                self.feed_word(*feed, block);
            }
            ItemKind::Arc {
                to,
                centre,
                clockwise,
                feed,
            } => {
                self.sync_end = None;
                self.arc(item, *to, **centre, *clockwise, *feed, block);
            }
            ItemKind::ThreadPass(pass) => self.thread_pass(item, pass, block),
            ItemKind::ThreadCycle(cycle) => {
                self.flush(block);
                self.thread_cycle(item, cycle);
            }
            // Refused by legalisation (no rigid tapping, no machine coordinates).
            ItemKind::TapCycle(_) | ItemKind::MachineMove(_) | ItemKind::Roughing(_) => {}
            ItemKind::Spindle { speed, direction } => self.spindle(*speed, *direction, block),
            ItemKind::SpindleStop => self.spindle_stop(block),
            ItemKind::SpindleMode(mode) => return self.spindle_mode(item, mode, block),
            ItemKind::Tool { number, offset } => self.tool(item, *number, *offset, block),
            ItemKind::GearRange { code, machine } => {
                self.machine_m(item, *code, *machine, true, block)
            }
            ItemKind::MachineCode { code, machine } => {
                self.machine_m(item, *code, *machine, false, block)
            }
            ItemKind::FeedMode(mode) => self.feed_mode(*mode, block),
            ItemKind::ProgramEnd(EndCode::M2) => block.words.push("M02".into()),
            ItemKind::ProgramEnd(EndCode::M30) => block.words.push("M30".into()),
            ItemKind::Comment(text) => self.comment_item(text, item.span, block),
            // Its effect is already in the items that use it: a comment of its own.
            ItemKind::ParamAssign { number, value } => {
                self.flush(block);
                self.comment_block(format!("R{number:02}={value}"));
            }
            ItemKind::Opaque {
                dialect: super::ID,
                text,
                block: context,
            } => self.kept(text, context.is_some_and(|c| c.cycle), block),
            ItemKind::Opaque { dialect, text, .. } => {
                self.as_comment(item, block, &format!("{dialect}: {text}"));
            }
            // Only its own dialect sees a cycle whole (`lower::unroll`).
            ItemKind::ModelCycle(cycle) => self.kept(&cycle.text, true, block),
            ItemKind::Delimiter => {}
            ItemKind::Coolant(c) => block.words.push(coolant_word(*c).into()),
            ItemKind::Stop { optional } => block
                .words
                .push(if *optional { "M01" } else { "M00" }.into()),
            ItemKind::Dwell { seconds } => return self.dwell(item, *seconds, block),
            ItemKind::Compensation(c) => self.compensation(item, c, block),
            ItemKind::WorkOffset(n) => self.work_offset(item, *n, block),
            // A zero feed no move runs at (the FANUC reader refuses `F0`).
            ItemKind::FeedRate(feed) if *feed == Length::ZERO => self.as_comment(item, block, "F0"),
            ItemKind::FeedRate(feed) => self.feed_rate(*feed, block),
        }
        true
    }

    /// A machine's M code (a gear range, or a code of the machine's own): the same
    /// machine's back in its block, another machine's as a comment.
    fn machine_m(
        &mut self,
        item: &Item,
        code: u32,
        machine: crate::ir::DialectId,
        gear: bool,
        block: &mut Block,
    ) {
        if machine == super::ID {
            block.words.push(format!("M{code:02}"));
        } else if gear {
            let text = format!("M{code}: gear range of the source machine");
            self.as_comment(item, block, &text);
        } else {
            self.as_comment(item, block, &crate::ir::machine_code_note(code, machine));
        }
    }

    /// A FANUC block kept as written. A cycle may leave another motion code (G90, G94) and F
    /// in force: the next move writes both. A contour's block with only its number keeps it
    /// (G70's P and Q name it).
    fn kept(&mut self, text: &str, cycle: bool, block: &mut Block) {
        self.sync_end = None;
        if cycle {
            self.motion = None;
            self.f = None;
        }
        if text.is_empty() {
            block.number_only = true;
        } else {
            block.verbatim = Some(block.words.len());
            block.words.push(text.to_string());
        }
    }

    /// A block that is only a comment.
    fn comment_block(&mut self, text: String) {
        self.write(Block {
            comment: Some(text),
            ..Block::default()
        });
    }

    /// M05: the spindle stands from here on.
    fn spindle_stop(&mut self, block: &mut Block) {
        self.turning = false;
        block.words.push("M05".into());
    }

    /// The spindle's speed and direction words.
    fn spindle(
        &mut self,
        speed: Option<u32>,
        direction: Option<SpindleDirection>,
        block: &mut Block,
    ) {
        // After a bare G97 the start says the speed the program has (`speed_unsaid`); a G97
        // that must say its speed (`speed_word`) says it before the block's M03/M04, where the
        // reader takes an S (written after M03, it read back as the start's own speed).
        let speed = speed.or(self
            .speed
            .filter(|_| direction.is_some() && (self.speed_unsaid || self.speed_word.is_some())));
        if let Some(s) = speed {
            block.words.push(format!("S{s}"));
            self.speed = Some(s);
            self.speed_word = None;
            self.speed_unsaid = false;
        }
        if direction.is_some() {
            self.turning = true;
        }
        match direction {
            Some(SpindleDirection::Clockwise) => block.words.push("M03".into()),
            Some(SpindleDirection::CounterClockwise) => block.words.push("M04".into()),
            None => {}
        }
    }

    /// G97, or G96 with its limit (G50 S) on a line of its own before it; `false` when
    /// the surface speed is refused.
    fn spindle_mode(&mut self, item: &Item, mode: &SpindleMode, block: &mut Block) -> bool {
        match mode {
            // While the spindle stands, a G97 needs no S: nothing runs at the rpm the
            // control keeps, and the next start says its S (the reader reads it back). So
            // too before any speed (`G18 G20 G40 G80 G97 G99` heading a program).
            SpindleMode::Rpm if !self.turning && (self.surface_speed || self.speed.is_none()) => {
                self.surface_speed = false;
                block.words.push("G97".into());
                self.speed_unsaid = true;
                true
            }
            SpindleMode::Rpm => {
                self.surface_speed = false;
                block.words.push("G97".into());
                self.speed_word = Some(item.clone());
                true
            }
            SpindleMode::SurfaceSpeed { feet: true, .. } if !self.inch => {
                self.diag(
                    codes::FANW_NO_EQUIVALENT,
                    item,
                    "a surface speed in feet per minute (G96 under G20): the FANUC program is written in millimetres (G21), where G96's S is m/min, and the unit cannot change after its start".to_string(),
                    "program the surface speed in m/min (G21) in the source, or cut at a speed in rpm (G97)",
                );
                false
            }
            SpindleMode::SurfaceSpeed { feet: false, .. } if self.inch => {
                self.diag(
                    codes::FANW_NO_EQUIVALENT,
                    item,
                    "a surface speed in metres per minute (G96 under G21) in a program written in inches: the FANUC program is in inches (G20), where G96's S is ft/min, and the unit cannot change after its start".to_string(),
                    "program the surface speed in ft/min (G20) in the source, or cut at a speed in rpm (G97)",
                );
                false
            }
            SpindleMode::SurfaceSpeed { limit, .. } => self.surface_speed(item, *limit, block),
        }
    }

    /// G96 with its speed limit `limit`; `false` when it is refused.
    fn surface_speed(&mut self, item: &Item, limit: Option<Decimal>, block: &mut Block) -> bool {
        let limit = match limit {
            Some(d) => match d.to_whole() {
                Ok(n) if n > 0 => Some(n),
                _ => {
                    self.diag(
                        codes::FANW_PRECISION,
                        item,
                        format!("the surface speed's limit of {d} rpm is not a whole number of rpm, which G50 S takes"),
                        "write the limit in whole rpm in the source",
                    );
                    return false;
                }
            },
            None => None,
        };
        let changed = limit.is_some() && limit != self.limit;
        // Under G96 already, a new limit is its G50 S alone.
        let alone = self.surface_speed && changed;
        match (limit, self.limit) {
            (Some(n), last) if last != Some(n) => {
                // The limit on a line of its own before the G96, which keeps the block's
                // number and comment; alone, the limit's line keeps them.
                let (comment, number) = (block.comment.take(), block.number.take());
                self.flush(block);
                let mut line = Block {
                    words: vec![format!("G50 S{n}")],
                    ..Block::default()
                };
                if alone {
                    (line.comment, line.number) = (comment, number);
                } else {
                    (block.comment, block.number) = (comment, number);
                }
                self.write(line);
                self.limit = Some(n);
            }
            (None, Some(_)) => {
                self.diag(
                    codes::FANW_NO_EQUIVALENT,
                    item,
                    "a surface speed without a speed limit after one with a limit: a FANUC program cannot lift the limit G50 S set".into(),
                    "give this G96 a limit in the source (G96 … D)",
                );
                return false;
            }
            _ => {}
        }
        if !alone {
            block.words.push("G96".into());
            self.speed_word = Some(item.clone());
        }
        self.surface_speed = true;
        true
    }

    /// G98 or G99. A feed after a feed mode word states its F again (what F holds across
    /// the change is not something to rely on).
    fn feed_mode(&mut self, mode: FeedMode, block: &mut Block) {
        block.words.push(
            if mode == FeedMode::PerRev {
                "G99"
            } else {
                "G98"
            }
            .into(),
        );
        if matches!(self.f, Some((_, false))) {
            self.f = None;
        }
    }

    /// A comment: the block's own, or (inside a G32 chain, where a comment block would
    /// stand between two thread blocks) one that waits until the chain ends.
    fn comment_item(&mut self, text: &str, span: Span, block: &mut Block) {
        if self.sync_end.is_some() && self.sync_end == Some(self.w.pos) {
            self.deferred.push((text.to_string(), span));
        } else if block.words.is_empty() && block.comment.is_none() {
            block.comment = Some(text.to_string());
        } else {
            self.flush(block);
            block.comment = Some(text.to_string());
        }
    }

    /// G04 U (X in systems B and C, P in seconds on a Haas) in a block of its own; `false`
    /// when the dwell is finer than the 0.001 s it takes.
    fn dwell(&mut self, item: &Item, seconds: Decimal, block: &mut Block) -> bool {
        let Ok(ms) = seconds.to_scaled(3) else {
            self.diag(
                codes::FANW_PRECISION,
                item,
                format!("the dwell of {seconds} s needs more than the 0.001 s a G04 takes"),
                "write the dwell in whole milliseconds in the source",
            );
            return false;
        };
        self.flush(block);
        let comment = block.comment.take();
        self.write(Block {
            number: item.block_number,
            words: vec![
                "G04".into(),
                // System B's dwell is X (U is a cycle's word there); a Haas's is P in
                // seconds (the profile's `haas_dwell_p`: the word its manual gives).
                format!(
                    "{}{}",
                    match self.profile.fanuc.gcode_system {
                        _ if self.profile.fanuc.haas_dwell_p => 'P',
                        GcodeSystem::A => 'U',
                        GcodeSystem::B | GcodeSystem::C => 'X',
                    },
                    Length::from_steps(ms * 10).mm_with_point()
                ),
            ],
            comment,
            moves: false,
            own_comment: false,
            number_only: false,
            verbatim: None,
        });
        true
    }

    /// G40, G41 or G42; a compensation a FANUC lathe has no form of is refused.
    fn compensation(&mut self, item: &Item, c: &Compensation, block: &mut Block) {
        match c {
            Compensation::Off => block.words.push("G40".into()),
            Compensation::FromTool { right, tool: None } => {
                block.words.push(if *right { "G42" } else { "G41" }.into())
            }
            _ => {
                let what = match c {
                    Compensation::FromTool { tool: Some(d), .. } => {
                        format!("cutter radius compensation with tool table entry {d}")
                    }
                    _ => "cutter radius compensation with a diameter in the program (G41.1/G42.1)"
                        .into(),
                };
                self.diag(
                    codes::FANW_NO_EQUIVALENT,
                    item,
                    format!("{what}: a FANUC lathe takes the nose radius from the offset of the tool in use"),
                    "compensate with the tool's own offset (G41/G42 without D) in the source",
                );
            }
        }
    }

    /// G54–G59; another work offset is refused.
    fn work_offset(&mut self, item: &Item, n: u8, block: &mut Block) {
        if (1..=6).contains(&n) {
            block.words.push(format!("G{}", 53 + u32::from(n)))
        } else {
            self.diag(
                codes::FANW_NO_EQUIVALENT,
                item,
                format!(
                    "work offset {n} (G59.{}) has no form in FANUC lathe G-code ncthread writes",
                    n.saturating_sub(6)
                ),
                "use G54–G59 in the source",
            )
        }
    }

    /// A feed of its own: in a G01 block when F last held a lead, unless the motion in force
    /// is a G00 or G01 (whose F is a feed: a rapid's F, read as a feed of its own).
    fn feed_rate(&mut self, feed: Length, block: &mut Block) {
        if self.f != Some((Lead::from_length(feed), false)) {
            let lead =
                matches!(self.f, Some((_, true))) && !matches!(self.motion, Some("G00" | "G01"));
            if lead || self.motion == Some("G32") {
                self.motion_word_only(block, "G01");
            }
            self.feed_word(feed, block);
        }
    }

    fn motion_word_only(&mut self, block: &mut Block, g: &'static str) {
        if self.motion != Some(g) {
            block.words.push(g.to_string());
            self.motion = Some(g);
        }
    }

    fn as_comment(&mut self, item: &Item, block: &mut Block, text: &str) {
        self.flush(block);
        self.write(Block {
            comment: Some(format!("{text} (not converted)")),
            ..Block::default()
        });
        self.w.report(
            Diagnostic::new(
                codes::FANW_COMMENT,
                format!("`{text}` has no FANUC equivalent; it is written as a comment"),
            )
            .at(self.w.src, item.span)
            .help("check the FANUC program by hand where this matters"),
        );
    }

    /// `T0101`: the tool and its offset, two digits each.
    fn tool(&mut self, item: &Item, number: Option<u32>, offset: Option<u32>, block: &mut Block) {
        let Some(t) = number else {
            self.diag(
                codes::FANW_NO_EQUIVALENT,
                item,
                "a tool offset without a tool: a FANUC T word names both".into(),
                "give the tool in the source",
            );
            return;
        };
        let o = offset.unwrap_or(match self.profile.fanuc.tool_offset {
            ToolOffset::Same => t,
            ToolOffset::None => 0,
        });
        if t > 99 || o > 99 || t == 0 {
            self.diag(
                codes::FANW_TOOL,
                item,
                format!("tool {t} with offset {o}: the T word holds a tool of 1–99 and an offset of 0–99 (T0101)"),
                "renumber the tool in the source to the turret station it stands in",
            );
            return;
        }
        block.words.push(format!("T{t:02}{o:02}"));
    }

    /// `G02`/`G03 X Z I K F`: I the centre's X offset from the start as a radius value.
    fn arc(
        &mut self,
        item: &Item,
        to: Pos,
        centre: Pos,
        clockwise: bool,
        feed: Length,
        block: &mut Block,
    ) {
        let (Some((sx, sz)), Some((cx, cz)), Some((ex, ez))) =
            (self.w.pos.known(), centre.known(), to.known())
        else {
            self.diag(
                codes::FANW_NO_EQUIVALENT,
                item,
                "an arc from a position that is not known: its centre cannot be written".into(),
                "move to an absolute X and Z before the arc",
            );
            return;
        };
        self.motion_block(block, if clockwise { "G02" } else { "G03" });
        let words = self.axes(item, Pos::new(ex, ez));
        block.words.extend(words);
        let dx = cx - sx;
        let grid = self.grid();
        let on_grid = dx.0 % (2 * grid.0) == 0 && (cz - sz).0 % grid.0 == 0;
        // A centre off the grid (an R arc's, from the source's radius) is written as the R
        // the control takes, where the centre it finds from it stays within 0.0005 mm.
        if !on_grid
            && (sx, sz) != (ex, ez)
            && !lower::arc::over_half_turn((sx, sz), (ex, ez), (cx, cz), clockwise)
        {
            let (r1, _) = lower::arc::radii((sx, sz), (ex, ez), (cx, cz));
            let r = Length(
                crate::fixed::div_round(Length::from_mm_f64(r1).0 as i128, grid.0 as i128) as i64
                    * grid.0,
            );
            let off =
                lower::arc::centre_miss((sx, sz), (ex, ez), (cx, cz), r.to_mm_f64(), clockwise);
            if off <= 0.0005 && r.0 > 0 {
                block.words.push(format!("R{}", self.text(r)));
                self.feed_word(feed, block);
                return;
            }
        }
        let i = if dx.0 % (2 * grid.0) == 0 {
            self.text(Length(dx.0 / 2))
        } else {
            let rounded =
                Length(crate::fixed::div_round(dx.0 as i128, 2 * grid.0 as i128) as i64 * grid.0);
            self.inexact.note(
                item.span,
                "I (as a diameter)",
                dx,
                rounded + rounded,
                grid + grid,
            );
            self.text(rounded)
        };
        let k = self.three(item, "K", cz - sz);
        block.words.push(format!("I{i}"));
        block.words.push(format!("K{k}"));
        self.feed_word(feed, block);
    }

    fn thread_pass(&mut self, item: &Item, pass: &ThreadPass, block: &mut Block) {
        let segments = match lower::pass_segments(self.w.pos, pass) {
            Ok(s) => s,
            Err(_) => {
                self.diag(
                    codes::FANW_NO_EQUIVALENT,
                    item,
                    "this thread pass needs its start point, which is not known".into(),
                    "move to the start of the thread with X and Z first",
                );
                return;
            }
        };
        let in_chain = self.sync_end.is_some() && self.sync_end == Some(self.w.pos);
        let end = pass.end_position(self.w.pos);
        // Refused by legalisation (the table's SyncInfeed, SteepSync and IndexWaitInCut):
        // the position goes on, so that what follows reads right.
        let refused = segments.iter().any(lower::SyncSegment::is_steep)
            || (in_chain && matches!(pass.start, SyncStart::Index(_)));
        if refused {
            self.w.pos = end;
            self.sync_end = Some(end);
            return;
        }
        let angle = match pass.start {
            SyncStart::Continue if !in_chain => {
                self.diag(
                    codes::FANW_INDEX_WAIT,
                    item,
                    "this thread move continues a synchronised move that does not end where it starts".into(),
                    "this is a bug in the program's reader; report it with the program",
                );
                return;
            }
            SyncStart::Continue => None,
            SyncStart::Index(a) => Some(a),
        };
        let Some(lead) = self.pass_lead(item, pass, &segments) else {
            return;
        };
        // A start rounded onto the grid (`--round`) keeps its helix: the angle runs on by
        // the turns between the exact start and the written one, as the other writers do.
        let grid = if self.inch { 254 } else { 100 };
        let angle = angle.map(|a| {
            let (from, to) = (
                segments.first().and_then(|s| s.from.z),
                segments.first().and_then(|s| s.to.z),
            );
            let a = crate::dialect::write::start_on(grid, from, to, pass.lead, a);
            Angle(a.0.rem_euclid(360_000))
        });
        for (n, seg) in segments.iter().enumerate() {
            self.motion_block(block, "G32");
            let words = self.axes(item, seg.to);
            block.words.extend(words);
            if (n == 0 && angle.is_some()) || self.f != Some((lead, true)) {
                block.words.push(format!("F{}", self.lead_text(lead)));
                self.f = Some((lead, true));
            }
            if n == 0
                && let Some(a) = angle.filter(|a| *a != Angle::ZERO)
            {
                block.words.push(format!("Q{}", a.0));
            }
        }
        self.w.pos = pass.end_position(self.w.pos);
        self.sync_end = Some(self.w.pos);
    }

    /// A pass's lead in the program's 4 decimals: another is refused (`None`), or with
    /// --round rounded with the drift at the thread's end as its deviation.
    fn pass_lead(
        &mut self,
        item: &Item,
        pass: &ThreadPass,
        segments: &[lower::SyncSegment],
    ) -> Option<Lead> {
        let (lead, exact) = if self.inch {
            let (_, lead) = pass.lead.inches_to(6);
            (lead, lead == pass.lead)
        } else {
            let (units, exact) = pass.lead.in_units(4);
            (Lead::from_units(units, 4), exact)
        };
        if lead.0 <= 0 {
            self.diag(
                codes::FANW_PRECISION,
                item,
                format!(
                    "the lead {} mm rounds to 0 in the FANUC program's 0.0001 mm",
                    pass.lead
                ),
                "a thread needs a lead the control can hold",
            );
            return None;
        }
        if !exact {
            let travel = match (
                segments.first().and_then(|s| s.from.z),
                segments.last().and_then(|s| s.to.z),
            ) {
                (Some(a), Some(b)) => (b - a).abs(),
                _ => Length::ZERO,
            };
            let drift = pass.lead.drift(lead, travel);
            // The grid a lead misses: 0.0001 mm, or 0.000001 in (said by `unit`).
            let grid = Length(if self.inch { 1 } else { Length::STEP });
            self.inexact
                .note_lead(item.span, "lead F", pass.lead, drift, grid);
        }
        Some(lead)
    }

    fn thread_cycle(&mut self, item: &Item, cycle: &ThreadCycle) {
        let Some(steps) = self.w.cycle_steps(cycle, item.span, "D") else {
            return;
        };
        for step in steps {
            match step {
                write::CycleStep::Comment(comment) => self.write(Block {
                    comment: Some(comment),
                    own_comment: true,
                    ..Block::default()
                }),
                write::CycleStep::Move(moved) => {
                    let mut block = Block::default();
                    self.item(&moved, &mut block);
                    self.flush(&mut block);
                }
            }
        }
        self.w.pos = item.kind.end_position(self.w.pos);
    }
}

/// The M code of a coolant command.
fn coolant_word(c: Coolant) -> &'static str {
    match c {
        Coolant::Mist => "M07",
        Coolant::Flood => "M08",
        Coolant::Off => "M09",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The writer's text as a string, as the tests read it.
    fn emit(
        program: &Program,
        src: &SourceFile,
        profile: &Profile,
        round: bool,
    ) -> (Option<String>, Vec<Diagnostic>) {
        let options = crate::dialect::WriteOptions {
            round,
            ..Default::default()
        };
        let (out, diags) =
            crate::dialect::Dialect::write(&super::super::Fanuc, program, src, profile, &options);
        (out.map(|o| o.into_string().expect("in memory")), diags)
    }
    use crate::ir::{SpindleDirection, ThreadPass};

    fn mm(v: i64) -> Length {
        Length::from_mm(v)
    }

    fn write(kinds: Vec<ItemKind>) -> (Option<String>, Vec<Diagnostic>) {
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
        emit(
            &program,
            &SourceFile::new("t", ""),
            &Profile::default(),
            false,
        )
    }

    /// A FANUC program read and written back with the default profile.
    fn fanuc_to_fanuc(text: &str) -> String {
        let src = SourceFile::new("t.nc", text);
        let (program, diags) = super::super::front::parse(
            &src,
            &Default::default(),
            crate::dialect::Unsupported::Error,
        );
        assert!(!crate::diag::has_errors(&diags), "{diags:?}");
        let (out, diags) = emit(&program, &src, &Profile::default(), false);
        out.unwrap_or_else(|| panic!("{diags:?}"))
    }

    /// The frame's `G21 G99` stands for the source's header feed mode, which is not written
    /// again; a source line that holds it with a move stays one block, with its comment.
    #[test]
    fn the_header_feed_mode_is_not_written_again_and_its_line_stays_one_block() {
        let out = fanuc_to_fanuc(
            "%\nO0001\n(HEADER)\nG99 (FEED) G0 X20. Z5.\nS500 M3\nG1 Z-10. F0.2\nM30\n%\n",
        );
        assert_eq!(out.matches("G99").count(), 1, "{out}");
        assert!(out.contains("\n(HEADER)\nG00 X20. Z5. (FEED)\n"), "{out}");
    }

    /// A new limit under G96 is its `G50 S` alone, on its source line with its comment (the
    /// comment was left on a line of its own after it); before a G96, the G96 keeps the
    /// comment of its line.
    #[test]
    fn a_limit_alone_keeps_its_comment() {
        let out = fanuc_to_fanuc(
            "G21 G99\nG50 S2000\nG96 S200 M03 (CSS)\nG50 S2500 (CLAMP)\nG00 X20. Z2.\nM30\n",
        );
        assert!(
            out.contains("\nG50 S2000\nG96 S200 M03 (CSS)\nG50 S2500 (CLAMP)\nG00"),
            "{out}"
        );
    }

    #[test]
    fn comments_are_upper_case_ascii_without_parentheses() {
        assert_eq!(comment_text("závit (Ø20) ok"), "ZAVIT [D20] OK");
        assert_eq!(comment_text("ø10 ⌀12 ∅14"), "D10 D12 D14");
        assert_eq!(comment_text("50% ; x"), "50 PCT , X");
    }

    #[test]
    fn a_transliteration_says_whether_accents_went_or_a_script_was_romanised() {
        let t = |latin, script| Transliteration { latin, script };
        assert_eq!(
            transliterate("(Ø20 TURN)"),
            ("[D20 TURN]".into(), t(false, false))
        );
        assert_eq!(transliterate("Závit"), ("ZAVIT".into(), t(true, false)));
        assert_eq!(transliterate("60°"), ("60DEG".into(), t(true, false)));
        assert_eq!(
            transliterate("Резьба M20"),
            ("REZ'BA M20".into(), t(false, true))
        );
        assert_eq!(transliterate("螺纹"), ("LUO WEN".into(), t(false, true)));
        assert_eq!(
            transliterate("Závit Резьба"),
            ("ZAVIT REZ'BA".into(), t(true, true))
        );
    }

    /// Accents dropped and other scripts romanised: one warning each per program, with the
    /// count and the first comment; a diameter sign alone is no warning.
    #[test]
    fn transliterated_comments_are_reported_once_per_program_and_kind() {
        let src = SourceFile::new(
            "t.ngc",
            "(Ø20 TURN)\n(Závit M20)\nG7 G0 X20 Z5 (Čep)\n(Резьба M20)\n(螺纹)\nM2\n",
        );
        let (program, diags) = crate::parse(
            &src,
            crate::dialect::iso::ID,
            &Profile::default(),
            crate::dialect::Unsupported::Error,
        );
        assert!(diags.is_empty(), "{diags:?}");
        let (out, diags) = emit(&program, &src, &Profile::default(), false);
        let out = out.unwrap();
        for line in [
            "(D20 TURN)",
            "(ZAVIT M20)",
            "G00 X20. Z5. (CEP)",
            "(REZ'BA M20)",
            "(LUO WEN)",
        ] {
            assert!(out.contains(&format!("{line}\n")), "{line}: {out}");
        }
        let messages: Vec<(&str, &str, u32, u32)> = diags
            .iter()
            .map(|d| {
                let at = d.location.as_ref().unwrap();
                (d.code.id, d.message.as_str(), at.line, at.column)
            })
            .collect();
        assert_eq!(
            messages,
            [
                (
                    "FANW008",
                    "comment text transliterated to ASCII: `Závit M20` → `ZAVIT M20` (2 comments, the first shown)",
                    2,
                    2
                ),
                (
                    "FANW008",
                    "comment text in another script romanised to ASCII: `Резьба M20` → `REZ'BA M20` (2 comments, the first shown)",
                    4,
                    2
                ),
            ]
        );
        // A long comment is shown by its start.
        let long = "Závit ".repeat(EXAMPLE_CHARS / 6 + 1);
        let src = SourceFile::new("t.ngc", format!("({long})\nM2\n"));
        let (program, _) = crate::parse(
            &src,
            crate::dialect::iso::ID,
            &Profile::default(),
            crate::dialect::Unsupported::Error,
        );
        let (_, diags) = emit(&program, &src, &Profile::default(), false);
        assert_eq!(
            diags[0].message,
            format!(
                "comment text transliterated to ASCII: `{}…` → `{}…`",
                &long[..long.char_indices().nth(EXAMPLE_CHARS).unwrap().0],
                &"ZAVIT ".repeat(EXAMPLE_CHARS / 6 + 1)[..EXAMPLE_CHARS]
            )
        );
        assert_eq!(
            codes::FANW_TRANSLITERATED.severity,
            crate::diag::Severity::Warning
        );
    }

    #[test]
    fn a_pass_with_its_runout_is_one_chain_and_its_angle_is_q() {
        let pass = ThreadPass {
            to: Pos::new(mm(20), mm(-20)),
            lead: Lead::from_length(Length::from_steps(15_000)),
            start: SyncStart::Index(Angle(180_000)),
            infeed: None,
            entry: None,
            exit: Some(crate::ir::Chamfer {
                length: Length::from_steps(15_000),
                offset: Length::from_steps(30_000),
            }),
        };
        let (out, d) = write(vec![
            ItemKind::Spindle {
                speed: Some(500),
                direction: Some(SpindleDirection::Clockwise),
            },
            ItemKind::Rapid {
                to: Pos::new(mm(20), mm(5)),
            },
            ItemKind::pass(pass),
            ItemKind::Tool {
                number: Some(3),
                offset: None,
            },
        ]);
        assert!(d.is_empty(), "{d:?}");
        let out = out.unwrap();
        assert!(
            out.contains("G32 X20. Z-18.5 F1.5 Q180000\nX23. Z-20.\n"),
            "{out}"
        );
        assert!(
            out.starts_with("%\nO0001\n(T, DIALECT ISO, CONVERTED BY NCTHREAD)\nG21 G99\n"),
            "{out}"
        );
        assert!(out.contains("T0303\n"), "{out}");
        assert!(
            !out.contains("M30"),
            "no end the source does not have: {out}"
        );
    }

    #[test]
    fn tools_over_99_and_lengths_off_the_grid_are_refused() {
        let (out, d) = write(vec![ItemKind::Tool {
            number: Some(120),
            offset: Some(1),
        }]);
        assert!(out.is_none());
        assert_eq!(d[0].code, codes::FANW_TOOL);
        let (out, d) = write(vec![ItemKind::Rapid {
            to: Pos::new(Length::from_steps(200_005), mm(5)),
        }]);
        assert!(out.is_none());
        assert_eq!(d[0].code, codes::FANW_PRECISION);
    }

    /// A block kept as written is the source's, in the machine's system already: in system C
    /// a bare `G73` (the roughing cycle's first block) stays `G73`, while a G code the writer
    /// builds is spelled in C (`G21` → `G71`, `G99` → `G95`).
    #[test]
    fn a_kept_block_is_never_renumbered() {
        let profile =
            Profile::from_toml(&SourceFile::new("p", "[fanuc]\ngcode_system = \"C\"\n")).unwrap();
        let text = "G71 G90 G95\nG00 X50. Z3.\nG73\nG73 P70 Q80 U0.5 W0.2 F0.3\nN70 G00 X18.\nN80 G01 Z-12.\nG72 P70 Q80\nG76\nM30\n";
        let src = SourceFile::new("t", text);
        let (program, d) = crate::dialect::fanuc::front::parse(
            &src,
            &profile.fanuc,
            crate::dialect::Unsupported::Error,
        );
        assert!(d.is_empty(), "{d:?}");
        let (out, d) = emit(&program, &src, &profile, false);
        let out = out.expect("written");
        assert!(d.is_empty(), "{d:?}");
        assert!(out.contains("G71 G90 G95\n"), "{out}");
        assert!(out.contains("\nG73\nG73 P70 Q80"), "{out}");
        assert!(out.contains("\nG76\n"), "{out}");
    }
}

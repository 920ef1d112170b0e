//! The nc31 front end: frames → groups → IR items, with the dialect's rules as diagnostics.
//!
//! Frames joined by `*` form a group that executes as one block. A group that starts with
//! G31, G32 or G33 is a thread group; any other group sets feed, spindle, tool, speed range
//! and/or moves the tool (rapid when any coordinate has `~`).

use std::collections::{HashMap, HashSet};
use std::ops::Range;

use super::syntax::{self, Frame, Line as SyntaxLine, Modifier, Word};
use crate::diag::{Code, Diagnostic};
use crate::dialect::Unsupported;
use crate::dialect::nc31::codes;
use crate::dialect::nc31::profile::Nc31Profile;
use crate::dialect::read::{Keep, Reader, UnsupportedWording};
use crate::fixed::Length;
use crate::ir::{ItemKind, Program};
use crate::source::{LinePlace, SourceFile, Span};

mod arc;
mod block;
mod chamfer;
mod repeat;
mod supported;
#[cfg(test)]
mod tests;
mod thread;

use repeat::Reported;

/// How the nc31 reader words its unsupported policy.
const UNSUPPORTED: UnsupportedWording = UnsupportedWording {
    code: codes::NCR_UNSUPPORTED,
    more: "in this group",
    in_one: "in a group",
    many: "groups",
    own_block: "put this word in a group of its own",
    refuse_help: "ncthread converts only what the guide documents; `--unsupported warn` keeps such a group as an opaque item",
    keep_help: "kept as an opaque group: only an nc31 target writes it back, and positions after it are unknown",
};

#[derive(Clone, Debug, Default)]
pub struct Options {
    pub unsupported: Unsupported,
}

/// The feed register.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Feed {
    /// No F frame yet.
    Unset,
    /// mm per revolution.
    Set(Length),
    /// A thread group (starting on this line) left the feed undefined. **\[decided\]**
    AfterThread(u32),
}

/// The most frames that the G25 repeats of one program may unroll, so that a hostile
/// program cannot make the reader build millions of items. **\[decided\]**
pub const REPEAT_LIMIT: usize = 10_000;

/// A frame of a group with the line it stands on.
#[derive(Clone)]
struct GroupFrame {
    frame: Frame,
    place: LinePlace,
}

impl GroupFrame {
    fn word(&self) -> &Word {
        self.frame
            .word
            .as_ref()
            .expect("groups hold only frames with a word")
    }

    fn text<'s>(&self, src: &'s SourceFile) -> &'s str {
        &src.line_of(self.place).text[self.word().range.clone()]
    }
}

struct FrontEnd<'a> {
    r: Reader<'a>,
    profile: &'a Nc31Profile,
    options: &'a Options,
    feed: Feed,
    /// The frames of the group being read.
    group: Vec<GroupFrame>,
    /// The open group contains a frame that could not be read: it is dropped when it ends.
    group_broken: bool,
    /// The groups read so far, in order, and whether each could be read (a group with an
    /// unreadable frame is not): what a G25 repeats.
    groups: Vec<(Vec<GroupFrame>, bool)>,
    /// How many frames the groups before each group hold (one more entry than `groups`).
    frames_before: Vec<usize>,
    /// Frame number → (group, frame within it) of its first use, and whether another frame
    /// has the same number.
    numbers: HashMap<u32, (usize, usize, bool)>,
    /// The G25 groups among `groups`, in order.
    repeats: Vec<usize>,
    /// Frames the G25 repeats have unrolled so far (at most [`REPEAT_LIMIT`]).
    unrolled: usize,
    /// The diagnostics a repeat does not report again, gathered up to the given count of
    /// the reader's diagnostics (only once a repeat has something to say).
    reported: (HashSet<Reported>, usize),
}

/// Reads an nc31 program. The program is usable only when no diagnostic is an error.
#[cfg(test)]
pub fn parse(
    src: &SourceFile,
    profile: &Nc31Profile,
    options: &Options,
) -> (Program, Vec<Diagnostic>) {
    read(src, profile, options, Keep::Program)
}

/// [`parse`], keeping the program or only the diagnostics.
pub(crate) fn read(
    src: &SourceFile,
    profile: &Nc31Profile,
    options: &Options,
    keep: Keep,
) -> (Program, Vec<Diagnostic>) {
    let mut fe = FrontEnd {
        r: Reader::new(src, super::ID, keep),
        profile,
        options,
        feed: Feed::Unset,
        group: Vec::new(),
        group_broken: false,
        groups: Vec::new(),
        frames_before: vec![0],
        numbers: HashMap::new(),
        repeats: Vec::new(),
        unrolled: 0,
        reported: (HashSet::new(), 0),
    };
    // M30 ends the program: frames after it never run. **[decided]** (as LinuxCNC)
    let (mut ended, mut seen) = (false, 0);
    for line in src.lines() {
        ended |= fe.r.ends_program(seen);
        // Nothing looks back past the line being read (a group is read when it closes),
        // but a G25's repeats at what was reported (those listed, not those counted).
        fe.r.items.line_read_keeping(None);
        let reported = &mut fe.reported.0;
        fe.r.diags.settle(|d| {
            reported.insert(repeat::reported(d));
        });
        fe.reported.1 = fe.r.diags.len();
        seen = fe.r.items.len();
        match syntax::parse_line(line.text) {
            Ok(SyntaxLine::Frame(_)) | Err(_) if ended => fe.r.after_end(
                codes::NCR_AFTER_END,
                src.line_span(line),
                "this frame comes after the program's end (M30); the control does not run it, and neither does ncthread",
                "remove it, or move M30 after it",
            ),
            Ok(SyntaxLine::Empty) => {}
            Ok(SyntaxLine::Comment(text)) => {
                let span = src.line_span(line);
                fe.push(ItemKind::Comment(text), span, None);
            }
            Ok(SyntaxLine::Delimiter) => {
                let span = src.line_span(line);
                if !fe.group.is_empty() || fe.group_broken {
                    fe.open_group_error(span, "a `%` line");
                    fe.group.clear();
                    fe.group_broken = false;
                }
                fe.push(ItemKind::Delimiter, span, None);
            }
            Ok(SyntaxLine::Frame(frame)) => {
                let continues = frame.has(Modifier::Group);
                if frame.word.is_some() {
                    fe.group.push(GroupFrame {
                        frame,
                        place: line.place(),
                    });
                }
                if !continues {
                    fe.end_group();
                }
            }
            Err(e) => {
                let span = src.span_in_line(line, e.range.clone());
                fe.r.error(e.code, span, e.message, e.help);
                // Whether the unreadable frame continued its group: its `*` tells.
                fe.group_broken = true;
                if !line.text.contains('*') {
                    fe.end_group();
                }
            }
        }
    }
    if let Some(last) = fe.group.last() {
        let span = fe.word_span(last);
        fe.open_group_error(span, "the end of the program");
    }
    fe.r.finish()
}

impl<'a> FrontEnd<'a> {
    fn push(&mut self, kind: ItemKind, span: Span, number: Option<u32>) {
        self.r.push(kind, span, number);
    }

    fn span(&self, f: &GroupFrame, range: Range<usize>) -> Span {
        self.r.src.span_in_line(self.r.src.line_of(f.place), range)
    }

    fn word_span(&self, f: &GroupFrame) -> Span {
        self.span(f, f.word().range.clone())
    }

    fn error(
        &mut self,
        code: Code,
        span: Span,
        message: impl Into<String>,
        help: impl Into<String>,
    ) {
        self.r.error(code, span, message, help);
    }

    fn word_error(
        &mut self,
        code: Code,
        f: &GroupFrame,
        message: impl Into<String>,
        help: impl Into<String>,
    ) {
        let span = self.word_span(f);
        self.error(code, span, message, help);
    }

    fn open_group_error(&mut self, span: Span, what: &str) {
        self.error(
            codes::NCR_OPEN_GROUP,
            span,
            format!("{what} cuts the group short: the frame before it ends with `*`"),
            "remove the `*` from the group's last frame, or add the frames the group is missing",
        );
    }

    /// The span of a whole group: its first line, from the first word to the end of the
    /// last frame.
    fn group_span(&self, frames: &[GroupFrame]) -> Span {
        let first = &frames[0];
        let mut span = self.span(first, first.frame.code_range.clone());
        if let Some(last) = frames.last() {
            let end = self.r.src.line_of(last.place).offset + last.frame.code_range.end;
            span.end = crate::source::offset32(end);
        }
        span
    }

    fn end_group(&mut self) {
        let frames = std::mem::take(&mut self.group);
        let broken = std::mem::take(&mut self.group_broken);
        if frames.is_empty() {
            return;
        }
        if !broken {
            self.read_group(&frames);
        }
        self.record(frames, !broken);
    }

    /// Keeps a group read from the source for the G25 repeats after it.
    fn record(&mut self, frames: Vec<GroupFrame>, readable: bool) {
        // Without repeats (G25 is refused by name) nothing reads them again: a large
        // program's groups are not kept.
        if !self.profile.repeat_g25 {
            return;
        }
        let index = self.groups.len();
        for (k, f) in frames.iter().enumerate() {
            if let Some(n) = f.frame.number {
                self.numbers
                    .entry(n)
                    .and_modify(|e| e.2 = true)
                    .or_insert((index, k, false));
            }
        }
        if frames[0].word().letter == 'G' && frames[0].word().value == 25 {
            self.repeats.push(index);
        }
        let before = self.frames_before.last().copied().unwrap_or(0);
        self.frames_before.push(before + frames.len());
        self.groups.push((frames, readable));
    }

    /// Reads one group: from the source, or again for a G25.
    fn read_group(&mut self, frames: &[GroupFrame]) {
        if !self.check_supported(frames) {
            return;
        }
        let span = self.group_span(frames);
        let number = frames[0].frame.number;
        let first_item = self.r.items.len();
        let gs: Vec<&GroupFrame> = frames.iter().filter(|f| f.word().letter == 'G').collect();
        match gs.as_slice() {
            [] if frames.iter().any(|f| f.frame.chamfer().is_some()) => self.chamfer(frames, span),
            [] => self.plain_group(frames, span),
            [g] if std::ptr::eq(*g, &frames[0]) => match g.word().value {
                31 => self.g31(frames, span),
                32 => self.g32(frames, span),
                2 | 3 | 12 | 13 => self.arc(frames, span),
                // The repeated groups carry their own numbers.
                25 => return self.g25(frames),
                _ => self.g33(frames, span),
            },
            [g, ..] => {
                let g = if std::ptr::eq(*g, &frames[0]) {
                    gs[1]
                } else {
                    *g
                };
                self.word_error(
                    codes::NCR_GROUP_WORD,
                    g,
                    format!("`{}` inside a group", g.text(self.r.src)),
                    "a G word opens its own group (`G31 *`, then the cycle's words); end the previous group first",
                );
            }
        }
        self.r.stamp_block(first_item, number, None, span, true);
    }

    /// Reports `~`, `@` and `±45` on a frame that does not take them.
    fn check_modifiers(
        &mut self,
        f: &GroupFrame,
        rapid: bool,
        incremental: bool,
        chamfer: bool,
    ) -> bool {
        let mut ok = true;
        let up = f.frame.chamfer().is_none_or(|(up, _)| up);
        for (m, allowed, what) in [
            (
                Modifier::Rapid,
                rapid,
                "`~` (rapid) applies to X and Z frames outside thread groups",
            ),
            (
                Modifier::Incremental,
                incremental,
                "`@` (incremental) applies to X and Z frames, and on G33 to its X offset",
            ),
            (
                Modifier::Chamfer { up },
                chamfer,
                "`+45`/`-45` (a 45° chamfer) applies to the X or Z frame of a chamfer group (`X<end>+45 *` then `F<feed>`), outside thread and arc groups",
            ),
        ] {
            if let Some(range) = f.frame.modifier_range(m).filter(|_| !allowed) {
                let span = self.span(f, range);
                self.error(
                    codes::NCR_MODIFIER,
                    span,
                    format!("`{}` on `{}`", m.ascii(), f.text(self.r.src)),
                    what,
                );
                ok = false;
            }
        }
        ok
    }

    /// A word's value times `unit`.
    fn scaled(&mut self, f: &GroupFrame, unit: Length) -> Option<Length> {
        let value = f.word().value.checked_mul(unit.0).map(Length);
        if value.is_none() {
            self.word_error(
                codes::NCR_NUMBER,
                f,
                format!("`{}` is too large", f.text(self.r.src)),
                "check the word's digits and the profile's units",
            );
        }
        value
    }

    /// An X or Z coordinate: absolute, or added to `base` with `@`.
    fn coordinate(&mut self, f: &GroupFrame, base: Option<Length>) -> Option<Length> {
        let value = self.scaled(f, self.profile.linear_unit)?;
        if !f.frame.has(Modifier::Incremental) {
            return Some(value);
        }
        match base {
            Some(b) => {
                let sum = b.0.checked_add(value.0).map(Length);
                if sum.is_none() {
                    self.word_error(
                        codes::NCR_NUMBER,
                        f,
                        format!("`{}` moves the tool too far", f.text(self.r.src)),
                        "check the word's digits and the profile's units",
                    );
                }
                sum
            }
            None => {
                let range = f
                    .frame
                    .modifier_range(Modifier::Incremental)
                    .unwrap_or(f.word().range.clone());
                let span = self.span(f, range);
                let axis = f.word().letter;
                self.error(
                    codes::NCR_UNKNOWN_POSITION,
                    span,
                    format!(
                        "incremental `{}` but the {axis} position is not known yet",
                        f.text(self.r.src)
                    ),
                    format!(
                        "program an absolute {axis} (without `@`) before the first incremental move"
                    ),
                );
                None
            }
        }
    }

    fn repeated(&mut self, f: &GroupFrame, first: &GroupFrame) {
        let line = first.place.number;
        self.word_error(
            codes::NCR_GROUP_WORD,
            f,
            format!(
                "`{}` repeats the {} word of this group (line {line})",
                f.text(self.r.src),
                f.word().letter
            ),
            "each address appears once per group",
        );
    }

    /// An F frame outside a thread group: the feed per revolution, positive.
    fn feed_rate(&mut self, fr: &GroupFrame) -> Option<Length> {
        match self.scaled(fr, self.profile.feed_unit) {
            Some(v) if v.0 > 0 => Some(v),
            Some(_) => {
                self.word_error(
                    codes::NCR_NUMBER,
                    fr,
                    format!("feed `{}` is not positive", fr.text(self.r.src)),
                    "F outside a thread group is the feed in 0.01 mm/rev, e.g. F30 = 0.3 mm/rev",
                );
                None
            }
            None => None,
        }
    }

    /// Why no feed is set: never programmed, or undefined after a thread group.
    fn why_no_feed(&self) -> String {
        match self.feed {
            Feed::AfterThread(line) => {
                format!("the feed is undefined after the thread group on line {line}")
            }
            _ => "no feed has been programmed yet".to_string(),
        }
    }

    /// S, T: a whole number that fits.
    fn whole(&mut self, f: &GroupFrame) -> Option<u32> {
        let v = u32::try_from(f.word().value).ok();
        if v.is_none() {
            self.word_error(
                codes::NCR_NUMBER,
                f,
                format!(
                    "`{}` is not a valid {} value",
                    f.text(self.r.src),
                    f.word().letter
                ),
                "S is the speed in rpm and T the turret position: whole numbers from 0",
            );
        }
        v
    }
}

//! The nc31 front end: frames → groups → IR items, with the dialect's rules as diagnostics.
//!
//! Frames joined by `*` form a group that executes as one block. A group that starts with
//! G31, G32 or G33 is a thread group; any other group sets feed, spindle, tool, speed range
//! and/or moves the tool (rapid when any coordinate has `~`).

use std::collections::{HashMap, HashSet};
use std::ops::Range;

use super::syntax::{self, Frame, Line as SyntaxLine, Modifier, Word};
use crate::diag::{Code, Diagnostic, codes};
use crate::dialect::Unsupported;
use crate::dialect::read::{Keep, Reader, UnsupportedWording};
use crate::fixed::{Angle, Lead, Length};
use crate::ir::{
    Coolant, CycleChamfer, EndCode, Finish, ItemKind, ModalContext, Pos, Program, Retract, Rise,
    SpindleDirection, SyncStart, TapCycle, ThreadCycle, ThreadPass,
};
use crate::lower::{self, ExpandError};
use crate::profile::{Nc31ArcDirection, Nc31Profile, Profile};
use crate::source::{SourceFile, Span};

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

/// A diagnostic as a repeat compares it with those reported before: code, line and
/// column, message.
type Reported = (&'static str, Option<(u32, u32)>, String);

fn reported(d: &Diagnostic) -> Reported {
    (
        d.code.id,
        d.location.as_ref().map(|l| (l.line, l.column)),
        d.message.clone(),
    )
}

/// A frame of a group with the line it stands on.
#[derive(Clone)]
struct GroupFrame {
    frame: Frame,
    line: u32,
}

impl GroupFrame {
    fn word(&self) -> &Word {
        self.frame
            .word
            .as_ref()
            .expect("groups hold only frames with a word")
    }

    fn text<'s>(&self, src: &'s SourceFile) -> &'s str {
        &src.line(self.line).text[self.word().range.clone()]
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
pub fn parse(src: &SourceFile, profile: &Profile, options: &Options) -> (Program, Vec<Diagnostic>) {
    read(src, profile, options, Keep::Program)
}

/// [`parse`], keeping the program or only the diagnostics.
pub(crate) fn read(
    src: &SourceFile,
    profile: &Profile,
    options: &Options,
    keep: Keep,
) -> (Program, Vec<Diagnostic>) {
    let mut fe = FrontEnd {
        r: Reader::new(src, super::ID, keep),
        profile: &profile.nc31,
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
        // Nothing looks back past the line being read (a group is read when it closes).
        fe.r.items.line_read();
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
                        line: line.number,
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

/// What a thread group's words are, by letter.
#[derive(Default)]
struct ThreadWords<'g> {
    x: Option<&'g GroupFrame>,
    z: Option<&'g GroupFrame>,
    f: Option<&'g GroupFrame>,
    p: Vec<&'g GroupFrame>,
}

impl<'a> FrontEnd<'a> {
    fn push(&mut self, kind: ItemKind, span: Span, number: Option<u32>) {
        self.r.push(kind, span, number);
    }

    fn span(&self, f: &GroupFrame, range: Range<usize>) -> Span {
        self.r.src.span_in_line(self.r.src.line(f.line), range)
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
            span.end = self.r.src.line(last.line).offset + last.frame.code_range.end;
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

    /// Reports words the guide does not document; with `--unsupported warn` the group is kept
    /// as one opaque item. Returns whether the group can be read.
    fn check_supported(&mut self, frames: &[GroupFrame]) -> bool {
        // G25 without the profile's key: never kept as written, since it repeats frames by
        // their numbers and an output numbers its frames anew.
        if !self.profile.repeat_g25
            && let Some(f) = frames
                .iter()
                .find(|f| f.word().letter == 'G' && f.word().value == 25)
        {
            self.word_error(
                codes::NCR_UNSUPPORTED,
                f,
                format!(
                    "`{}`: G25 (a repeat of frames) is not in the guide",
                    f.text(self.r.src)
                ),
                "if the machine repeats frames with `G25 *`, `P<from><to> *`, `P<count>`, set `repeat_g25 = true` in the profile's [nc31] section (ncthread then writes the repeated frames out); `--unsupported warn` cannot keep it as written, since the output numbers its frames anew",
            );
            return false;
        }
        let mut found = Vec::new();
        for f in frames {
            let w = f.word();
            let reason = match w.letter {
                'X' | 'Z' | 'F' | 'P' | 'S' | 'T' => None,
                'G' if matches!(w.value, 31..=33) => None,
                'G' if matches!(w.value, 2 | 3 | 12 | 13) && self.profile.arcs => None,
                'G' if w.value == 25 && self.profile.repeat_g25 => None,
                // Refused below, also under `--unsupported warn`.
                'G' if w.value == 25 => None,
                'G' if matches!(w.value, 2 | 3 | 12 | 13) => Some(format!(
                    "G{} (an arc) is not in the guide: if the machine takes G2/G3 groups with P offsets, set `arcs = \"g2-g3-p\"` and `arc_direction` in the profile's [nc31] section",
                    w.value
                )),
                'G' => Some(format!(
                    "G{} is not among the documented G words (G31, G32, G33)",
                    w.value
                )),
                'M' if matches!(w.value, 3 | 4 | 5 | 30)
                    || (self.profile.coolant && matches!(w.value, 8 | 9))
                    || self.profile.gear_range_mcodes.contains(&(w.value as u32)) =>
                {
                    None
                }
                'M' if matches!(w.value, 8 | 9) => Some(format!(
                    "M{} (coolant) is not in the guide: if the machine takes M8/M9, set `coolant = \"m8-m9\"` in the profile's [nc31] section",
                    w.value
                )),
                'M' => Some(format!(
                    "M{} is not among the documented M words (M3, M4, M5, M30, speed ranges {})",
                    w.value,
                    self.profile
                        .gear_range_mcodes
                        .iter()
                        .map(|m| format!("M{m}"))
                        .collect::<Vec<_>>()
                        .join(", ")
                )),
                other => Some(format!("address {other} is not documented for the НЦ-31")),
            };
            if let Some(reason) = reason {
                found.push((f, reason));
            }
        }
        if found.is_empty() {
            return true;
        }
        let keep = self.options.unsupported == Unsupported::Warn;
        let found = found
            .into_iter()
            .map(|(f, reason)| {
                (
                    self.word_span(f),
                    format!("`{}`: {reason}", f.text(self.r.src)),
                )
            })
            .collect();
        let thread = frames
            .iter()
            .any(|f| f.word().letter == 'G' && matches!(f.word().value, 31..=33));
        if !self.r.unsupported(&UNSUPPORTED, found, keep, thread) {
            return false;
        }
        // A kept group must not change what ncthread follows (the feed, the spindle, a
        // thread group's words), or the groups after it would be read wrongly.
        if let Some(f) = frames.iter().find(|f| {
            let w = f.word();
            matches!(w.letter, 'F' | 'S' | 'T')
                || (w.letter == 'G' && matches!(w.value, 2 | 3 | 12 | 13 | 31..=33))
                || (w.letter == 'M'
                    && (matches!(w.value, 3 | 4 | 5 | 30)
                        || (self.profile.coolant && matches!(w.value, 8 | 9))
                        || self.profile.gear_range_mcodes.contains(&(w.value as u32))))
        }) {
            let span = self.word_span(f);
            self.r
                .state_in_opaque(&UNSUPPORTED, span, f.text(self.r.src));
            return false;
        }
        let text = frames
            .iter()
            .map(|f| &self.r.src.line(f.line).text[f.frame.code_range.clone()])
            .collect::<Vec<_>>()
            .join("\n");
        let span = self.group_span(frames);
        let context = ModalContext {
            inch: false,
            diameter: true,
            incremental: false,
            per_minute: None,
            // The reader cannot tell: positions after the block are unknown.
            moves: true,
        };
        self.r
            .keep_opaque(text, span, frames[0].frame.number, context);
        false
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
        let line = first.line;
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

    /// A group without a G word: feed, tool, speed range, spindle, motion, stop, end.
    fn plain_group(&mut self, frames: &[GroupFrame], span: Span) {
        let mut ok = true;
        let (mut x, mut z, mut f, mut s, mut t) = (None, None, None, None, None);
        let mut direction: Option<(SpindleDirection, &GroupFrame)> = None;
        let (mut stop, mut end) = (false, false);
        let mut gears = Vec::new();
        let mut coolant = Vec::new();
        for fr in frames {
            let w = fr.word();
            let axis = matches!(w.letter, 'X' | 'Z');
            ok &= self.check_modifiers(fr, axis, axis, false);
            let slot = match w.letter {
                'X' => Some(&mut x),
                'Z' => Some(&mut z),
                'F' => Some(&mut f),
                'S' => Some(&mut s),
                'T' => Some(&mut t),
                _ => None,
            };
            if let Some(slot) = slot {
                if let Some(first) = *slot {
                    self.repeated(fr, first);
                    ok = false;
                } else {
                    *slot = Some(fr);
                }
                continue;
            }
            match (w.letter, w.value) {
                ('M', 3 | 4) => {
                    let d = if w.value == 3 {
                        SpindleDirection::Clockwise
                    } else {
                        SpindleDirection::CounterClockwise
                    };
                    if let Some((_, first)) = direction {
                        self.repeated(fr, first);
                        ok = false;
                    }
                    direction = Some((d, fr));
                }
                ('M', 5) => stop = true,
                ('M', 30) => end = true,
                ('M', 8) => coolant.push(Coolant::Flood),
                ('M', 9) => coolant.push(Coolant::Off),
                ('M', m) => gears.push(m as u32),
                _ => {
                    // P outside G31.
                    self.word_error(
                        codes::NCR_GROUP_WORD,
                        fr,
                        format!("`{}` outside a G31 group", fr.text(self.r.src)),
                        "P words give the depths of a G31 cycle: `G31 *`, X, Z, F, then P (depth), P (first pass), optional P (taper)",
                    );
                    ok = false;
                }
            }
        }
        if direction.is_some() && stop {
            let fr = frames
                .iter()
                .find(|f| f.word().letter == 'M' && f.word().value == 5)
                .expect("M5 is in the group");
            self.word_error(
                codes::NCR_GROUP_WORD,
                fr,
                "M5 in the same group as a spindle start",
                "start and stop the spindle in different groups",
            );
            ok = false;
        }
        let feed = f.and_then(|fr| self.feed_rate(fr));
        if f.is_some() && feed.is_none() {
            ok = false;
        }
        let speed = s.and_then(|fr| self.whole(fr));
        let tool = t.and_then(|fr| self.whole(fr));
        ok &= s.is_none() || speed.is_some();
        ok &= t.is_none() || tool.is_some();
        let to_x = x.map(|fr| self.coordinate(fr, self.r.pos.x));
        let to_z = z.map(|fr| self.coordinate(fr, self.r.pos.z));
        if matches!(to_x, Some(None)) || matches!(to_z, Some(None)) {
            ok = false;
        }
        if let Some(feed) = feed {
            self.feed = Feed::Set(feed);
        }
        let moves = x.is_some() || z.is_some();
        let rapid = [x, z]
            .into_iter()
            .flatten()
            .any(|fr| fr.frame.has(Modifier::Rapid));
        let feed_now = match self.feed {
            Feed::Set(v) => Some(v),
            _ => None,
        };
        if moves && !rapid && feed_now.is_none() {
            let fr = x.or(z).expect("the group moves");
            let why = self.why_no_feed();
            self.word_error(
                codes::NCR_NO_FEED,
                fr,
                format!("feed move `{}` but {why}", fr.text(self.r.src)),
                "program the feed in a frame of its own (e.g. `F60` = 0.6 mm/rev) before this move, or mark the move rapid with `~`",
            );
            ok = false;
        }
        if !ok {
            return;
        }
        if let Some(number) = tool {
            self.push(
                ItemKind::Tool {
                    number: Some(number),
                    offset: None,
                },
                span,
                None,
            );
        }
        for g in gears {
            self.push(
                ItemKind::GearRange {
                    code: g,
                    machine: super::ID,
                },
                span,
                None,
            );
        }
        if speed.is_some() || direction.is_some() {
            self.push(
                ItemKind::Spindle {
                    speed,
                    direction: direction.map(|(d, _)| d),
                },
                span,
                None,
            );
        }
        // Coolant on before the group's motion, off after it, as the spindle. **[decided]**
        for &c in coolant.iter().filter(|c| **c != Coolant::Off) {
            self.push(ItemKind::Coolant(c), span, None);
        }
        if moves {
            let to = Pos {
                x: to_x.flatten(),
                z: to_z.flatten(),
            };
            let kind = match (rapid, feed_now) {
                (false, Some(feed)) => ItemKind::Feed { to, feed },
                _ => ItemKind::Rapid { to },
            };
            self.r.pos = kind.end_position(self.r.pos);
            self.push(kind, span, None);
        }
        for &c in coolant.iter().filter(|c| **c == Coolant::Off) {
            self.push(ItemKind::Coolant(c), span, None);
        }
        // A feed that no move of the group uses stays where it is written.
        if let Some(feed) = feed
            && (!moves || rapid)
        {
            self.push(ItemKind::FeedRate(feed), span, None);
        }
        if stop {
            self.push(ItemKind::SpindleStop, span, None);
        }
        if end {
            self.push(ItemKind::ProgramEnd(EndCode::M30), span, None);
        }
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

    /// Sorts a thread group's words; reports words that do not belong and repeats.
    fn thread_words<'g>(
        &mut self,
        frames: &'g [GroupFrame],
        allowed: &[char],
        max_p: usize,
        about: &str,
    ) -> Option<ThreadWords<'g>> {
        let mut words = ThreadWords::default();
        let mut ok = true;
        let g = &frames[0];
        let g33 = g.word().value == 33;
        ok &= self.check_modifiers(g, false, g33, false);
        for fr in &frames[1..] {
            let letter = fr.word().letter;
            let coordinate = matches!(letter, 'X' | 'Z');
            ok &= self.check_modifiers(fr, false, coordinate, false);
            if !allowed.contains(&letter) {
                let help = if g.word().value == 32 && letter == 'X' {
                    "G32 cuts along Z at the current diameter; move to the pass diameter in a group before `G32 *`".to_string()
                } else {
                    format!("{about}; other words go in groups of their own")
                };
                self.word_error(
                    codes::NCR_GROUP_WORD,
                    fr,
                    format!(
                        "`{}` does not belong in a {} group",
                        fr.text(self.r.src),
                        g.text(self.r.src)
                    ),
                    help,
                );
                ok = false;
                continue;
            }
            let slot = match letter {
                'X' => &mut words.x,
                'Z' => &mut words.z,
                'F' => &mut words.f,
                _ => {
                    if words.p.len() == max_p {
                        self.word_error(
                            codes::NCR_GROUP_WORD,
                            fr,
                            format!("`{}` is a P word too many", fr.text(self.r.src)),
                            "G31 takes P (thread depth), P (first-pass depth) and an optional third P (taper)",
                        );
                        ok = false;
                    } else {
                        words.p.push(fr);
                    }
                    continue;
                }
            };
            if let Some(first) = *slot {
                self.repeated(fr, first);
                ok = false;
            } else {
                *slot = Some(fr);
            }
        }
        ok.then_some(words)
    }

    fn missing(&mut self, g: &GroupFrame, missing: &[&str], about: &str) -> bool {
        if missing.is_empty() {
            return false;
        }
        self.word_error(
            codes::NCR_MISSING_WORD,
            g,
            format!(
                "the {} group has no {}",
                g.text(self.r.src),
                missing.join(", no ")
            ),
            about.to_string(),
        );
        true
    }

    fn lead(&mut self, f: &GroupFrame) -> Option<Lead> {
        let lead = self.scaled(f, self.profile.lead_unit)?;
        if lead.0 <= 0 {
            self.word_error(
                codes::NCR_LEAD,
                f,
                format!("lead `{}` is not positive", f.text(self.r.src)),
                "F in a thread group is the lead in 0.0001 mm: F15000 = 1.5 mm",
            );
            return None;
        }
        let lead = Lead::from_length(lead);
        if lead > Lead::MAX {
            self.word_error(
                codes::NCR_NUMBER,
                f,
                format!("`{}` is too large for a lead", f.text(self.r.src)),
                "a lead is at most 1,000,000 mm",
            );
            return None;
        }
        Some(lead)
    }

    fn start_unknown(&mut self, g: &GroupFrame, what: &str) {
        self.word_error(
            codes::NCR_UNKNOWN_POSITION,
            g,
            format!("{} starts from the tool position, and the {what} is not known", g.text(self.r.src)),
            "move to the start point with X and Z (e.g. `X3600 ~ *` then `Z450 ~`) before the cycle",
        );
    }

    /// `G31 *` X Z F P P [P]: the multi-pass cycle.
    fn g31(&mut self, frames: &[GroupFrame], span: Span) {
        const ABOUT: &str = "G31 takes X (thread diameter), Z (end), F (lead), P (thread depth per side), P (first-pass depth) and an optional P (taper on diameter)";
        let g = &frames[0];
        let Some(w) = self.thread_words(frames, &['X', 'Z', 'F', 'P'], 3, ABOUT) else {
            return;
        };
        let mut missing = Vec::new();
        for (present, name) in [
            (w.x.is_some(), "X (thread diameter)"),
            (w.z.is_some(), "Z (end)"),
            (w.f.is_some(), "F (lead)"),
            (!w.p.is_empty(), "P (thread depth)"),
            (w.p.len() >= 2, "P (first-pass depth)"),
        ] {
            if !present {
                missing.push(name);
            }
        }
        if self.missing(g, &missing, ABOUT) {
            return;
        }
        let (Some(xf), Some(zf), Some(ff)) = (w.x, w.z, w.f) else {
            return;
        };
        let Some((ax, az)) = self.r.pos.known() else {
            self.start_unknown(g, "start point");
            return;
        };
        let unit = self.profile.linear_unit;
        let crest = self.coordinate(xf, Some(ax));
        let end_z = self.coordinate(zf, Some(az));
        let lead = self.lead(ff);
        let depth = self.scaled(w.p[0], unit);
        let first = self.scaled(w.p[1], unit);
        let taper = match w.p.get(2) {
            Some(pf) => self.scaled(pf, unit),
            None => Some(Length::ZERO),
        };
        let (Some(crest), Some(end_z), Some(lead), Some(depth), Some(first), Some(taper)) =
            (crest, end_z, lead, depth, first, taper)
        else {
            return;
        };
        if crest.0 <= 0 {
            self.word_error(
                codes::NCR_NUMBER,
                xf,
                format!("thread diameter `{}` is not positive", xf.text(self.r.src)),
                "X in G31 is the thread's crest diameter in 0.01 mm (X3600 = Ø36)",
            );
            return;
        }
        if taper.0 < 0 {
            self.word_error(
                codes::NCR_DEPTHS,
                w.p[2],
                format!("taper `{}` is negative", w.p[2].text(self.r.src)),
                "the third P is the difference of the larger and the smaller diameter; X is the smaller one at the start",
            );
            return;
        }
        let cycle = ThreadCycle {
            start: (ax, az),
            crest,
            end_z,
            lead,
            depth,
            first_depth: first,
            taper,
            infeed: self.profile.infeed(),
            infeed_moves_end: false,
            start_angle: Angle::ZERO,
            entry: None,
            entry_infeed: false,
            runout: Some(self.profile.runout(lead))
                .filter(|r| r.0 > 0)
                .map(|length| CycleChamfer {
                    length,
                    rise: Rise::ToCrest,
                }),
            retract: Retract::AboveCrest(self.profile.retract),
            spring_passes: 0,
            finish: Finish::Start,
            internal: ax < crest,
            schedule: self.profile.schedule,
        };
        if let Err(e) = lower::expand(&cycle) {
            let (code, frame, help) = match e {
                ExpandError::Lead => (codes::NCR_LEAD, ff, "the lead must be positive".to_string()),
                ExpandError::NoTravel => (
                    codes::NCR_TRAVEL,
                    zf,
                    "Z is where every pass ends; it must differ from the start Z".to_string(),
                ),
                ExpandError::FirstDepth | ExpandError::TooManyPasses => (
                    codes::NCR_DEPTHS,
                    w.p[1],
                    "the second P is the first pass's depth per side in 0.01 mm (P20 = 0.2 mm)".to_string(),
                ),
                ExpandError::DepthTooSmall { .. } => (
                    codes::NCR_DEPTHS,
                    w.p[0],
                    format!(
                        "with the {} schedule the thread depth (first P) must be at least the first-pass depth (second P){}",
                        cycle.schedule.id(),
                        if cycle.schedule == crate::ir::Schedule::Halving {
                            " plus the four halving passes P/2 + P/4 + P/8 + P/16"
                        } else {
                            ""
                        }
                    ),
                ),
                ExpandError::ShortPass { .. } => (
                    codes::NCR_TRAVEL,
                    zf,
                    "the runout (machine parameter 7) and the infeed shift (parameter 6) must fit inside the pass; move the start point further out or shorten the runout".to_string(),
                ),
            };
            let message = e.message(&cycle);
            self.word_error(code, frame, message, help);
            return;
        }
        self.push(ItemKind::ThreadCycle(Box::new(cycle)), span, None);
        self.r.pos = Pos::new(ax, az);
        self.feed = Feed::AfterThread(g.line);
    }

    /// `G32 *` F Z: one synchronised pass along Z at the current diameter.
    fn g32(&mut self, frames: &[GroupFrame], span: Span) {
        const ABOUT: &str = "G32 takes F (lead) and Z (end)";
        let g = &frames[0];
        let Some(w) = self.thread_words(frames, &['Z', 'F'], 0, ABOUT) else {
            return;
        };
        let mut missing = Vec::new();
        if w.f.is_none() {
            missing.push("F (lead)");
        }
        if w.z.is_none() {
            missing.push("Z (end)");
        }
        if self.missing(g, &missing, ABOUT) {
            return;
        }
        let (Some(zf), Some(ff)) = (w.z, w.f) else {
            return;
        };
        let lead = self.lead(ff);
        let end_z = self.coordinate(zf, self.r.pos.z);
        let (Some(lead), Some(end_z)) = (lead, end_z) else {
            return;
        };
        if self.r.pos.z == Some(end_z) {
            self.word_error(
                codes::NCR_TRAVEL,
                zf,
                format!("the pass ends at Z{} where it starts", end_z.mm()),
                "Z is the end of the pass; it must differ from the current Z",
            );
            return;
        }
        let pass = ThreadPass {
            to: Pos {
                x: self.r.pos.x,
                z: Some(end_z),
            },
            lead,
            // G32 starts from the index pulse. **[seed]**
            start: SyncStart::Index(Angle::ZERO),
            infeed: None,
            entry: None,
            exit: None,
        };
        let kind = ItemKind::pass(pass);
        self.r.pos = kind.end_position(self.r.pos);
        self.push(kind, span, None);
        self.feed = Feed::AfterThread(g.line);
    }

    /// An arc group: `G2 *`/`G3 *` X, Z, P (the centre's radial offset from the start,
    /// unsigned, in radius units), P (its axial offset), within one quadrant; or `G12 *`/
    /// `G13 *` X, Z, a quarter circle. **\[evidence\]** one shop's generator (nc31.md,
    /// "General motion"). The signs of the offsets come from the quadrant: of the centres
    /// they allow, the one on whose circle the end lies (within one linear unit) and around
    /// which the arc turns the profile's way within one quadrant. **\[decided\]**
    fn arc(&mut self, frames: &[GroupFrame], span: Span) {
        let g = &frames[0];
        let code = g.word().value;
        let quarter = code >= 12;
        let about = if quarter {
            "G12/G13 take X and Z (the end of a quarter circle)"
        } else {
            "G2/G3 take X, Z and two P (the centre's unsigned offsets from the start: radial, then axial)"
        };
        let (allowed, max_p): (&[char], usize) = if quarter {
            (&['X', 'Z'], 0)
        } else {
            (&['X', 'Z', 'P'], 2)
        };
        let Some(w) = self.thread_words(frames, allowed, max_p, about) else {
            return;
        };
        let arc_error = |fe: &mut Self, at: &GroupFrame, message: String, help: &str| {
            fe.word_error(codes::NCR_ARC, at, message, help.to_string());
        };
        let Some(direction) = self.profile.arc_direction else {
            return arc_error(
                self,
                g,
                format!("G{code}: the profile enables arcs but does not say which way G2 turns"),
                "set `arc_direction = \"front-tool\"` or `\"iso\"` in the profile's [nc31] section, as the machine's documentation says",
            );
        };
        if !quarter && w.p.len() < 2 {
            return arc_error(
                self,
                g,
                format!("G{code} without its two P words (the centre's offsets)"),
                about,
            );
        }
        if w.x.is_none() && w.z.is_none() {
            return arc_error(self, g, format!("G{code} without X or Z"), about);
        }
        let Feed::Set(feed) = self.feed else {
            let why = self.why_no_feed();
            self.word_error(
                codes::NCR_NO_FEED,
                g,
                format!("arc `G{code}` but {why}"),
                "program the feed in a frame of its own (e.g. `F20` = 0.2 mm/rev) before the arc",
            );
            return;
        };
        let Some((sx, sz)) = self.r.pos.known() else {
            self.word_error(
                codes::NCR_UNKNOWN_POSITION,
                g,
                format!("arc `G{code}` from a position that is not known yet"),
                "move to an absolute X and Z before the arc",
            );
            return;
        };
        let ex = match w.x {
            Some(fr) => self.coordinate(fr, Some(sx)),
            None => Some(sx),
        };
        let ez = match w.z {
            Some(fr) => self.coordinate(fr, Some(sz)),
            None => Some(sz),
        };
        let (Some(ex), Some(ez)) = (ex, ez) else {
            return;
        };
        let g2_type = matches!(code, 2 | 12);
        let clockwise = g2_type != (direction == Nc31ArcDirection::FrontTool);
        let candidates: Vec<Pos> = if quarter {
            vec![Pos::new(ex, sz), Pos::new(sx, ez)]
        } else {
            let unit = self.profile.linear_unit;
            let (Some(a), Some(b)) = (self.scaled(w.p[0], unit), self.scaled(w.p[1], unit)) else {
                return;
            };
            if a.0 < 0 || b.0 < 0 {
                return arc_error(
                    self,
                    if a.0 < 0 { w.p[0] } else { w.p[1] },
                    "a negative P in an arc group: its offsets are unsigned".into(),
                    "the signs come from the quadrant the arc turns in; write the offsets without a sign",
                );
            }
            let mut out = Vec::new();
            for (dx, dz) in [(a, b), (-a, b), (a, -b), (-a, -b)] {
                let c = Pos::new(sx + dx + dx, sz + dz);
                if !out.contains(&c) {
                    out.push(c);
                }
            }
            out
        };
        let tolerance = self.profile.linear_unit.to_mm_f64();
        let fits: Vec<Pos> = candidates
            .into_iter()
            .filter(|c| {
                let Some((cx, cz)) = c.known() else {
                    return false;
                };
                let (r1, r2) = lower::arc::radii((sx, sz), (ex, ez), (cx, cz));
                r1 > 0.0
                    && (r1 - r2).abs() <= tolerance
                    && lower::arc::within_quadrant((sx, sz), (ex, ez), (cx, cz), clockwise)
            })
            .collect();
        let centre = match fits.as_slice() {
            [c] => *c,
            [] => {
                return arc_error(
                    self,
                    g,
                    format!(
                        "G{code} to X{} Z{}: no centre its offsets allow has the end on its circle with the arc turning {} within one quadrant",
                        ex.mm(),
                        ez.mm(),
                        if clockwise {
                            "clockwise (G2 seen as LinuxCNC sees it)"
                        } else {
                            "counter-clockwise (G3 seen as LinuxCNC sees it)"
                        }
                    ),
                    "check the P offsets (radial first, in radius units) and the profile's arc_direction; an arc over a quadrant boundary is written as two groups",
                );
            }
            _ => {
                return arc_error(
                    self,
                    g,
                    format!("G{code}: more than one centre fits its offsets"),
                    "a zero offset leaves the side open; write the arc so that its centre is one",
                );
            }
        };
        let kind = ItemKind::Arc {
            to: Pos::new(ex, ez),
            centre: Box::new(centre),
            clockwise,
            feed,
        };
        self.r.pos = kind.end_position(self.r.pos);
        self.push(kind, span, None);
    }

    /// A chamfer group: `X<end>+45 *` or `X<end>-45 *` (likewise Z, `@` allowed) closed by
    /// `F<feed>`. The named axis goes to its end; the other moves by the same radial amount
    /// (X by twice it: X is a diameter), up for `+45` and down for `-45`: a 45° feed move.
    /// The F frame sets the feed, as every F frame outside a thread group does.
    /// **\[evidence\]** one shop's generator and checker (nc31.md, "General motion").
    fn chamfer(&mut self, frames: &[GroupFrame], span: Span) {
        const ABOUT: &str = "a chamfer group is `X<end>+45 *` or `X<end>-45 *` (likewise Z) closed by `F<feed>`: the other axis moves by the same radial amount, towards plus for `+45` and minus for `-45`";
        let mut ok = true;
        let (mut axis, mut feed): (Option<&GroupFrame>, Option<&GroupFrame>) = (None, None);
        for fr in frames {
            let w = fr.word();
            let chamfered = fr.frame.chamfer().is_some();
            match w.letter {
                'X' | 'Z' if chamfered => {
                    if let Some(first) = axis {
                        let line = first.line;
                        self.word_error(
                            codes::NCR_GROUP_WORD,
                            fr,
                            format!(
                                "a second chamfer `{}` in the group of `{}` (line {line})",
                                fr.text(self.r.src),
                                first.text(self.r.src)
                            ),
                            ABOUT,
                        );
                        ok = false;
                    } else {
                        axis = Some(fr);
                    }
                    if let Some(range) = fr.frame.modifier_range(Modifier::Rapid) {
                        let span = self.span(fr, range);
                        self.error(
                            codes::NCR_MODIFIER,
                            span,
                            format!("`~` on the chamfer `{}`", fr.text(self.r.src)),
                            "a chamfer is a feed move at the F that closes its group; a rapid is written without `+45`/`-45`",
                        );
                        ok = false;
                    }
                    ok &= self.check_modifiers(fr, true, true, true);
                }
                'F' => {
                    if let Some(first) = feed {
                        self.repeated(fr, first);
                        ok = false;
                    } else {
                        feed = Some(fr);
                    }
                    ok &= self.check_modifiers(fr, false, false, false);
                }
                // The mark on a word that takes none.
                _ if chamfered => ok &= self.check_modifiers(fr, false, false, false),
                _ => {
                    self.word_error(
                        codes::NCR_GROUP_WORD,
                        fr,
                        format!(
                            "`{}` does not belong in a chamfer group",
                            fr.text(self.r.src)
                        ),
                        format!("{ABOUT}; other words go in groups of their own"),
                    );
                    ok = false;
                }
            }
        }
        let Some(af) = axis.filter(|_| ok) else {
            return;
        };
        // `X3000+45`
        let shown = format!(
            "{}{}",
            af.text(self.r.src),
            af.frame
                .chamfer()
                .map_or("", |(up, _)| Modifier::Chamfer { up }.ascii())
        );
        let Some(ff) = feed else {
            return self.word_error(
                codes::NCR_CHAMFER,
                af,
                format!("the chamfer `{shown}` is not closed by an F frame"),
                ABOUT,
            );
        };
        if frames.last().is_some_and(|last| !std::ptr::eq(last, ff)) {
            return self.word_error(
                codes::NCR_CHAMFER,
                ff,
                format!(
                    "`{}` does not close the chamfer group: its F frame comes last",
                    ff.text(self.r.src)
                ),
                ABOUT,
            );
        }
        let Some(rate) = self.feed_rate(ff) else {
            return;
        };
        let Some((sx, sz)) = self.r.pos.known() else {
            return self.word_error(
                codes::NCR_UNKNOWN_POSITION,
                af,
                format!(
                    "the chamfer `{shown}` starts where the tool stands, and that is not known yet"
                ),
                "move to an absolute X and Z before the chamfer",
            );
        };
        let up = af.frame.chamfer().is_some_and(|(up, _)| up);
        let sign = if up { 1 } else { -1 };
        let end = if af.word().letter == 'X' {
            let Some(ex) = self.coordinate(af, Some(sx)) else {
                return;
            };
            let travel = ex.0.checked_sub(sx.0);
            if travel.is_some_and(|d| d % 2 != 0) {
                return self.word_error(
                    codes::NCR_CHAMFER,
                    af,
                    format!(
                        "the chamfer `{shown}` changes the diameter by {} mm: half of it, the Z travel, is off the 0.0001 mm grid",
                        (ex - sx).mm()
                    ),
                    "a 45° chamfer moves Z by half the diameter change; with the profile's linear unit this X cannot be reached at 45°",
                );
            }
            travel
                .and_then(|d| (d / 2).checked_abs())
                .and_then(|r| sz.0.checked_add(sign * r))
                .map(|ez| (ex, Length(ez)))
        } else {
            let Some(ez) = self.coordinate(af, Some(sz)) else {
                return;
            };
            ez.0.checked_sub(sz.0)
                .and_then(i64::checked_abs)
                .and_then(|r| r.checked_mul(2))
                .and_then(|d| sx.0.checked_add(sign * d))
                .map(|ex| (Length(ex), ez))
        };
        let Some((ex, ez)) = end else {
            return self.word_error(
                codes::NCR_NUMBER,
                af,
                format!("the chamfer `{shown}` moves the tool too far"),
                "check the word's digits and the profile's units",
            );
        };
        if (ex, ez) == (sx, sz) {
            return self.word_error(
                codes::NCR_CHAMFER,
                af,
                format!(
                    "the chamfer `{shown}` does not move: the tool already stands at its {}",
                    af.word().letter
                ),
                ABOUT,
            );
        }
        self.feed = Feed::Set(rate);
        let kind = ItemKind::Feed {
            to: Pos::new(ex, ez),
            feed: rate,
        };
        self.r.pos = kind.end_position(self.r.pos);
        self.push(kind, span, None);
    }

    /// `G25 *`, `P<from><to> *`, `P<count>`: the groups from frame N<from> to frame N<to>
    /// (the last three digits of the first P are <to>) are read again `count` times here,
    /// from where the tool stands, as the control runs them (incremental frames cut further
    /// each time; absolute ones go to the same place again). The range must be whole groups
    /// before the G25 and hold no G25. **\[evidence\]** one shop's checker (nc31.md, "General
    /// motion"); the count of repetitions after the frames' own run and the limits are
    /// **\[decided\]**.
    fn g25(&mut self, frames: &[GroupFrame]) {
        const ABOUT: &str = "G25 takes P (the first frame's number followed by the last frame's number in three digits: P5009 repeats N5 to N9) and P (how many times)";
        let g = &frames[0];
        let Some(w) = self.thread_words(frames, &['P'], 2, ABOUT) else {
            return;
        };
        let repeat_error = |fe: &mut Self, at: &GroupFrame, message: String, help: &str| {
            fe.word_error(codes::NCR_REPEAT, at, message, help.to_string());
        };
        let [range, count] = w.p[..] else {
            let missing = if w.p.is_empty() {
                "no P (range), no P (count)"
            } else {
                "no P (count)"
            };
            return repeat_error(self, g, format!("the G25 group has {missing}"), ABOUT);
        };
        let value = range.word().value;
        let (from, to) = (value / 1000, value % 1000);
        let (Ok(from), Ok(to)) = (u32::try_from(from), u32::try_from(to)) else {
            return repeat_error(
                self,
                range,
                format!(
                    "`{}` is not a pair of frame numbers",
                    range.text(self.r.src)
                ),
                ABOUT,
            );
        };
        if from > to {
            return repeat_error(
                self,
                range,
                format!(
                    "`{}` repeats N{from} to N{to}: the range runs backwards",
                    range.text(self.r.src)
                ),
                ABOUT,
            );
        }
        let times = count.word().value;
        if times < 1 {
            return repeat_error(
                self,
                count,
                format!("`{}`: a G25 repeats at least once", count.text(self.r.src)),
                "the second P is how many times the frames run again (P1 once)",
            );
        }
        let own = frames
            .iter()
            .filter_map(|f| f.frame.number)
            .find(|n| (from..=to).contains(n));
        if let Some(n) = own {
            return repeat_error(
                self,
                range,
                format!(
                    "`{}` repeats N{from} to N{to}, which holds this G25's own frame N{n}",
                    range.text(self.r.src)
                ),
                "a G25 repeats frames before it; end the range before the G25 group",
            );
        }
        let mut ends =
            [(from, "first"), (to, "last")].map(|(n, which)| match self.numbers.get(&n) {
                None => Err(format!("there is no frame N{n} before this G25")),
                Some((_, _, true)) => Err(format!(
                    "more than one frame before this G25 is numbered N{n}"
                )),
                Some(&(group, frame, false)) => {
                    let len = self.groups.get(group).map_or(0, |(f, _)| f.len());
                    let whole = if which == "first" {
                        frame == 0
                    } else {
                        frame + 1 == len
                    };
                    if whole {
                        Ok(group)
                    } else {
                        Err(format!(
                            "N{n} is not the {which} frame of its group: a repeat runs whole groups"
                        ))
                    }
                }
            });
        let first = std::mem::replace(&mut ends[0], Ok(0));
        let last = std::mem::replace(&mut ends[1], Ok(0));
        let (first, last) = match (first, last) {
            (Ok(a), Ok(b)) if a <= b => (a, b),
            (Ok(_), Ok(_)) => {
                return repeat_error(
                    self,
                    range,
                    format!(
                        "`{}`: frame N{from} comes after frame N{to} in the program",
                        range.text(self.r.src)
                    ),
                    "the range runs from an earlier frame to a later one",
                );
            }
            (Err(why), _) | (_, Err(why)) => {
                return repeat_error(
                    self,
                    range,
                    format!("`{}`: {why}", range.text(self.r.src)),
                    "the first P names frames of this program before the G25: N<from> starts a group and N<to> ends one",
                );
            }
        };
        let nested = self.repeats.partition_point(|&i| i < first);
        if let Some(&inner) = self.repeats.get(nested).filter(|&&i| i <= last) {
            let line = self.groups[inner].0[0].line;
            return repeat_error(
                self,
                range,
                format!(
                    "`{}` holds the G25 on line {line}: a repeat cannot repeat a repeat",
                    range.text(self.r.src)
                ),
                "write the inner repeat's frames out, or repeat a range without a G25",
            );
        }
        let per_run = self.frames_before[last + 1] - self.frames_before[first];
        let total = usize::try_from(times)
            .ok()
            .and_then(|t| t.checked_mul(per_run))
            .and_then(|n| n.checked_add(self.unrolled))
            .filter(|&n| n <= REPEAT_LIMIT);
        let Some(total) = total else {
            return repeat_error(
                self,
                count,
                format!(
                    "`{}` repeats {per_run} frame(s) {times} times: this program's repeats would unroll more than {REPEAT_LIMIT} frames",
                    count.text(self.r.src)
                ),
                "ncthread reads at most 10,000 repeated frames in a program; split the program",
            );
        };
        self.unrolled = total;
        let replay: Vec<Vec<GroupFrame>> = self.groups[first..=last]
            .iter()
            .filter(|(_, readable)| *readable)
            .map(|(frames, _)| frames.clone())
            .collect();
        for _ in 0..times {
            let mark = self.r.diags.len();
            for frames in &replay {
                self.read_group(frames);
            }
            if self.r.diags.len() == mark {
                continue;
            }
            // What the frames already said when they were read is not said again; what is
            // new (a feed or a position that differs here) names the G25.
            let new: Vec<Diagnostic> = self.r.diags.drain(mark..).collect();
            for d in &self.r.diags[self.reported.1.min(mark)..] {
                self.reported.0.insert(reported(d));
            }
            let mut failed = false;
            for mut d in new {
                if !self.reported.0.insert(reported(&d)) {
                    continue;
                }
                d.message
                    .push_str(&format!(" (repeated by the G25 on line {})", g.line));
                failed |= d.is_error();
                self.r.diags.push(d);
            }
            self.reported.1 = self.r.diags.len();
            if failed {
                break;
            }
        }
    }

    /// `G33 [@] *` X Z F: tapping; with `@` the tool then moves to X (point C).
    fn g33(&mut self, frames: &[GroupFrame], span: Span) {
        const ABOUT: &str = "G33 takes X (point C, with `@` on G33), Z (end) and F (lead)";
        let g = &frames[0];
        let offset = g.frame.has(Modifier::Incremental);
        let Some(w) = self.thread_words(frames, &['X', 'Z', 'F'], 0, ABOUT) else {
            return;
        };
        let mut missing = Vec::new();
        if offset && w.x.is_none() {
            missing.push("X (point C after `@`)");
        }
        if w.z.is_none() {
            missing.push("Z (end)");
        }
        if w.f.is_none() {
            missing.push("F (lead)");
        }
        if self.missing(g, &missing, ABOUT) {
            return;
        }
        let (Some(zf), Some(ff)) = (w.z, w.f) else {
            return;
        };
        let Some(start_z) = self.r.pos.z else {
            self.start_unknown(g, "Z position");
            return;
        };
        let lead = self.lead(ff);
        let end_z = self.coordinate(zf, Some(start_z));
        let x = match w.x {
            Some(xf) => match self.coordinate(xf, self.r.pos.x) {
                Some(x) => Some((x, xf)),
                None => return,
            },
            None => None,
        };
        let (Some(lead), Some(end_z)) = (lead, end_z) else {
            return;
        };
        if end_z == start_z {
            self.word_error(
                codes::NCR_TRAVEL,
                zf,
                format!("the tap ends at Z{} where it starts", end_z.mm()),
                "Z is the bottom of the tapped hole; it must differ from the start Z",
            );
            return;
        }
        let then_x = match x {
            Some((x, _)) if offset => Some(x),
            Some((x, xf)) if self.r.pos.x != Some(x) => {
                let current = self
                    .r
                    .pos
                    .x
                    .map_or("not known".to_string(), |c| format!("Ø{}", c.mm()));
                self.word_error(
                    codes::NCR_GROUP_WORD,
                    xf,
                    format!("`{}` in a G33 group without `@`, but the tool stands at {current}", xf.text(self.r.src)),
                    "without `@` on G33 the tap does not move in X; write `G33 @ *` to move to X (point C) after the cycle",
                );
                return;
            }
            _ => None,
        };
        let kind = ItemKind::TapCycle(TapCycle {
            end_z,
            lead,
            then_x,
        });
        self.r.pos = kind.end_position(self.r.pos);
        self.push(kind, span, None);
        self.feed = Feed::AfterThread(g.line);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diag::Severity;
    use crate::ir::Schedule;

    fn run(text: &str) -> (Program, Vec<Diagnostic>) {
        run_with(text, &Profile::default(), Unsupported::Error)
    }

    fn run_with(
        text: &str,
        profile: &Profile,
        unsupported: Unsupported,
    ) -> (Program, Vec<Diagnostic>) {
        parse(
            &SourceFile::new("t.nc", text),
            profile,
            &Options { unsupported },
        )
    }

    fn kinds(text: &str) -> Vec<ItemKind> {
        let (program, diags) = run(text);
        assert!(diags.is_empty(), "{text:?}: {diags:?}");
        program.items.into_iter().map(|i| i.kind).collect()
    }

    fn mm(v: f64) -> Length {
        Length::from_mm_f64(v)
    }

    /// (code, line, column) of the first error.
    fn first_error(text: &str) -> (&'static str, u32, u32) {
        let (_, diags) = run(text);
        let d = diags
            .iter()
            .find(|d| d.is_error())
            .unwrap_or_else(|| panic!("no error for {text:?}"));
        let loc = d.location.as_ref().expect("located");
        assert!(d.help.is_some(), "{text:?}: no help");
        (d.code.id, loc.line, loc.column)
    }

    const START: &str = "N0 M3\nN1 S700\nN2 X3600 ~ *\nN3 Z450 ~\n";

    #[test]
    fn groups_move_both_axes_at_once_rapid_if_any_frame_says_so() {
        let k = kinds("N3 F30\nN4 X10000 ~ *\nN5 Z5000\nN6 X3600\nN7 Z-100 @\n");
        assert_eq!(
            k,
            vec![
                // The F frame of its own stays (no move of its group uses it).
                ItemKind::FeedRate(mm(0.3)),
                ItemKind::Rapid {
                    to: Pos::new(mm(100.0), mm(50.0))
                },
                ItemKind::Feed {
                    to: Pos {
                        x: Some(mm(36.0)),
                        z: None
                    },
                    feed: mm(0.3)
                },
                ItemKind::Feed {
                    to: Pos {
                        x: None,
                        z: Some(mm(49.0))
                    },
                    feed: mm(0.3)
                },
            ]
        );
    }

    #[test]
    fn spindle_tool_and_speed_range_words() {
        let k = kinds("N0 M40\nN1 M3\nN2 S700\nN6 T5\nN17 M5\nN18 M30\n");
        assert_eq!(
            k,
            vec![
                ItemKind::GearRange {
                    code: 40,
                    machine: super::super::ID,
                },
                ItemKind::Spindle {
                    speed: None,
                    direction: Some(SpindleDirection::Clockwise)
                },
                ItemKind::Spindle {
                    speed: Some(700),
                    direction: None
                },
                ItemKind::Tool {
                    number: Some(5),
                    offset: None
                },
                ItemKind::SpindleStop,
                ItemKind::ProgramEnd(EndCode::M30),
            ]
        );
        // One group: S and M4 become one spindle item.
        let k = kinds("M4 *\nS150\n");
        assert_eq!(
            k,
            vec![ItemKind::Spindle {
                speed: Some(150),
                direction: Some(SpindleDirection::CounterClockwise)
            }]
        );
    }

    #[test]
    fn g31_becomes_one_cycle_from_the_start_point() {
        let text = format!(
            "{START}N9 G31 *\nN10 X3600 *\nN11 Z-4750 *\nN12 F15000 *\nN13 P96 *\nN14 P20\n"
        );
        let (program, diags) = run(&text);
        assert!(diags.is_empty(), "{diags:?}");
        let item = program.items.last().unwrap();
        assert_eq!(item.block_number, Some(9));
        assert_eq!((item.span.line, item.span.column), (5, 1));
        let ItemKind::ThreadCycle(c) = &item.kind else {
            panic!("{:?}", item.kind)
        };
        assert_eq!(c.start, (mm(36.0), mm(4.5)));
        assert_eq!(c.crest, mm(36.0));
        assert_eq!(c.end_z, mm(-47.5));
        assert_eq!(c.lead, crate::fixed::Lead::from_mm_f64(1.5).unwrap());
        assert_eq!(
            (c.depth, c.first_depth, c.taper),
            (mm(0.96), mm(0.2), Length::ZERO)
        );
        assert!(!c.internal);
        assert_eq!(c.retract, crate::ir::Retract::AboveCrest(mm(0.5)));
        assert_eq!(c.schedule, Schedule::Halving);
        // `Z-5200 @` from Z4.5 is the same end.
        let inc = text.replace("Z-4750 *", "Z-5200 @ *");
        let (program, _) = run(&inc);
        assert_eq!(program.items.last().unwrap().kind, item.kind);
    }

    #[test]
    fn g31_takes_parameters_6_and_7_and_the_taper() {
        let mut profile = Profile::default();
        profile.nc31.infeed_p6 = 2365;
        profile.nc31.runout_p7 = 10;
        let text = format!("{START}G31 *\nX3600 *\nZ-4750 *\nF15000 *\nP96 *\nP20 *\nP676\n");
        let (program, diags) = run_with(&text, &profile, Unsupported::Error);
        assert!(diags.is_empty(), "{diags:?}");
        let ItemKind::ThreadCycle(c) = &program.items.last().unwrap().kind else {
            panic!()
        };
        assert_eq!(c.infeed.of(mm(0.96)), mm(0.5543));
        assert_eq!(c.runout.map(|r| r.length), Some(mm(1.5)));
        assert_eq!(c.taper, mm(6.76));
        // A start inside the thread diameter: internal.
        let text = "M3\nS100\nX2000 ~ *\nZ500 ~\nG31 *\nX2200 *\nZ-3000 *\nF15000 *\nP50 *\nP20\n";
        let (program, diags) = run(text);
        assert!(diags.is_empty(), "{diags:?}");
        assert!(
            matches!(&program.items.last().unwrap().kind, ItemKind::ThreadCycle(c) if c.internal)
        );
    }

    /// Arc groups where the profile declares them: the centre from unsigned offsets and
    /// the quadrant, quarter arcs, and the refusals.
    #[test]
    fn arc_groups_take_their_centre_from_the_quadrant() {
        let profile = |direction| {
            let mut p = Profile::default();
            p.nc31.arcs = true;
            p.nc31.arc_direction = direction;
            p
        };
        let arc = |direction, text: &str| {
            let head = "M3\nS500\nX2000 ~ *\nZ0 ~\nF10\n";
            let (p, d) = run_with(
                &format!("{head}{text}"),
                &profile(direction),
                Unsupported::Error,
            );
            let arc = p.items.iter().find_map(|i| match &i.kind {
                ItemKind::Arc {
                    centre, clockwise, ..
                } => Some((**centre, *clockwise)),
                _ => None,
            });
            (arc, d.iter().find(|d| d.is_error()).map(|d| d.code.id))
        };
        let iso = Some(Nc31ArcDirection::Iso);
        let front = Some(Nc31ArcDirection::FrontTool);
        // From Ø20 Z0 to Ø30 Z-5 around r10 Z-5 (ISO G3) or r15 Z0 (ISO G2).
        let g = |code: &str| format!("{code} *\nX3000 *\nZ-500 *\nP0 *\nP500\n");
        assert_eq!(
            arc(iso, &g("G3")),
            (Some((Pos::new(mm(20.0), mm(-5.0)), false)), None)
        );
        assert_eq!(
            arc(front, &g("G2")),
            (Some((Pos::new(mm(20.0), mm(-5.0)), false)), None)
        );
        let g = |code: &str| format!("{code} *\nX3000 *\nZ-500 *\nP500 *\nP0\n");
        assert_eq!(
            arc(iso, &g("G2")),
            (Some((Pos::new(mm(30.0), mm(0.0)), true)), None)
        );
        // Quarter arcs.
        let q = |code: &str| format!("{code} *\nX3000 *\nZ-500\n");
        assert_eq!(
            arc(iso, &q("G13")),
            (Some((Pos::new(mm(20.0), mm(-5.0)), false)), None)
        );
        assert_eq!(
            arc(iso, &q("G12")),
            (Some((Pos::new(mm(30.0), mm(0.0)), true)), None)
        );
        // Refused: no direction declared, offsets that fit no centre, a quarter that is
        // not one, a missing P, arcs not declared at all.
        assert_eq!(arc(None, &q("G13")).1, Some("NCR016"));
        assert_eq!(
            arc(iso, "G3 *\nX3000 *\nZ-500 *\nP100 *\nP500\n").1,
            Some("NCR016")
        );
        assert_eq!(arc(iso, "G13 *\nX3000 *\nZ-700\n").1, Some("NCR016"));
        assert_eq!(arc(iso, "G3 *\nX3000 *\nZ-500 *\nP0\n").1, Some("NCR016"));
        let (_, d) = run("M3\nS500\nX2000 ~ *\nZ0 ~\nF10\nG13 *\nX3000 *\nZ-500\n");
        assert_eq!(
            d.iter().find(|d| d.is_error()).map(|d| d.code.id),
            Some("NCR005")
        );
    }

    #[test]
    fn g32_is_one_pass_at_the_current_diameter() {
        let k = kinds(&format!("{START}N9 G32 *\nN10 F15000 *\nN11 Z-4700\n"));
        assert_eq!(
            k.last(),
            Some(&ItemKind::pass(ThreadPass {
                to: Pos::new(mm(36.0), mm(-47.0)),
                lead: crate::fixed::Lead::from_mm_f64(1.5).unwrap(),
                start: crate::ir::SyncStart::default(),
                infeed: None,
                entry: None,
                exit: None
            }))
        );
    }

    #[test]
    fn g33_taps_and_moves_to_point_c_with_the_offset() {
        let text = "M3\nS150\nX0 ~ *\nZ600 ~\nN9 G33 @ *\nN10 X2000 *\nN11 Z-10000 *\nN12 F15000\nX10000 ~\n";
        let k = kinds(text);
        assert_eq!(
            k[3],
            ItemKind::TapCycle(TapCycle {
                end_z: mm(-100.0),
                lead: crate::fixed::Lead::from_mm_f64(1.5).unwrap(),
                then_x: Some(mm(20.0))
            })
        );
        // Without `@`, X must be where the tool is.
        let k = kinds("M3\nS150\nX0 ~ *\nZ600 ~\nG33 *\nX0 *\nZ-10000 *\nF15000\n");
        assert!(matches!(
            k[3],
            ItemKind::TapCycle(TapCycle { then_x: None, .. })
        ));
    }

    #[test]
    fn feed_is_undefined_after_a_thread_group() {
        let text = format!("N3 F30\n{START}N9 G32 *\nN10 F15000 *\nN11 Z-4700\nN12 X4000\n");
        assert_eq!(first_error(&text), ("NCR008", 9, 5));
        let (_, diags) = run(&text);
        assert!(diags[0].message.contains("line 6"), "{}", diags[0].message);
        // F60 after the pass defines it again (the seed's program).
        let ok = format!("N3 F30\n{START}N9 G32 *\nN10 F15000 *\nN11 Z-4700\nN12 F60\nN13 X4000\n");
        assert!(run(&ok).1.is_empty());
    }

    #[test]
    fn every_rule_has_its_code_and_place() {
        let g31 = |p1: &str, p2: &str| {
            format!("{START}G31 *\nX3600 *\nZ-4750 *\nF15000 *\n{p1} *\n{p2}\n")
        };
        let cases: Vec<(String, (&str, u32, u32))> = vec![
            ("X36.00".into(), ("NCR002", 1, 4)),
            ("N4 X3600 Z450".into(), ("NCR003", 1, 10)),
            ("N4 F30 ~".into(), ("NCR004", 1, 8)),
            ("N4 S700 @".into(), ("NCR004", 1, 9)),
            ("N4 G1 *\nX100".into(), ("NCR005", 1, 4)),
            ("N4 M8".into(), ("NCR005", 1, 4)),
            ("N4 H5".into(), ("NCR005", 1, 4)),
            ("N4 F0".into(), ("NCR006", 1, 4)),
            ("N4 S-5".into(), ("NCR006", 1, 4)),
            ("N4 X100 @".into(), ("NCR007", 1, 9)),
            (
                "N4 G31 *\nX3600 *\nZ-4750 *\nF15000 *\nP96 *\nP20".into(),
                ("NCR007", 1, 4),
            ),
            ("N4 X3600".into(), ("NCR008", 1, 4)),
            ("N4 X3600 ~ *".into(), ("NCR009", 1, 4)),
            ("N4 X3600 ~ *\n%".into(), ("NCR009", 2, 1)),
            (
                format!("{START}G31 *\nX3600 *\nZ-4750 *\nP96 *\nP20\n"),
                ("NCR010", 5, 1),
            ),
            (format!("{START}G32 *\nF15000\n"), ("NCR010", 5, 1)),
            (
                format!("{START}G33 @ *\nZ-100 *\nF15000\n"),
                ("NCR010", 5, 1),
            ),
            (
                format!("{START}G32 *\nX3500 *\nF15000 *\nZ-4700\n"),
                ("NCR011", 6, 1),
            ),
            (
                format!("{START}G31 *\nX3600 *\nZ-4750 *\nF15000 *\nS700 *\nP96 *\nP20\n"),
                ("NCR011", 9, 1),
            ),
            (
                format!("{START}G31 *\nX3600 *\nX3600 *\nZ-4750 *\nF15000 *\nP96 *\nP20\n"),
                ("NCR011", 7, 1),
            ),
            (
                format!("{START}X3600 *\nG32 *\nF15000 *\nZ-4700\n"),
                ("NCR011", 6, 1),
            ),
            (format!("{START}P20\n"), ("NCR011", 5, 1)),
            (
                format!("{START}G33 *\nX2000 *\nZ-100 *\nF15000\n"),
                ("NCR011", 6, 1),
            ),
            (g31("P30", "P20"), ("NCR012", 9, 1)),
            (g31("P96", "P0"), ("NCR012", 10, 1)),
            (
                format!("{START}G31 *\nX3600 *\nZ-4750 *\nF15000 *\nP96 *\nP20 *\nP-10\n"),
                ("NCR012", 11, 1),
            ),
            (format!("{START}G32 *\nF0 *\nZ-4700\n"), ("NCR013", 6, 1)),
            (
                format!("{START}G31 *\nX3600 *\nZ450 *\nF15000 *\nP96 *\nP20\n"),
                ("NCR014", 7, 1),
            ),
            (format!("{START}G32 *\nF15000 *\nZ0 @\n"), ("NCR014", 7, 1)),
            ("N4 G31 ~ *\nX1".into(), ("NCR004", 1, 8)),
            ("N4 X100 (comment".into(), ("NCR001", 1, 9)),
        ];
        for (text, expected) in &cases {
            assert_eq!(first_error(text), *expected, "{text:?}");
        }
    }

    #[test]
    fn runout_that_does_not_fit_is_refused_at_z() {
        let mut profile = Profile::default();
        profile.nc31.runout_p7 = 31;
        // 3.1 leads of 2 = 6.2 mm; the pass is 5 mm long.
        let text = "M3\nS100\nX3600 ~ *\nZ0 ~\nG31 *\nX3600 *\nZ-500 *\nF20000 *\nP96 *\nP20\n";
        let (_, diags) = run_with(text, &profile, Unsupported::Error);
        assert_eq!(diags[0].code, codes::NCR_TRAVEL);
        assert_eq!(diags[0].location.as_ref().unwrap().line, 7);
    }

    #[test]
    fn a_bad_frame_inside_a_group_does_not_cascade() {
        let (_, diags) = run("X36.00 ~ *\nZ450 ~\nF30\n");
        assert_eq!(diags.len(), 1, "{diags:?}");
        assert_eq!(diags[0].code, codes::NCR_DECIMAL_POINT);
    }

    #[test]
    fn unsupported_warn_keeps_the_group_opaque_and_forgets_the_position() {
        let (program, diags) = run_with(
            "X100 ~ *\nZ100 ~\nN5 G4 *\nP100\nX10 @ ~\n",
            &Profile::default(),
            Unsupported::Warn,
        );
        assert_eq!(diags[0].severity, Severity::Warning);
        assert!(
            matches!(&program.items[1].kind, ItemKind::Opaque { block: Some(_), text, .. } if text == "N5 G4 *\nP100")
        );
        assert_eq!(program.items[1].block_number, Some(5));
        assert_eq!(diags[1].code, codes::NCR_UNKNOWN_POSITION);
    }

    #[test]
    fn comments_and_delimiters_are_items() {
        let k = kinds("%\n(M36X1.5)\nM30\n%\n");
        assert_eq!(
            k,
            vec![
                ItemKind::Delimiter,
                ItemKind::Comment("M36X1.5".into()),
                ItemKind::ProgramEnd(EndCode::M30),
                ItemKind::Delimiter
            ]
        );
    }

    /// The items a chamfer group `text` makes from Ø20 Z0 at F20 (0.2 mm/rev).
    fn chamfer(text: &str) -> Vec<ItemKind> {
        let k = kinds(&format!("M3\nS500\nX2000 ~ *\nZ0 ~\n{text}"));
        k[3..].to_vec()
    }

    fn feed(x: f64, z: f64, f: f64) -> ItemKind {
        ItemKind::Feed {
            to: Pos::new(mm(x), mm(z)),
            feed: mm(f),
        }
    }

    /// `X<end>±45 *` + `F`: X to its end, Z by half the diameter change, the sign giving
    /// Z's direction; `Z<end>±45 *` + `F`: Z to its end, the diameter by twice the Z travel.
    /// Read whatever the profile says (nc31.md: "Read it").
    #[test]
    fn chamfers_move_the_other_axis_by_the_same_radial_amount() {
        // X grows by 10 (radius 5): Z +5 or -5.
        assert_eq!(chamfer("X3000+45 *\nF20\n"), [feed(30.0, 5.0, 0.2)]);
        assert_eq!(chamfer("X3000-45 *\nF20\n"), [feed(30.0, -5.0, 0.2)]);
        // X shrinks: the sign still gives Z's direction.
        assert_eq!(chamfer("X1000+45 *\nF20\n"), [feed(10.0, 5.0, 0.2)]);
        assert_eq!(chamfer("X1000-45 *\nF20\n"), [feed(10.0, -5.0, 0.2)]);
        // Z travels 5: the diameter grows or shrinks by 10.
        assert_eq!(chamfer("Z-500+45 *\nF20\n"), [feed(30.0, -5.0, 0.2)]);
        assert_eq!(chamfer("Z-500-45 *\nF20\n"), [feed(10.0, -5.0, 0.2)]);
        assert_eq!(chamfer("Z300+45 *\nF20\n"), [feed(26.0, 3.0, 0.2)]);
        assert_eq!(chamfer("Z300-45 *\nF20\n"), [feed(14.0, 3.0, 0.2)]);
        // Incremental, and the F frame sets the feed for the moves after it.
        assert_eq!(
            chamfer("X1000 @ +45 *\nF15\nZ-2000\n"),
            [
                feed(30.0, 5.0, 0.15),
                ItemKind::Feed {
                    to: Pos {
                        x: None,
                        z: Some(mm(-20.0))
                    },
                    feed: mm(0.15)
                }
            ]
        );
        assert_eq!(chamfer("Z-200@-45*\nF20\n"), [feed(16.0, -2.0, 0.2)]);
        // With a unit of 0.0001 mm half a diameter change can be off the grid: refused.
        let mut fine = Profile::default();
        fine.nc31.linear_unit = Length(1);
        let text = "M3\nS500\nX200000 ~ *\nZ0 ~\nN7 X200001+45 *\nF20\n";
        let (_, diags) = run_with(text, &fine, Unsupported::Error);
        assert_eq!(
            diags.iter().map(|d| d.code.id).collect::<Vec<_>>(),
            ["NCR017"]
        );
        let text = text.replace("X200001", "X200002");
        let (program, diags) = run_with(&text, &fine, Unsupported::Error);
        assert!(diags.is_empty(), "{diags:?}");
        assert_eq!(
            program.items.last().map(|i| &i.kind),
            Some(&ItemKind::Feed {
                to: Pos::new(Length(200_002), Length(1)),
                feed: mm(0.2)
            })
        );
    }

    #[test]
    fn chamfer_rules_have_their_code_and_place() {
        let head = "M3\nS500\nX2000 ~ *\nZ0 ~\n";
        let cases: Vec<(String, (&str, u32, u32))> = vec![
            // Not closed by F, or F not last.
            (format!("{head}X3000+45\n"), ("NCR017", 5, 1)),
            (format!("{head}F20 *\nX3000+45\n"), ("NCR017", 5, 1)),
            // No travel.
            (format!("{head}X2000+45 *\nF20\n"), ("NCR017", 5, 1)),
            (format!("{head}Z0-45 *\nF20\n"), ("NCR017", 5, 1)),
            // A rapid mark, a word that does not belong, a second chamfer, a second F.
            (format!("{head}X3000+45 ~ *\nF20\n"), ("NCR004", 5, 10)),
            (format!("{head}X3000+45 *\nS700 *\nF20\n"), ("NCR011", 6, 1)),
            (format!("{head}X3000+45 *\nZ100 *\nF20\n"), ("NCR011", 6, 1)),
            (
                format!("{head}X3000+45 *\nZ100-45 *\nF20\n"),
                ("NCR011", 6, 1),
            ),
            (format!("{head}X3000+45 *\nF20 *\nF30\n"), ("NCR011", 7, 1)),
            // The mark on a word that is not the chamfer's X or Z.
            (format!("{head}X3000+45 *\nF20+45\n"), ("NCR004", 6, 4)),
            (
                format!("{head}G32 *\nF15000 *\nZ-100+45\n"),
                ("NCR004", 7, 6),
            ),
            (format!("{head}S700-45\n"), ("NCR004", 5, 5)),
            // A feed that is not positive, a start that is not known.
            (format!("{head}X3000+45 *\nF0\n"), ("NCR006", 6, 1)),
            ("X3000+45 *\nF20\n".into(), ("NCR007", 1, 1)),
        ];
        for (text, expected) in &cases {
            assert_eq!(first_error(text), *expected, "{text:?}");
        }
    }

    fn repeating() -> Profile {
        let mut p = Profile::default();
        p.nc31.repeat_g25 = true;
        p
    }

    /// Grooves 5 mm apart: the frames N5 to N7 (incremental) run again twice at the G25.
    const GROOVES: &str = "N0 M3\nN1 S500\nN2 X2000 ~ *\nN3 Z0 ~\nN4 F10\nN5 Z-500 @ ~\nN6 X-400 @\nN7 X400 @ ~\nN8 G25 *\nN9 P5007 *\nN10 P2\nN11 X5000 ~\n";

    #[test]
    fn g25_reads_the_frames_again_count_times() {
        let (program, diags) = run_with(GROOVES, &repeating(), Unsupported::Error);
        assert!(diags.is_empty(), "{diags:?}");
        let moves: Vec<(ItemKind, u32)> = program
            .items
            .iter()
            .skip(4)
            .map(|i| (i.kind.clone(), i.span.line))
            .collect();
        let z = |z: f64| ItemKind::Rapid {
            to: Pos {
                x: None,
                z: Some(mm(z)),
            },
        };
        let x = |x: f64, rapid: bool| {
            let to = Pos {
                x: Some(mm(x)),
                z: None,
            };
            if rapid {
                ItemKind::Rapid { to }
            } else {
                ItemKind::Feed { to, feed: mm(0.1) }
            }
        };
        let mut expected = Vec::new();
        for groove in 1..=3 {
            expected.extend([
                (z(-5.0 * groove as f64), 6),
                (x(16.0, false), 7),
                (x(20.0, true), 8),
            ]);
        }
        expected.push((x(50.0, true), 12));
        assert_eq!(moves, expected);
        // The repeated items keep their frames' numbers.
        assert_eq!(program.items[7].block_number, Some(5));
        // Without the profile's key G25 is refused by name (the help names the key), also
        // when kept as written: one error, at the G25.
        for unsupported in [Unsupported::Error, Unsupported::Warn] {
            let (_, diags) = run_with(GROOVES, &Profile::default(), unsupported);
            assert_eq!(diags.len(), 1, "{diags:?}");
            let d = &diags[0];
            assert_eq!(
                (
                    d.code,
                    d.severity,
                    d.location.as_ref().map(|l| (l.line, l.column))
                ),
                (codes::NCR_UNSUPPORTED, Severity::Error, Some((9, 4)))
            );
            let help = d.help.as_deref().unwrap_or_default();
            assert!(help.contains("repeat_g25 = true"), "{help}");
        }
    }

    #[test]
    fn g25_repeats_absolute_frames_as_the_control_does() {
        // An absolute move repeated goes to the same place again.
        let text = "N0 M3\nN1 S500\nN2 X2000 ~ *\nN3 Z0 ~\nN4 F10\nN5 Z-100\nN6 G25 *\nN7 P5005 *\nN8 P3\n";
        let (program, diags) = run_with(text, &repeating(), Unsupported::Error);
        assert!(diags.is_empty(), "{diags:?}");
        let feeds = program
            .items
            .iter()
            .filter(|i| matches!(i.kind, ItemKind::Feed { .. }))
            .count();
        assert_eq!(feeds, 4);
    }

    #[test]
    fn g25_rules_have_their_code_and_place() {
        let head = "N0 M3\nN1 S500\nN2 X2000 ~ *\nN3 Z0 ~\nN4 F10\nN5 Z-500 @ ~\nN6 X-400 @\nN7 X400 @ ~\n";
        let g25 = |range: &str, count: &str| format!("{head}N8 G25 *\nN9 {range} *\nN10 {count}\n");
        let cases: Vec<(String, (&str, u32, u32))> = vec![
            // The range: backwards, not in the program, holding the G25, negative.
            (g25("P7005", "P2"), ("NCR018", 10, 4)),
            (g25("P20021", "P2"), ("NCR018", 10, 4)),
            (g25("P5008", "P2"), ("NCR018", 10, 4)),
            (g25("P5009", "P2"), ("NCR018", 10, 4)),
            (g25("P-5007", "P2"), ("NCR018", 10, 4)),
            // Inside a group: N3 ends the group N2–N3, N2 starts it.
            (g25("P3007", "P2"), ("NCR018", 10, 4)),
            (g25("P2002", "P2"), ("NCR018", 10, 4)),
            // The count: under 1, or too many frames in all.
            (g25("P5007", "P0"), ("NCR018", 11, 5)),
            (g25("P5007", "P-1"), ("NCR018", 11, 5)),
            (g25("P5007", "P3334"), ("NCR018", 11, 5)),
            // Missing P words, another word.
            (format!("{head}N8 G25 *\nN9 P5007\n"), ("NCR018", 9, 4)),
            (format!("{head}N8 G25\n"), ("NCR018", 9, 4)),
            (
                format!("{head}N8 G25 *\nN9 X100 *\nN10 P5007 *\nN11 P2\n"),
                ("NCR011", 10, 4),
            ),
            (
                format!("{head}N8 G25 ~ *\nN9 P5007 *\nN10 P2\n"),
                ("NCR004", 9, 8),
            ),
            // A repeat of a repeat.
            (
                format!("{head}N8 G25 *\nN9 P5007 *\nN10 P1\nN11 G25 *\nN12 P5010 *\nN13 P1\n"),
                ("NCR018", 13, 5),
            ),
            // Two frames numbered N5, frame numbers out of order.
            (
                format!("{head}N5 X2000 ~\nN8 G25 *\nN9 P5007 *\nN10 P2\n"),
                ("NCR018", 11, 4),
            ),
            (
                format!("{head}N1 X2000 ~\nN8 G25 *\nN9 P7001 *\nN10 P2\n"),
                ("NCR018", 11, 4),
            ),
        ];
        for (text, expected) in &cases {
            let (_, diags) = run_with(text, &repeating(), Unsupported::Error);
            let d = diags
                .iter()
                .find(|d| d.is_error())
                .unwrap_or_else(|| panic!("no error for {text:?}"));
            let loc = d.location.as_ref().expect("located");
            assert!(d.help.is_some(), "{text:?}: no help");
            assert_eq!(
                (d.code.id, loc.line, loc.column),
                *expected,
                "{text:?}: {}",
                d.message
            );
        }
        // The limit is over the whole program: 3334 × 3 frames is too many, and so are two
        // repeats of 1700 × 3.
        let text =
            format!("{head}N8 G25 *\nN9 P5007 *\nN10 P1700\nN11 G25 *\nN12 P5007 *\nN13 P1700\n");
        let (_, diags) = run_with(&text, &repeating(), Unsupported::Error);
        assert_eq!(
            diags
                .iter()
                .map(|d| (d.code.id, d.location.as_ref().unwrap().line))
                .collect::<Vec<_>>(),
            [("NCR018", 14)]
        );
    }

    /// A repeat that fails where its frames did not (the feed is undefined after a thread)
    /// says so once, naming the G25; what the frames already said is not said again.
    #[test]
    fn a_repeat_reports_what_is_new_once() {
        let text = "N0 M3\nN1 S500\nN2 X2000 ~ *\nN3 Z0 ~\nN4 F10\nN5 Z-100\nN6 G32 *\nN7 F15000 *\nN8 Z-200\nN9 G25 *\nN10 P5005 *\nN11 P3\n";
        let (_, diags) = run_with(text, &repeating(), Unsupported::Error);
        assert_eq!(diags.len(), 1, "{diags:?}");
        assert_eq!(diags[0].code, codes::NCR_NO_FEED);
        assert_eq!(diags[0].location.as_ref().unwrap().line, 6);
        assert!(
            diags[0]
                .message
                .ends_with("(repeated by the G25 on line 10)"),
            "{}",
            diags[0].message
        );
        let text = "N0 M3\nN1 S500\nN2 X2000 ~ *\nN3 Z0 ~\nN5 Z-100\nN6 G25 *\nN7 P5005 *\nN8 P3\n";
        let (_, diags) = run_with(text, &repeating(), Unsupported::Error);
        assert_eq!(diags.len(), 1, "{diags:?}");
        assert!(!diags[0].message.contains("G25"), "{}", diags[0].message);
        // Many repeats of frames that failed add nothing (and stay quick: the diagnostics
        // reported are gathered once, not at every repeat), until the limit: 1666 repeats of
        // 6 frames fit in 10,000, the 334 after them are refused at their count.
        let mut text = String::from("N0 M3\nN1 S500\nN2 X2000 ~ *\nN3 Z0 ~\nN5 Z-100\n");
        for n in 0..2000 {
            text.push_str(&format!("N{} G25 *\nP5005 *\nP6\n", 6 + n));
        }
        let (_, diags) = run_with(&text, &repeating(), Unsupported::Error);
        assert_eq!(diags.len(), 1 + 334);
        assert_eq!(
            (diags[1].code, diags[1].location.as_ref().map(|l| l.line)),
            (codes::NCR_REPEAT, Some(8 + 3 * 1666))
        );
    }

    #[test]
    fn units_come_from_the_profile() {
        let mut profile = Profile::default();
        profile.nc31.linear_unit = Length(10);
        profile.nc31.feed_unit = Length(10);
        let (program, diags) = run_with("F300\nX36000 *\nZ4500\n", &profile, Unsupported::Error);
        assert!(diags.is_empty());
        assert_eq!(program.items[0].kind, ItemKind::FeedRate(mm(0.3)));
        assert_eq!(
            program.items[1].kind,
            ItemKind::Feed {
                to: Pos::new(mm(36.0), mm(4.5)),
                feed: mm(0.3)
            }
        );
    }
}

//! IR → RS274/NGC as LinuxCNC reads it (diameter mode, ZX plane, mm, feed per revolution).

use std::fmt::Write as _;

use crate::diag::{Code, Diagnostic};
use crate::dialect::DialectId;
use crate::dialect::iso::codes;
use crate::dialect::write::{self, Writer};
use crate::fixed::{Angle, Decimal, Lead, Length};
use crate::ir::{
    Compensation, Coolant, EndCode, FeedMode, Item, ItemKind, MachineMove, Pos, Program,
    SpindleDirection, SpindleMode, SyncStart, TapCycle, ThreadCycle, ThreadPass,
};
use crate::lower::{self, SyncSegment};
use crate::profile::{Profile, ToolChange};
use crate::source::SourceFile;

/// What the ISO writer says of a rigid tap.
const TAP_NOTE: &str = "tap: in, reverse, out";

/// How the header comment of a program ncthread wrote ends.
const HEADER_END: &str = ", converted by ncthread";

/// The fewest decimals of a tapered K (more when the Z lead would not read back exactly).
const K_DECIMALS: usize = 8;

struct Emitter<'a> {
    w: Writer<'a>,
    profile: &'a Profile,
    /// Where the last G33 ended, while the next line may continue it (LinuxCNC then does
    /// not wait for the index pulse).
    sync_end: Option<Pos>,
    /// The last item was `T… M6`, which stopped the spindle: a stop right after it is that
    /// stop, not another.
    m6_stopped: bool,
    /// The last speed and the direction while the spindle turns.
    speed: Option<u32>,
    turning: Option<SpindleDirection>,
    /// The spindle item after a G96 or a G97 went on the mode's line.
    spindle_on_mode_line: bool,
    /// A surface speed in feet per minute is in force: a line with S is written under G20
    /// (LinuxCNC takes G96's S in the units in force when S is set), then G21 again (and
    /// one in metres per minute under G21 in an inch program).
    surface_feet: bool,
    /// G96 is in force (its S is a surface speed).
    surface: bool,
    /// The output's unit of length.
    units: Units,
}

/// The output's unit of length: millimetres, or inches for a program written in inches.
/// The grid holds 0.0001 in exactly; a value between (a computed point) is written to
/// 0.000001 in, within 0.0000127 mm, and counted for one warning.
#[derive(Debug, Default)]
struct Units {
    inch: bool,
    rounded: usize,
    largest: Length,
    /// The first value rounded, and its item.
    first: Option<String>,
    span: Option<crate::source::Span>,
    /// The last tapered K written, by the unit, the lead and the move's ΔX and ΔZ, which
    /// alone decide it ([`k_value`]): a thread cycle's passes end in the same runout, and finding the K
    /// formats and reads back a number several times.
    last_k: Option<((bool, Lead, Length, Length), String)>,
}

impl Units {
    /// A length in the output's unit.
    fn len(&mut self, v: Length) -> String {
        if !self.inch {
            return v.mm();
        }
        let (text, exact) = v.inches();
        self.count(exact, v.inch_deviation(&text, false), &text);
        text
    }

    /// Half a length (a diameter's radius) in the output's unit, exact to the grid's half
    /// step in millimetres.
    fn half(&mut self, v: Length) -> String {
        if !self.inch {
            return v.half_mm();
        }
        let (text, exact) = v.half_inches();
        self.count(exact, v.inch_deviation(&text, true), &text);
        text
    }

    /// A lead in the output's unit: in inches exact to 11 decimals (what the reader reads
    /// back exactly).
    fn lead(&mut self, l: Lead) -> String {
        if !self.inch {
            return l.mm();
        }
        let (text, _) = l.inches();
        text
    }

    /// The one warning of the values written between two 0.0001 in steps.
    fn diagnostic(&self, src: &SourceFile) -> Option<Diagnostic> {
        let text = self.first.as_ref()?;
        Some(
            Diagnostic::new(
                codes::ISOW_INCH_ROUNDED,
                format!(
                    "{} value(s) of this inch program lie between two 0.0001 in steps (computed points; the first is written {text}): written to 0.000001 in, each within {} mm",
                    self.rounded,
                    self.largest.mm()
                ),
            )
            .at(src, self.span.unwrap_or_default())
            .help("half of 0.000001 in is 0.0000127 mm, far inside the 0.001 mm that `verify` allows; nothing to do"),
        )
    }

    fn count(&mut self, exact: bool, deviation: Length, text: &str) {
        if !exact {
            self.rounded += 1;
            self.largest = self.largest.max(deviation);
            if self.first.is_none() {
                self.first = Some(text.to_string());
            }
        }
    }

    /// Where a position written in the output's unit is read back: in inches, a point
    /// between two 0.0001 in steps is written to 0.000001 in, and read as that.
    fn read_back(&self, p: Pos) -> Pos {
        if !self.inch {
            return p;
        }
        Pos {
            x: p.x.map(Length::inch_read_back),
            z: p.z.map(Length::inch_read_back),
        }
    }

    /// `X… Z…` of a position.
    fn axes(&mut self, to: Pos) -> String {
        let mut s = String::new();
        self.push_axes(&mut s, to);
        s
    }

    /// [`Self::axes`] appended to `out`.
    fn push_axes(&mut self, out: &mut String, to: Pos) {
        if let Some(x) = to.x {
            out.push_str(" X");
            self.push_len(out, x);
        }
        if let Some(z) = to.z {
            out.push_str(" Z");
            self.push_len(out, z);
        }
    }

    /// [`Self::len`] appended to `out`.
    fn push_len(&mut self, out: &mut String, v: Length) {
        if self.inch {
            out.push_str(&self.len(v));
        } else {
            v.push_mm(out);
        }
    }
}

/// The ISO writer taking a program's items one at a time (a conversion's streaming read,
/// after [`write::Facts`] gathered what it needs to know first), or a whole program
/// ([`Dialect::write`](crate::dialect::Dialect::write)). It looks one item ahead.
pub(crate) struct Items<'a> {
    e: Emitter<'a>,
    from: DialectId,
    inch: bool,
    arcs: bool,
    /// The header is written (after the leading `%` lines and a header comment).
    started: bool,
    /// Where in the output held the header's modes line takes ` G91.1`, until an arc says it.
    arcs_at: Option<usize>,
    /// The header's modes, as the ISO reader reads them back: they are not written again.
    skip_header_modes: bool,
    /// The item waiting for the one after it.
    pending: Option<Item>,
}

impl<'a> Items<'a> {
    /// For `program`'s dialect and unit (its items are not needed).
    pub fn new(
        facts: &write::Facts,
        program: &Program,
        src: &'a SourceFile,
        profile: &'a Profile,
    ) -> Self {
        let mut e = Emitter {
            w: Writer::new(src),
            profile,
            sync_end: None,
            m6_stopped: false,
            speed: None,
            turning: None,
            spindle_on_mode_line: false,
            surface_feet: false,
            surface: false,
            units: Units {
                inch: program.inch,
                ..Units::default()
            },
        };
        e.w.post = Some(split_long_lines);
        e.w.out.push_str("%\n");
        Items {
            e,
            from: program.dialect,
            inch: program.inch,
            arcs: facts.arcs,
            started: false,
            arcs_at: None,
            skip_header_modes: true,
            pending: None,
        }
    }

    /// The header: where the program came from (`header`: kept from a program ncthread
    /// wrote, so that converting the output again gives the same text), and the modes.
    fn start(&mut self, header: Option<&str>) {
        self.started = true;
        match header {
            Some(c) => {
                let _ = writeln!(self.e.w.out, "({})", comment_text(c));
            }
            None => {
                let _ = writeln!(
                    self.e.w.out,
                    "({}, dialect {}{HEADER_END})",
                    comment_text(&self.e.w.src.name),
                    self.from
                );
            }
        }
        // Arcs are written with I and K from their start (G91.1, LinuxCNC's start-up mode,
        // said where a machine's start-up codes might differ).
        let unit = if self.inch { "G20" } else { "G21" };
        if self.arcs {
            let _ = writeln!(self.e.w.out, "G7 G18 {unit} G90 G91.1 G95");
        } else {
            let _ = write!(self.e.w.out, "G7 G18 {unit} G90");
            self.arcs_at = Some(self.e.w.out.len());
            let _ = writeln!(self.e.w.out, " G95");
        }
    }

    /// Writes the item held back, which `item` follows, the header first: whether `item` is
    /// now the one held back (a delimiter or the header's comment before the header is not).
    fn before(&mut self, item: &Item) -> bool {
        if !self.started {
            if item.kind == ItemKind::Delimiter {
                return false;
            }
            if let ItemKind::Comment(c) = &item.kind
                && c.ends_with(HEADER_END)
            {
                self.start(Some(c));
                return false;
            }
            self.start(None);
        }
        if let Some(before) = self.pending.take() {
            self.write(&before, Some(item));
        }
        true
    }

    /// Writes `item`, which `next` follows.
    fn write(&mut self, item: &Item, next: Option<&Item>) {
        if self.skip_header_modes && item.kind == ItemKind::FeedMode(FeedMode::PerRev) {
            self.skip_header_modes = false;
            // Its comment stays, on a line of its own.
            if let Some(c) = &item.comment {
                let _ = writeln!(self.e.w.out, "({})", comment_text(c));
            }
            return;
        }
        if !matches!(item.kind, ItemKind::Comment(_) | ItemKind::Delimiter) {
            self.skip_header_modes = false;
        }
        self.e.w.spill();
        self.e.item(item, next);
    }
}

impl write::ItemWriter for Items<'_> {
    #[cfg(unix)]
    fn follow(&mut self, follow: crate::source::Follow) {
        self.e.w.follow(follow);
    }

    /// An arc after the header: ` G91.1` goes into its modes line while the line is held.
    fn late_facts(&mut self, facts: &write::Facts) -> bool {
        if !facts.arcs || self.arcs {
            return true;
        }
        self.arcs = true;
        if !self.started {
            return true;
        }
        match self.arcs_at.take() {
            Some(at) if self.e.w.holds_all() => {
                self.e.w.out.insert_str(at, " G91.1");
                true
            }
            _ => false,
        }
    }

    fn item(&mut self, item: &Item) {
        if self.before(item) {
            self.pending = Some(item.clone());
        }
    }

    fn take(&mut self, item: Item) {
        if self.before(&item) {
            self.pending = Some(item);
        }
    }

    fn finish(mut self: Box<Self>) -> (Option<crate::dialect::Output>, Vec<Diagnostic>) {
        if !self.started {
            self.start(None);
        }
        if let Some(last) = self.pending.take() {
            self.write(&last, None);
        }
        let mut e = self.e;
        e.w.out.push_str("%\n");
        let units = e.units.diagnostic(e.w.src);
        e.w.diags.extend(units);
        e.w.finish()
    }
}

/// The output with every line LinuxCNC could not read ([`syntax::LINE_MAX`] bytes) split: a
/// long comment goes on lines of its own after its block's code, in parts broken at a blank
/// where one is near.
fn split_long_lines(out: String) -> String {
    use super::syntax::LINE_MAX;
    // Each line's length from the line feeds found, as `lines` gives the line (without a CR
    // before its line feed): a search per line took a tenth of the writer's time.
    let bytes = out.as_bytes();
    let mut start = 0;
    let long = memchr::memchr_iter(b'\n', bytes)
        .chain(std::iter::once(bytes.len()))
        .any(|end| {
            let mut line = &bytes[start.min(end)..end];
            if end < bytes.len() {
                line = line.strip_suffix(b"\r").unwrap_or(line);
            }
            start = end + 1;
            line.len() > LINE_MAX
        });
    if !long {
        return out;
    }
    let mut split = String::with_capacity(out.len() + 64);
    for line in out.lines() {
        let (Some(open), true) = (line.find('('), line.len() > LINE_MAX) else {
            split.push_str(line);
            split.push('\n');
            continue;
        };
        let code = line[..open].trim_end();
        if !code.is_empty() {
            split.push_str(code);
            split.push('\n');
        }
        let mut rest = line[open + 1..].trim_end().trim_end_matches(')').trim();
        while !rest.is_empty() {
            let mut end = rest.floor_char_boundary(LINE_MAX - 2);
            if end < rest.len()
                && let Some(blank) = rest[..end].rfind(' ').filter(|&b| b > end / 2)
            {
                end = blank;
            }
            split.push('(');
            split.push_str(rest[..end].trim_end());
            split.push_str(")\n");
            rest = rest[end..].trim_start();
        }
    }
    split
}

/// Makes text safe inside `( )`: no nested parentheses, and no leading word that LinuxCNC
/// would act on (`MSG,`, `DEBUG,`, `PRINT,`, `LOG…`, `PROBE…`, `ABORT,`).
fn comment_text(text: &str) -> String {
    let text: String = text
        .chars()
        .map(|c| match c {
            '(' => '[',
            ')' => ']',
            c if c.is_control() => ' ',
            c => c,
        })
        .collect();
    // The reader trims comments: so does the writer, so that a conversion reads back as it is.
    let text = text.trim().to_string();
    let upper = text.trim_start().to_ascii_uppercase();
    let active = ["MSG,", "DEBUG,", "PRINT,", "LOG", "PROBE", "ABORT,"];
    if active.iter().any(|a| upper.starts_with(a)) {
        format!("- {text}")
    } else {
        text
    }
}

/// K for a segment: the lead itself for a move along Z (or the advance of a move along X),
/// exact; for a tapered move the advance along its path with the fewest decimals (at least
/// [`K_DECIMALS`]) that the iso reader turns back into exactly the same Z lead, so that a
/// conversion read back (and `verify`, and ISO → ISO) holds the lead it was given.
fn k_value(segment: &SyncSegment, units: &mut Units) -> String {
    let (Some(x0), Some(x1), Some(z0), Some(z1)) =
        (segment.from.x, segment.to.x, segment.from.z, segment.to.z)
    else {
        return units.lead(segment.lead);
    };
    if x0 == x1 || z0 == z1 {
        return units.lead(segment.lead);
    }
    let key = (units.inch, segment.lead, x1 - x0, z1 - z0);
    if let Some((last, text)) = &units.last_k
        && *last == key
    {
        return text.clone();
    }
    let text = tapered_k(segment, units.inch, (x0, x1, z0, z1));
    units.last_k = Some((key, text.clone()));
    text
}

/// [`k_value`] of a tapered move, found.
fn tapered_k(
    segment: &SyncSegment,
    inch: bool,
    (x0, x1, z0, z1): (Length, Length, Length, Length),
) -> String {
    let trim = |text: String| text.trim_end_matches('0').trim_end_matches('.').to_string();
    // The reader reads an inch K as K · 25.4 mm, in floating point.
    let per_unit = if inch { 25.4 } else { 1.0 };
    let k = segment.lead_along_path() / per_unit;
    let reads_back = |text: &str| {
        crate::fixed::Decimal::parse(text)
            .and_then(|d| lower::z_lead_of_k(d.to_f64() * per_unit, z1 - z0, x1 - x0))
            == Some(segment.lead)
    };
    for decimals in K_DECIMALS..=17 {
        let text = trim(format!("{k:.decimals$}"));
        if reads_back(&text) {
            return text;
        }
    }
    trim(format!("{k:.17}"))
}

/// `S500 M3`, `M4`, `S500`: the words for a spindle speed and/or direction.
fn spindle_words(speed: Option<u32>, direction: Option<SpindleDirection>) -> String {
    let mut s = String::new();
    if let Some(speed) = speed {
        let _ = write!(s, "S{speed} ");
    }
    match direction {
        Some(SpindleDirection::Clockwise) => s.push_str("M3"),
        Some(SpindleDirection::CounterClockwise) => s.push_str("M4"),
        None => {}
    }
    s.trim_end().to_string()
}

impl Emitter<'_> {
    /// A line that may set S: under a surface speed in feet per minute it stands between
    /// `G20` and `G21`, so that LinuxCNC takes its S in ft/min while every length of the
    /// program stays in millimetres.
    fn speed_line(&mut self, text: &str, sets_speed: bool) {
        let other = sets_speed && self.surface && self.surface_feet != self.units.inch;
        let (speed_unit, back) = if self.units.inch {
            ("G21", "G20")
        } else {
            ("G20", "G21")
        };
        if other {
            self.line(speed_unit);
        }
        self.line(text);
        if other {
            self.line(back);
        }
    }

    fn diag(
        &mut self,
        code: Code,
        item: &Item,
        message: impl Into<String>,
        help: impl Into<String>,
    ) {
        self.w.error(code, item.span, message, help);
    }

    fn line(&mut self, text: &str) {
        self.w.out.push_str(text.trim_start());
        self.w.out.push('\n');
    }

    /// `(text)` on a line of its own (`text` of ncthread's own words: no parenthesis).
    fn comment_line(&mut self, text: &str) {
        self.w.out.push('(');
        self.w.out.push_str(text);
        self.w.out.push_str(")\n");
    }

    /// A line whose words say lengths in the output's unit.
    fn unit_line(&mut self, words: impl FnOnce(&mut Units) -> String) {
        let text = words(&mut self.units);
        self.line(&text);
    }

    fn item(&mut self, item: &Item, next: Option<&Item>) {
        let rounded = self.units.rounded;
        self.item_words(item, next);
        if self.units.rounded > rounded && self.units.span.is_none() {
            self.units.span = Some(item.span);
        }
        // The next line starts where LinuxCNC reads this one's end.
        self.w.pos = self.units.read_back(self.w.pos);
    }

    fn item_words(&mut self, item: &Item, next: Option<&Item>) {
        let start = self.w.out.len();
        let m6_stopped = std::mem::take(&mut self.m6_stopped);
        // Only a comment line keeps a G33 chain going.
        if !matches!(
            item.kind,
            ItemKind::ThreadPass(_) | ItemKind::Comment(_) | ItemKind::Delimiter
        ) {
            self.sync_end = None;
        }
        match &item.kind {
            // The commonest lines, written in place.
            ItemKind::Rapid { to } => {
                self.w.out.push_str("G0");
                self.units.push_axes(&mut self.w.out, *to);
                self.w.out.push('\n');
            }
            ItemKind::Feed { to, feed } => {
                self.w.out.push_str("G1");
                self.units.push_axes(&mut self.w.out, *to);
                self.w.out.push_str(" F");
                self.units.push_len(&mut self.w.out, *feed);
                self.w.out.push('\n');
            }
            ItemKind::Arc {
                to,
                centre,
                clockwise,
                feed,
            } => self.arc(item, *to, **centre, *clockwise, *feed),
            ItemKind::ThreadPass(pass) => self.thread_pass(item, pass),
            ItemKind::ThreadCycle(cycle) => self.thread_cycle(item, cycle),
            ItemKind::TapCycle(tap) => self.tap_cycle(item, tap),
            // Written on the G96 or G97 line before it.
            ItemKind::Spindle { .. } if std::mem::take(&mut self.spindle_on_mode_line) => {}
            ItemKind::Spindle { speed, direction } => self.spindle(*speed, *direction),
            ItemKind::FeedRate(f) => self.unit_line(|u| format!("F{}", u.len(*f))),
            ItemKind::SpindleMode(SpindleMode::Rpm) => self.rpm_mode(next),
            ItemKind::Compensation(c) => self.unit_line(|u| compensation_words(c, u)),
            ItemKind::WorkOffset(n) => self.line(work_offset_word(*n)),
            // The motion mode after G53 is the line's G0/G1, as in the source.
            ItemKind::MachineMove(m) => self.unit_line(|u| machine_move_words(m, u)),
            ItemKind::SpindleMode(SpindleMode::SurfaceSpeed { limit, feet }) => {
                if !self.surface_speed(item, *limit, *feet, next) {
                    return;
                }
            }
            // LinuxCNC's M6 has just stopped the spindle (the iso reader notes that stop).
            ItemKind::SpindleStop if m6_stopped => {}
            ItemKind::SpindleStop => {
                self.turning = None;
                self.line("M5");
            }
            ItemKind::Tool { number, offset } => self.tool(*number, *offset, next),
            ItemKind::GearRange { code: m, .. } => self.gear_range(item, *m),
            ItemKind::MachineCode { code, machine } => self.machine_code(item, *code, *machine),
            ItemKind::FeedMode(FeedMode::PerRev) => self.line("G95"),
            ItemKind::FeedMode(FeedMode::PerMin) => self.line("G94"),
            ItemKind::ProgramEnd(EndCode::M2) => self.line("M2"),
            ItemKind::ProgramEnd(EndCode::M30) => self.line("M30"),
            ItemKind::Comment(text) => self.line(&format!("({})", comment_text(text))),
            // Its effect is already in the items that use it; keep it for the reader.
            ItemKind::ParamAssign { number, value } => {
                self.line(&format!("(R{number:02}={value})"))
            }
            // ISO words ncthread keeps without modelling them (coolant, path control…).
            ItemKind::Opaque {
                dialect: super::ID,
                text,
                ..
            } => self.line(text),
            ItemKind::Opaque {
                dialect,
                text,
                block,
            } => self.opaque(item, *dialect, text, block.is_some()),
            ItemKind::Dwell { seconds } => self.line(&format!("G4 P{seconds}")),
            ItemKind::Coolant(c) => self.line(coolant_word(*c)),
            ItemKind::Stop { optional } => self.line(if *optional { "M1" } else { "M0" }),
            ItemKind::Delimiter => {}
            // Unrolled into its moves at the top of `emit`.
            ItemKind::Roughing(_) | ItemKind::ModelCycle(_) => {}
        }
        self.w.pos = item.kind.end_position(self.w.pos);
        self.item_comment(item, start);
    }

    /// The spindle's speed and direction on a line.
    fn spindle(&mut self, speed: Option<u32>, direction: Option<SpindleDirection>) {
        if speed.is_some() {
            self.speed = speed;
        }
        if direction.is_some() {
            self.turning = direction;
        }
        let text = spindle_words(speed, direction);
        self.speed_line(&text, speed.is_some());
    }

    /// G97, with the speed that follows it on its line (`G97 S800 M3`): LinuxCNC sets the
    /// mode, then the speed, in one block, where a `G97` of its own would turn the spindle
    /// at the surface speed's S as rpm until the next line.
    fn rpm_mode(&mut self, next: Option<&Item>) {
        self.surface_feet = false;
        self.surface = false;
        match self.speed_on_mode_line(next) {
            Some(words) => self.speed_line(&format!("G97 {words}"), true),
            None => self.line("G97"),
        }
    }

    /// The words of the speed item `next`, when it gives S, for the line of the G96 or G97
    /// before it (which then writes it, `spindle_on_mode_line`); its speed and direction taken.
    fn speed_on_mode_line(&mut self, next: Option<&Item>) -> Option<String> {
        let Some(ItemKind::Spindle {
            speed: Some(s),
            direction,
        }) = next.map(|n| &n.kind)
        else {
            return None;
        };
        self.speed = Some(*s);
        if direction.is_some() {
            self.turning = *direction;
        }
        self.spindle_on_mode_line = true;
        Some(spindle_words(Some(*s), *direction))
    }

    /// G96 with its limit D. LinuxCNC wants S on the G96 line: the speed item that follows
    /// goes there (or the speed in force). `false` when there is no speed to write.
    fn surface_speed(
        &mut self,
        item: &Item,
        limit: Option<Decimal>,
        feet: bool,
        next: Option<&Item>,
    ) -> bool {
        let limit = &limit;
        self.surface_feet = feet;
        self.surface = true;
        let mut text = "G96".to_string();
        if let Some(d) = limit {
            let _ = write!(text, " D{d}");
        }
        match self.speed_on_mode_line(next) {
            Some(words) => {
                let _ = write!(text, " {words}");
            }
            None => match self.speed {
                Some(s) => {
                    let _ = write!(text, " S{s}");
                }
                None => {
                    self.diag(
                        codes::ISOW_UNKNOWN_START,
                        item,
                        "G96 with no surface speed to write (LinuxCNC needs S on the G96 line)",
                        "give the surface speed with S on the line that sets the mode",
                    );
                    return false;
                }
            },
        }
        self.speed_line(&text, true);
        true
    }

    /// T (with M6 when the profile changes tools so) and G43 H. LinuxCNC's M6 stops the
    /// spindle; it is restarted unless the source stops it here too (an ISO source says so
    /// with the item that follows).
    fn tool(&mut self, number: Option<u32>, offset: Option<u32>, next: Option<&Item>) {
        let mut text = String::new();
        if let Some(t) = number {
            let _ = write!(text, "T{t}");
            if self.profile.iso.tool_change == ToolChange::M6 {
                text.push_str(" M6");
            }
        }
        if let Some(d) = offset {
            let _ = write!(text, " G43 H{d}");
        }
        self.line(&text);
        let stops = next.is_some_and(|n| n.kind == ItemKind::SpindleStop);
        // The reader notes the stop of a turning spindle that M6 makes: that stop is
        // this M6's, not an M5 of its own.
        let m6 = number.is_some() && self.profile.iso.tool_change == ToolChange::M6;
        if m6 && stops && self.turning.is_some() {
            self.turning = None;
            self.m6_stopped = true;
        }
        if m6 && self.turning.is_some() && !stops {
            let restart = spindle_words(self.speed, self.turning);
            let text = format!("{restart} (restart the spindle after M6)");
            self.speed_line(&text, self.speed.is_some());
        }
    }

    /// A gear range: its M code as the profile maps it, else a comment (and why).
    fn gear_range(&mut self, item: &Item, m: u32) {
        let why = format!("M{m} selects a gear range; LinuxCNC has no such M code");
        self.mapped_mcode(item, m, &why, "gear range");
    }

    /// A machine's own M code: LinuxCNC's user M code as it is, another machine's as the
    /// profile maps it, else a comment (and why). It moves no axis either way.
    fn machine_code(&mut self, item: &Item, m: u32, machine: DialectId) {
        if machine == super::ID {
            self.line(&format!("M{m}"));
        } else {
            let why = format!(
                "M{m} is the {machine} machine's own M code (it moves no axis), which no LinuxCNC M code says"
            );
            let note = format!("the {machine} machine's own M code");
            self.mapped_mcode(item, m, &why, &note);
        }
    }

    /// Another machine's M code `m`: the LinuxCNC M word the profile's `[iso] mcodes` maps
    /// it to, else a comment naming it (`note`) and a warning saying `why`.
    fn mapped_mcode(&mut self, item: &Item, m: u32, why: &str, note: &str) {
        if let Some(word) = self.profile.iso.mcodes.get(&m) {
            let word = word.clone();
            self.line(&word);
            return;
        }
        self.line(&format!("(M{m}: {note}, not converted)"));
        // A user M code (M100–M199) of the same number where there is one.
        let suggestion = if m < 100 {
            format!("M1{m:02}")
        } else {
            "M1…".to_string()
        };
        self.diag(
            codes::ISOW_MCODE,
            item,
            format!("{why}, so it is written as a comment"),
            format!("map it in the profile if the machine needs it: [iso] mcodes = {{ {m} = \"{suggestion}\" }}"),
        );
    }

    /// Another dialect's word or block ncthread keeps without modelling it: a comment,
    /// and why.
    fn opaque(&mut self, item: &Item, dialect: DialectId, text: &str, block: bool) {
        self.line(&format!("({dialect}: {})", comment_text(text)));
        let what = if block { "block" } else { "word" };
        self.diag(
            codes::ISOW_OPAQUE,
            item,
            format!("the {dialect} {what} `{text}` has no documented meaning; it is written as a comment"),
            "check the ISO program by hand where this matters; only the same dialect can write it back",
        );
    }

    /// The item's comment, inline on the item's first line (written from `start`), unless
    /// that line is a comment itself (LinuxCNC keeps only the last comment of a line): then
    /// on a line before it. A line that ends in a comment of the writer's (a start angle's
    /// note) gets this one in the same parentheses, as the reader joins a line's comments:
    /// `(a; b)`.
    fn item_comment(&mut self, item: &Item, start: usize) {
        let comment = match (&item.kind, &item.comment) {
            (ItemKind::TapCycle(_), Some(c)) if !c.contains(TAP_NOTE) => {
                Some(format!("{TAP_NOTE}; {c}"))
            }
            (_, c) => c.as_deref().map(str::to_string),
        };
        if let Some(comment) = &comment {
            let text = comment_text(comment);
            if self.w.out.len() == start || self.w.out[start..].starts_with('(') {
                self.w.out.insert_str(start, &format!("({text})\n"));
            } else {
                let eol = start + self.w.out[start..].find('\n').unwrap_or(0);
                if self.w.out[start..eol].ends_with(')') {
                    self.w.out.insert_str(eol - 1, &format!("; {text}"));
                } else {
                    self.w.out.insert_str(eol, &format!(" ({text})"));
                }
            }
        }
    }

    /// `G2`/`G3 X Z I K F`: I and K the centre's offset from the start (G91.1), I in radius
    /// (LinuxCNC halves X in G7, not I), exact to the grid's half step.
    fn arc(&mut self, item: &Item, to: Pos, centre: Pos, clockwise: bool, feed: Length) {
        let (Some((sx, sz)), Some((cx, cz))) = (self.w.pos.known(), centre.known()) else {
            self.diag(
                codes::ISOW_UNKNOWN_START,
                item,
                "an arc from a position that is not known: its centre cannot be written as an offset from its start",
                "move to an absolute X and Z before the arc",
            );
            return;
        };
        let g = if clockwise { "G2" } else { "G3" };
        let u = &mut self.units;
        let text = format!(
            "{g}{} I{} K{} F{}",
            u.axes(to),
            u.half(cx - sx),
            u.len(cz - sz),
            u.len(feed)
        );
        self.line(&text);
    }

    /// A thread cycle as the passes [`lower::expand`] gives, each introduced by a comment.
    fn thread_cycle(&mut self, item: &Item, cycle: &ThreadCycle) {
        let Some(expansion) = self.w.expand(cycle, item.span) else {
            return;
        };
        let summary = expansion.summary(cycle, "Ø");
        self.comment_line(&summary);
        for step in expansion.steps() {
            let m = match step {
                lower::Step::Heading(heading) => {
                    self.comment_line(&heading);
                    continue;
                }
                lower::Step::Move(m) => m,
            };
            match m {
                lower::Move::Rapid(to) => {
                    self.sync_end = None;
                    self.w.out.push_str("G0");
                    self.units.push_axes(&mut self.w.out, *to);
                    self.w.out.push('\n');
                }
                lower::Move::Pass(pass) => self.thread_pass(item, pass),
            }
            self.w.pos = m.end_position(self.w.pos);
        }
    }

    /// `G33.1 Z K` (LinuxCNC's rigid tap: in, spindle reversal, out, direction restored),
    /// then `G0 X` to point C.
    fn tap_cycle(&mut self, item: &Item, tap: &TapCycle) {
        if self.w.pos.z.is_none() {
            self.diag(
                codes::ISOW_UNKNOWN_START,
                item,
                "the tapping cycle returns to its start Z, which is not known",
                "move to the start of the hole with X and Z first",
            );
            return;
        }
        // The note (what G33.1 does) goes into the line's one comment, unless a program
        // ncthread wrote carries it already.
        let note = if item.comment.is_some() {
            String::new()
        } else {
            format!(" ({TAP_NOTE})")
        };
        let text = format!(
            "G33.1 Z{} K{}{note}",
            self.units.len(tap.end_z),
            self.units.lead(tap.lead)
        );
        self.line(&text);
        if let Some(x) = tap.then_x {
            let text = format!("G0 X{}", self.units.len(x));
            self.line(&text);
        }
    }

    fn thread_pass(&mut self, item: &Item, pass: &ThreadPass) {
        let mut segments = match lower::pass_segments(self.w.pos, pass) {
            Ok(s) => s,
            Err(_) => {
                self.diag(
                    codes::ISOW_UNKNOWN_START,
                    item,
                    "this thread pass needs its start point, which is not known",
                    "move to the start of the thread with X and Z first",
                );
                return;
            }
        };
        // LinuxCNC continues a G33 that starts where another ended without waiting for the
        // index pulse: a continuation is written right after the move it continues (a pass
        // that must wait there is refused by legalisation).
        let in_chain = self.sync_end == Some(self.w.pos);
        match pass.start {
            SyncStart::Continue if !in_chain => {
                self.diag(
                    codes::ISOW_INDEX_WAIT,
                    item,
                    "this thread move continues a synchronised move that does not end where it starts",
                    "this is a bug in the program's reader; report it with the program",
                );
                return;
            }
            SyncStart::Continue => {}
            SyncStart::Index(angle)
                if angle != Angle::ZERO && segments.first().is_some_and(|s| s.is_radial()) =>
            {
                self.diag(
                    codes::ISOW_UNKNOWN_START,
                    item,
                    format!("start angle {angle}° on a pass that starts with a synchronised move along X"),
                    "RS274/NGC G33 has no start angle, and a move along X cannot start earlier along Z",
                );
                return;
            }
            SyncStart::Index(angle) => match lower::start_angle_as_shift(&mut segments, angle) {
                Ok(Some((start, shift))) => {
                    let text = format!(
                        "G0{} (start angle {angle}°: start {shift} mm earlier along the pass)",
                        self.units.axes(start),
                    );
                    self.line(&text);
                }
                Ok(None) => {}
                Err(_) => {
                    self.diag(
                        codes::ISOW_UNKNOWN_START,
                        item,
                        format!("start angle {angle}° on a pass whose start point is not known"),
                        "RS274/NGC G33 has no start angle: ncthread starts the pass lead·angle/360 earlier, which needs the start point; move to it with X and Z first",
                    );
                    return;
                }
            },
        }
        // Each K from where the move starts and ends as they are read back (in inches, a
        // point between two 0.0001 in steps), so that the same lead reads back and
        // converting again writes the same K.
        let mut from = segments.first().map(|s| self.units.read_back(s.from));
        for seg in &segments {
            let read = lower::SyncSegment {
                from: from.unwrap_or(seg.from),
                to: self.units.read_back(seg.to),
                lead: seg.lead,
            };
            self.w.out.push_str("G33");
            self.units.push_axes(&mut self.w.out, seg.to);
            self.w.out.push_str(" K");
            let k = k_value(&read, &mut self.units);
            self.w.out.push_str(&k);
            self.w.out.push('\n');
            from = Some(self.units.read_back(seg.to));
        }
        self.sync_end = segments.last().map(|s| self.units.read_back(s.to));
    }
}

/// The words of a cutter radius compensation: G40, G41/G42 (with the tool table entry D),
/// or G41.1/G42.1 with its diameter (and orientation L).
fn compensation_words(c: &Compensation, units: &mut Units) -> String {
    match c {
        Compensation::Off => "G40".to_string(),
        Compensation::FromTool { right, tool } => {
            let g = if *right { "G42" } else { "G41" };
            tool.map_or(g.to_string(), |t| format!("{g} D{t}"))
        }
        Compensation::Dynamic {
            right,
            diameter,
            orientation,
        } => {
            let g = if *right { "G42.1" } else { "G41.1" };
            let l = orientation.map_or(String::new(), |l| format!(" L{l}"));
            format!("{g} D{}{l}", units.len(*diameter))
        }
    }
}

/// The words of a move in the machine's coordinates: G53 with its G0/G1, G28/G30 (via a
/// point), or G28.1/G30.1.
fn machine_move_words(m: &MachineMove, units: &mut Units) -> String {
    match m {
        MachineMove::Machine { to, feed: None } => format!("G53 G0{}", units.axes(*to)),
        MachineMove::Machine { to, feed: Some(f) } => {
            format!("G53 G1{} F{}", units.axes(*to), units.len(*f))
        }
        MachineMove::Home { second, via } => {
            format!(
                "{}{}",
                if *second { "G30" } else { "G28" },
                units.axes(*via)
            )
        }
        MachineMove::StoreHome { second } => (if *second { "G30.1" } else { "G28.1" }).to_string(),
    }
}

/// The word of work offset `n` (1: G54 … 9: G59.3).
fn work_offset_word(n: u8) -> &'static str {
    match n {
        1 => "G54",
        2 => "G55",
        3 => "G56",
        4 => "G57",
        5 => "G58",
        6 => "G59",
        7 => "G59.1",
        8 => "G59.2",
        _ => "G59.3",
    }
}

/// The M code of a coolant command.
fn coolant_word(c: Coolant) -> &'static str {
    match c {
        Coolant::Mist => "M7",
        Coolant::Flood => "M8",
        Coolant::Off => "M9",
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
    ) -> (Option<String>, Vec<Diagnostic>) {
        let options = crate::dialect::WriteOptions::default();
        let (out, diags) =
            crate::dialect::Dialect::write(&super::super::Iso, program, src, profile, &options);
        (out.map(|o| o.into_string().expect("in memory")), diags)
    }
    use crate::fixed::Length;

    #[test]
    fn a_long_comment_is_split_onto_lines_linuxcnc_reads() {
        let words = ["WORD"; 70].join(" ");
        let wide = "Č".repeat(140);
        let out = split_long_lines(format!("%\n({words})\nT1 M6 ({wide})\nG0 X1\n%\n"));
        assert!(
            out.lines()
                .all(|l| l.len() <= super::super::syntax::LINE_MAX),
            "{out}"
        );
        let lines: Vec<&str> = out.lines().collect();
        assert_eq!(lines[1].len(), 251, "{out}");
        assert!(
            lines[1].ends_with("WORD)") && lines[2].starts_with("(WORD"),
            "{out}"
        );
        assert_eq!(lines[3], "T1 M6");
        let back: String = lines[4..6]
            .iter()
            .map(|l| l.trim_matches(['(', ')']))
            .collect();
        assert_eq!(back, wide);
        assert_eq!(&lines[6..], ["G0 X1", "%"]);
    }

    #[test]
    fn a_line_is_long_as_lines_measures_it() {
        let max = super::super::syntax::LINE_MAX;
        let a = |n: usize| "a".repeat(n);
        for text in [
            String::new(),
            "\n".into(),
            format!("{}\n", a(max)),
            format!("{}\r\n", a(max)),
            format!("{}\r", a(max)),
            a(max),
            a(max + 1),
            format!("x\n{}\nG0\n", a(max + 1)),
            format!("x\n{}\r\nG0\n", a(max)),
            format!("x\n{}\r\r\nG0\n", a(max)),
        ] {
            // The lines are split, or the text kept whole, as when each line was measured
            // with `lines` (the text is rebuilt from its lines only then).
            let fits = !text.lines().any(|l| l.len() > max);
            let rebuilt: String = text.lines().flat_map(|l| [l, "\n"]).collect();
            let split = split_long_lines(text.clone());
            if fits {
                assert_eq!(split, text, "{text:?}");
            } else if !text.contains('(') {
                assert_eq!(split, rebuilt, "{text:?}");
            }
        }
    }

    #[test]
    fn comments_cannot_nest_or_command() {
        assert_eq!(comment_text("A (B) C"), "A [B] C");
        assert_eq!(comment_text("msg, hello"), "- msg, hello");
        assert_eq!(comment_text("ROZTOČENÍ"), "ROZTOČENÍ");
    }

    #[test]
    fn k_keeps_enough_digits() {
        let seg = SyncSegment {
            from: Pos::new(Length::from_mm(226), Length::from_mm(3)),
            to: Pos::new(Length::from_mm(246), Length::from_mm(-100)),
            lead: crate::fixed::Lead::from_length(Length::from_steps(15_000)),
        };
        let mm = &mut Units::default();
        assert_eq!(k_value(&seg, mm), "1.507052888241");
        let straight = SyncSegment {
            to: Pos::new(Length::from_mm(226), Length::from_mm(-100)),
            ..seg
        };
        assert_eq!(k_value(&straight, mm), "1.5");
        // In an inch program: 20 threads per inch, exact; a taper's K reads back to the
        // same lead along Z.
        let inch = &mut Units {
            inch: true,
            ..Units::default()
        };
        let tpi20 = SyncSegment {
            lead: crate::fixed::Lead::from_length(Length::from_steps(12_700)),
            ..straight
        };
        assert_eq!(k_value(&tpi20, inch), "0.05");
        let taper = SyncSegment {
            lead: tpi20.lead,
            ..seg
        };
        let k = k_value(&taper, inch);
        let back = crate::fixed::Decimal::parse(&k).unwrap().to_f64() * 25.4;
        assert_eq!(
            lower::z_lead_of_k(back, Length::from_mm(-103), Length::from_mm(20)),
            Some(tpi20.lead)
        );
        assert_eq!(inch.len(Length(254)), "0.0001");
        assert_eq!(inch.half(Length(254)), "0.00005");
        assert_eq!(inch.rounded, 0);
        assert_eq!(inch.len(Length(100)), "0.000039");
        assert_eq!(inch.rounded, 1);
    }

    #[test]
    fn a_k_remembered_is_the_k_found() {
        let seg = |x0: i64, z0: i64, dx: i64, dz: i64, lead: i64| SyncSegment {
            from: Pos::new(Length::from_steps(x0), Length::from_steps(z0)),
            to: Pos::new(Length::from_steps(x0 + dx), Length::from_steps(z0 + dz)),
            lead: crate::fixed::Lead::from_length(Length::from_steps(lead)),
        };
        // A runout written again (elsewhere, the same ΔX and ΔZ), then others between.
        let moves = [
            seg(326_000, -158_529, 9_200, -10_000, 15_000),
            seg(322_000, -150_000, 9_200, -10_000, 15_000),
            seg(322_000, -150_000, 9_201, -10_000, 15_000),
            seg(322_000, -150_000, 9_200, -10_000, 15_001),
            seg(322_000, -150_000, 9_200, -10_001, 15_000),
            seg(300_000, -150_000, 9_200, -10_000, 15_000),
            seg(300_000, -150_000, 0, -10_000, 15_000),
            seg(300_000, -150_000, 9_200, -10_000, 15_000),
        ];
        for inch in [false, true] {
            let kept = &mut Units {
                inch,
                ..Units::default()
            };
            for m in &moves {
                let fresh = &mut Units {
                    inch,
                    ..Units::default()
                };
                assert_eq!(k_value(m, kept), k_value(m, fresh), "{m:?}");
            }
        }
    }

    #[test]
    fn a_cycle_that_cannot_be_expanded_is_refused() {
        use crate::ir::{Schedule, ThreadCycle};
        use crate::source::Span;
        let src = SourceFile::new("t", "");
        let item = |kind| Item::new(kind, Span::default());
        // Depth 0.3 is less than the halving law needs for a first pass of 0.2 (0.3875).
        let cycle = ThreadCycle {
            depth: Length::from_steps(3_000),
            ..crate::lower::seed_m36_cycle(Schedule::Halving)
        };
        let program = Program {
            items: vec![
                item(ItemKind::Spindle {
                    speed: Some(100),
                    direction: Some(SpindleDirection::Clockwise),
                }),
                item(ItemKind::ThreadCycle(Box::new(cycle))),
            ],
            dialect: crate::dialect::nc31::ID,
            library: Vec::new(),
            number: None,
            inch: false,
            name: None,
        };
        let (out, diags) = emit(&program, &src, &Profile::default());
        assert!(out.is_none());
        assert_eq!(diags[0].code, codes::CYCLE_INVALID);
        assert!(diags[0].message.contains("0.3875"), "{}", diags[0].message);
    }
}

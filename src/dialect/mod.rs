//! The dialects. Each lives in its own folder (reader, writer, its rules, its codes) and
//! meets the others only in the IR. The rest of ncthread knows them only through the
//! [`Dialect`] trait and the registry [`ALL`]: adding a dialect is a folder and a line there.

pub mod capabilities;
pub mod czech;
pub mod detect;
pub mod fanuc;
pub mod heidenhain;
pub mod iso;
pub(crate) mod lex;
pub(crate) mod machine;
pub mod nc31;
pub(crate) mod read;
pub mod siemens;
pub(crate) mod write;
pub use write::{Facts, ItemWriter, Output, WriterReads, WriterView};

pub use read::{ItemSink, Keep, SoFar, Unsupported};
pub(crate) use read::{Letters, WORD_REPORTS, budget, comment_text, one_line, pest_error_offset};
pub(crate) use write::Inexact;

use crate::diag::Diagnostic;
use crate::encoding::TextEncoding;
pub use crate::ir::DialectId;
use crate::ir::Program;
use crate::profile::Profile;
use crate::source::SourceFile;

/// Every diagnostic code: the readers', the profile's, the writers' and the shared ones, in
/// the order README.md lists them (`scripts/codes-table.py`) and the manual page prints them.
pub fn all_codes() -> &'static [crate::diag::Code] {
    static ALL_CODES: std::sync::LazyLock<Vec<crate::diag::Code>> =
        std::sync::LazyLock::new(|| {
            [
                czech::codes::READ,
                nc31::codes::READ,
                crate::diag::codes::PROFILE,
                iso::codes::READ,
                fanuc::codes::READ,
                siemens::codes::READ,
                heidenhain::codes::READ,
                czech::codes::WRITE,
                iso::codes::WRITE,
                nc31::codes::WRITE,
                fanuc::codes::WRITE,
                siemens::codes::WRITE,
                heidenhain::codes::WRITE,
                crate::diag::codes::SHARED,
            ]
            .concat()
        });
    &ALL_CODES
}

/// Every dialect, in the order ncthread lists them.
pub static ALL: [&'static dyn Dialect; 6] = [
    &czech::Czech,
    &nc31::Nc31,
    &iso::Iso,
    &fanuc::Fanuc,
    &siemens::Siemens,
    &heidenhain::Heidenhain,
];

/// The dialect with this id (`czech`, `nc31`, `iso`), when there is one.
/// The dialect whose programs alone are called `*.ext` (case-insensitive): `ngc` is iso's;
/// `nc`, which every dialect uses, is none's.
pub fn by_extension(ext: &str) -> Option<DialectId> {
    let ext = ext.to_ascii_lowercase();
    let mut having = ALL
        .iter()
        .filter(|d| d.extensions().contains(&ext.as_str()));
    match (having.next(), having.next()) {
        (Some(d), None) => Some(d.id()),
        _ => None,
    }
}

/// The dialect with this id, as ncthread spells it (lower case).
pub fn by_id(id: &str) -> Option<&'static dyn Dialect> {
    ALL.iter().copied().find(|d| d.id().as_str() == id)
}

/// The ids of every dialect, in the registry's order.
pub fn ids() -> impl Iterator<Item = DialectId> {
    ALL.iter().map(|d| d.id())
}

/// A name that is no dialect's id: what [`DialectId`]'s `FromStr` says.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnknownDialect {
    pub given: String,
}

impl std::fmt::Display for UnknownDialect {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let known: Vec<&str> = ids().map(DialectId::as_str).collect();
        write!(
            f,
            "unknown dialect `{}`: the dialects are {}",
            self.given,
            known.join(", ")
        )
    }
}

impl std::error::Error for UnknownDialect {}

/// A dialect's id from its name, in any case (`"FANUC"`, `"iso"`), blanks around it
/// ignored; any other name is an [`UnknownDialect`] that lists the dialects.
///
/// ```
/// use ncthread::DialectId;
/// let id: DialectId = "FANUC".parse().unwrap();
/// assert_eq!(id, ncthread::dialect::fanuc::ID);
/// let err = "fanux".parse::<DialectId>().unwrap_err();
/// assert_eq!(err.to_string(), "unknown dialect `fanux`: the dialects are czech, nc31, iso, fanuc, siemens, heidenhain");
/// ```
impl std::str::FromStr for DialectId {
    type Err = UnknownDialect;

    fn from_str(s: &str) -> Result<DialectId, UnknownDialect> {
        let name = s.trim().to_ascii_lowercase();
        by_id(&name).map(|d| d.id()).ok_or_else(|| UnknownDialect {
            given: s.to_string(),
        })
    }
}

/// The dialect of an id. Every [`DialectId`] names a dialect (its constructor is the
/// crate's, and parsing checks the name), so the fallback is never taken.
pub fn get(id: DialectId) -> &'static dyn Dialect {
    by_id(id.as_str()).unwrap_or(ALL[0])
}

/// The capability table of every dialect (`ncthread dialects`, README.md).
pub fn capability_table(profile: &Profile) -> String {
    let tables: Vec<(&str, capabilities::Capabilities)> = ALL
        .iter()
        .map(|d| (d.id().as_str(), d.capabilities(profile)))
        .collect();
    capabilities::table(&tables)
}

/// How a writer writes what the reader cannot decide for it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WriteOptions {
    /// Block numbers for a target that numbers its blocks, when the program's own are not
    /// that target's.
    pub renumber: Renumber,
    /// Round values the target cannot hold to its grid (with a warning) instead of refusing.
    pub round: bool,
    /// Write comments as comment lines where the control has none (for a PC-side archive).
    pub comments: bool,
}

/// How blocks are numbered: `N{start}`, then every `step`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Renumber {
    pub start: u32,
    pub step: u32,
}

impl Default for Renumber {
    fn default() -> Self {
        Renumber {
            start: 10,
            step: 10,
        }
    }
}

/// How a line looks to one dialect, for `--from auto` ([`detect`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LineMark {
    /// Only this dialect writes such a line.
    Mark,
    /// It looks like this dialect's but does not prove it (the НЦ-31's one whole-number word
    /// without a modifier).
    Weak,
    /// A line that says nothing of the dialect (a comment line that several dialects have).
    Neutral,
}

/// One dialect's claim on a line: the claim with the highest `priority` decides the line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LineClaim {
    pub priority: u8,
    pub mark: LineMark,
}

/// A program dialect: what the rest of ncthread knows of it.
pub trait Dialect: Sync {
    /// Its id (`czech`): `--from`, `--to`, the IR's [`DialectId`].
    fn id(&self) -> DialectId;
    /// For people: `the czech control`.
    fn title(&self) -> &'static str;
    /// The extension `batch` gives its outputs (without the dot).
    fn extension(&self) -> &'static str;
    /// The extensions its programs are found under in a shop's archive (without the dot,
    /// matched case-insensitively): what `batch` and `check` take from a folder.
    fn extensions(&self) -> &'static [&'static str];
    /// The encoding of its files when they are not UTF-8.
    fn legacy_encoding(&self) -> TextEncoding;
    /// Its claim on one line of a text whose dialect is not given (`--from auto`).
    fn claim_line(&self, line: &str) -> Option<LineClaim>;
    /// What its mark is, for `--from auto`'s reason: `a czech mark (a `"` comment, …)`.
    fn mark_description(&self) -> &'static str;
    /// Its weak claims alone choose it (uncertainly), and why: the НЦ-31's whole-number words.
    fn weak_reason(&self) -> Option<&'static str> {
        None
    }
    /// A line no dialect claims (several or decimal words) speaks against it.
    fn plain_lines_contradict(&self) -> bool {
        false
    }
    /// The dialect chosen, uncertainly, when no line carries any dialect's mark.
    fn is_fallback(&self) -> bool {
        self.fallback_reason().is_some()
    }
    /// Why it is chosen when no line carries any dialect's mark (for the one fallback).
    fn fallback_reason(&self) -> Option<&'static str> {
        None
    }
    /// Which of two dialects with as many marked lines wins (the higher).
    fn tie_rank(&self) -> u8;
    /// What `--from auto` says beside this dialect when it chose it, for a profile: which
    /// variant of the language it reads the program in, and why (FANUC's G-code system).
    fn auto_note(&self, _profile: &Profile) -> Option<String> {
        None
    }
    /// LinuxCNC's interpreter reads its programs (so `rs274` can judge them).
    fn linuxcnc_reads(&self) -> bool {
        false
    }
    /// Its writer writes an inch program in inches (else every output is in millimetres).
    fn says_inches(&self) -> bool {
        false
    }
    /// The feed mode its output is in before the program sets one (a header that the
    /// writer always writes), if any.
    fn output_feed_mode(&self) -> Option<crate::ir::FeedMode> {
        None
    }
    /// Reads a program, keeping what `keep` says: the program, only its diagnostics (a
    /// conversion's read-back), or nothing, each line's items handed to a sink once read.
    /// The items and diagnostics are the same whatever it keeps.
    fn read_keeping(
        &self,
        src: &SourceFile,
        profile: &Profile,
        unsupported: Unsupported,
        keep: Keep<'_>,
    ) -> (Program, Vec<Diagnostic>);
    /// Reads a program. It is usable only when no diagnostic is an error.
    fn read(
        &self,
        src: &SourceFile,
        profile: &Profile,
        unsupported: Unsupported,
    ) -> (Program, Vec<Diagnostic>) {
        self.read_keeping(src, profile, unsupported, Keep::Program)
    }
    /// The diagnostics of [`Dialect::read`] without the program: what a conversion's
    /// read-back of its output needs. A reader may let go of each line's items once read.
    fn diagnostics(
        &self,
        src: &SourceFile,
        profile: &Profile,
        unsupported: Unsupported,
    ) -> Vec<Diagnostic> {
        self.read_keeping(src, profile, unsupported, Keep::Diagnostics)
            .1
    }
    /// [`Dialect::read`], each item handed to `sink` once its line is read: the program
    /// returned holds none (issue 34: a program need not be in memory whole).
    fn stream(
        &self,
        src: &SourceFile,
        profile: &Profile,
        unsupported: Unsupported,
        sink: &mut dyn ItemSink,
    ) -> (Program, Vec<Diagnostic>) {
        self.read_keeping(src, profile, unsupported, Keep::Stream(sink))
    }
    /// What it reads and writes, for the machine `profile` describes.
    fn capabilities(&self, profile: &Profile) -> capabilities::Capabilities;
    /// The diagnostic that refuses a use of a construct its table says it does not write: its
    /// code, in its words. `None` when it refuses that construct itself while writing.
    fn refusal(&self, at: capabilities::Occurrence, src: &SourceFile) -> Option<Diagnostic>;
    /// What its writer ([`Dialect::item_writer`]) reads of the facts and the program's
    /// header: everything unless a dialect says less.
    fn writer_reads(&self) -> WriterReads {
        WriterReads::ALL
    }
    /// Its writer, taking a program one item at a time (a conversion never holds the
    /// program: issue 34), given what a first read gathered ([`Facts`]) and the program as
    /// read without its items (its dialect, number, name and unit).
    fn item_writer<'a>(
        &self,
        facts: &Facts,
        program: &Program,
        src: &'a SourceFile,
        profile: &'a Profile,
        options: &WriteOptions,
    ) -> Box<dyn ItemWriter + Send + 'a>;
    /// Writes `program` (read from `src`, whose lines the diagnostics point at), roughing
    /// cycles as their moves, through [`Dialect::item_writer`]. `None` when an item cannot
    /// be written; the diagnostics say why.
    fn write(
        &self,
        program: &Program,
        src: &SourceFile,
        profile: &Profile,
        options: &WriteOptions,
    ) -> (Option<crate::dialect::Output>, Vec<Diagnostic>) {
        let program = &*crate::lower::unroll(program, Some(self.id()));
        let mut facts = Facts::default();
        program.items.iter().for_each(|item| {
            facts.item(item);
        });
        let mut writer = self.item_writer(&facts, program, src, profile, options);
        for item in &program.items {
            writer.item(item);
        }
        writer.finish()
    }
}

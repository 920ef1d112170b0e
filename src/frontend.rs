//! What every front end shows of one program — the CLI and the browser page (`web/`) call
//! these, so that a page's result is the CLI's own: the program decoded and its dialect
//! chosen from its bytes, what `--from auto` says of that choice, and `verify`'s verdict.

use crate::diag::{self, Diagnostic};
use crate::dialect::{self, DialectId};
use crate::profile::Profile;
use crate::source::SourceFile;
use crate::text::{Decoded, TextEncoding};
use crate::{Outcome, sim};

/// A program read from its bytes: its text (as a [`SourceFile`] named `name`), the dialect
/// it is read in, and how it was decoded.
pub struct Read {
    pub src: SourceFile,
    pub from: DialectId,
    pub decoded: Decoded,
}

/// Decodes the bytes of a program called `name` in dialect `from`, or (`None`: `--from
/// auto`) chooses the dialect from its text and name; `encoding` when given, else UTF-8 when
/// valid, else the dialect's legacy encoding.
pub fn read(
    name: String,
    bytes: Vec<u8>,
    from: Option<DialectId>,
    encoding: Option<TextEncoding>,
) -> Read {
    let mut decoded =
        crate::text::decode_program_owned(bytes, from, encoding, Some(std::path::Path::new(&name)));
    let text = std::mem::take(&mut decoded.text);
    Read {
        src: SourceFile::new(name, text),
        from: decoded.dialect,
        decoded,
    }
}

impl Read {
    /// What `--from auto` chose and why, and which variant of the dialect it reads the
    /// program in (for `profile`): `None` when the dialect was given. With `always` false,
    /// only what the CLI says on stderr: a choice it is not sure of, or a variant.
    pub fn auto_note(&self, profile: &Profile, always: bool) -> Option<String> {
        let d = self.decoded.detection.as_ref()?;
        let name = &self.src.name;
        let variant = dialect::get(d.dialect)
            .auto_note(profile)
            .map_or(String::new(), |v| format!(", {v}"));
        if !d.certain {
            Some(format!(
                "--from auto: reading {name} as {} ({}){variant}; give --from to be sure",
                d.dialect, d.reason
            ))
        } else if always {
            Some(format!(
                "--from auto: reading {name} as {} ({}){variant}",
                d.dialect, d.reason
            ))
        } else if !variant.is_empty() {
            Some(format!(
                "--from auto: reading {name} as {}{variant}",
                d.dialect
            ))
        } else {
            None
        }
    }
}

/// `verify`'s verdict on `outcome`: its first lines, and whether it passes. `src` is the
/// source program read in `from`; `other` names the other program, in `to`.
pub fn verdict(
    outcome: &Outcome,
    src: &SourceFile,
    from: DialectId,
    other: &str,
    to: DialectId,
) -> (String, bool) {
    match outcome {
        Outcome::Equivalent {
            segments,
            deviation,
            tolerance,
        } => (
            format!(
                "equivalent: {} ({from}) and {other} ({to}) make the same motion ({segments} segments after normalising; largest deviation {} mm; tolerance {} mm, 0.01°)\n",
                src.name,
                deviation.mm(),
                tolerance.mm()
            ),
            true,
        ),
        Outcome::Different(d) => (
            format!(
                "DIFFERENT: {}\n  {} ({from}): {}\n  {other} ({to}): {}\n  first difference: {d}\n",
                d.what,
                src.name,
                segment_text(&d.left),
                segment_text(&d.right),
            ),
            false,
        ),
        Outcome::Refused => (
            "not verified: a program could not be read or converted (see the errors above)\n"
                .to_string(),
            false,
        ),
    }
}

/// A segment of a difference as the verdict prints it.
pub fn segment_text(s: &Option<sim::Segment>) -> String {
    s.map_or("(nothing: the program has ended)".to_string(), |s| {
        s.to_text()
    })
}

/// Diagnostics as the CLI prints them (human form): at most `max_errors` errors per file
/// (0: every one), each with its source line and caret, then how many more there are.
pub fn render_diagnostics(diags: &[Diagnostic], max_errors: usize, color: bool) -> String {
    let (kept, hidden) = diag::cap(diags, max_errors);
    let mut text = String::new();
    for d in kept {
        text.push_str(&d.render(color));
        text.push_str("\n\n");
    }
    for (file, count) in hidden {
        text.push_str(&diag::more_errors(&file, count));
        text.push('\n');
    }
    text
}

//! Bytes ↔ text: a program's decoding with its dialect's legacy default (or its dialect
//! chosen from the text), output encoding with line endings and (optionally) ASCII
//! transliteration. The encodings themselves are [`crate::encoding`]'s.

use crate::diag::{Diagnostic, codes};
use crate::dialect::detect::{Detection, detect};
use crate::dialect::{self, DialectId};
use crate::source::SourceFile;

pub use crate::encoding::TextEncoding;
use crate::encoding::without_bom;

/// The legacy encoding of a dialect's files when they are not UTF-8.
pub fn legacy_encoding(dialect: DialectId) -> TextEncoding {
    dialect::get(dialect).legacy_encoding()
}

/// Decodes a program: UTF-8 (a BOM is removed) when the bytes are valid UTF-8, else the
/// dialect's legacy encoding (see [`legacy_choice`]). Returns the text and the encoding used.
pub fn decode(bytes: &[u8], dialect: DialectId) -> (String, TextEncoding) {
    let body = without_bom(bytes);
    match std::str::from_utf8(body) {
        Ok(text) => (text.to_string(), TextEncoding::UTF_8),
        Err(_) => {
            let encoding = legacy_choice(body, dialect).0;
            (encoding.decode(body), encoding)
        }
    }
}

/// Which legacy encoding a non-UTF-8 file is in. A Czech file is windows-1250 unless its
/// bytes read as Czech only in DOS Latin 2 (CP852, the shop-floor PC's): then CP852, with a
/// note. When neither reads cleanly the choice is not certain (`Some(false)`): the caller
/// refuses rather than garble it. `None`: nothing to tell (no doubt, or no other candidate).
pub fn legacy_choice(body: &[u8], dialect: DialectId) -> (TextEncoding, Option<bool>) {
    let legacy = legacy_encoding(dialect);
    if legacy != TextEncoding::Standard(encoding_rs::WINDOWS_1250) {
        return (legacy, None);
    }
    const LETTERS: &str = "áčďéěíňóřšťúůýžÁČĎÉĚÍŇÓŘŠŤÚŮÝŽäöüÄÖÜ";
    const FAIR: &str = "°§´¨«»–—„“”‚‘’×÷µ±·";
    // (Czech letters, characters no Czech text has there) in each reading.
    let score = |e: TextEncoding| {
        let text = e.decode(body);
        let mut letters = 0usize;
        let mut odd = 0usize;
        for c in text.chars().filter(|c| !c.is_ascii()) {
            if LETTERS.contains(c) {
                letters += 1;
            } else if !FAIR.contains(c) {
                odd += 1;
            }
        }
        (letters, odd)
    };
    let (l1250, odd1250) = score(legacy);
    let (l852, odd852) = score(TextEncoding::Ibm852);
    if odd1250 == 0 && l1250 >= l852 {
        (legacy, None)
    } else if odd852 == 0 && l852 > 0 {
        (TextEncoding::Ibm852, Some(true))
    } else if odd1250 <= odd852 {
        (legacy, Some(false))
    } else {
        (TextEncoding::Ibm852, Some(false))
    }
}

/// The diagnostic of a legacy encoding chosen from the bytes: a note that a Czech file was
/// read as CP852, or the refusal of a file that reads cleanly in neither.
pub fn legacy_diagnostic(name: &str, encoding: TextEncoding, certain: bool) -> Diagnostic {
    if certain {
        Diagnostic::new(
            codes::ENCODING_GUESSED,
            format!("{name} is read as {encoding}: its bytes are Czech letters in DOS Latin 2, not in windows-1250"),
        )
        .help("give --encoding to say which it is")
    } else {
        Diagnostic::new(
            codes::ENCODING_UNKNOWN,
            format!("{name} reads cleanly neither as windows-1250 nor as IBM852 (CP852): which one it is cannot be told"),
        )
        .help("give --encoding windows-1250 or --encoding ibm852 (or another label)")
    }
}

/// [`decode`], or with `encoding` when one is given.
pub fn decode_as(
    bytes: &[u8],
    encoding: Option<TextEncoding>,
    dialect: DialectId,
) -> (String, TextEncoding) {
    let (bytes, _) = split_eof_mark(bytes);
    match encoding {
        Some(e) => (e.decode(bytes), e),
        None => decode(bytes, dialect),
    }
}

/// Decodes a program whose dialect is not given, and chooses the dialect: the text is read
/// as UTF-8 when valid (or in `encoding` when given); otherwise the dialect is chosen from the
/// ASCII part and the bytes are decoded with that dialect's legacy encoding.
pub fn decode_detect_as(
    bytes: &[u8],
    encoding: Option<TextEncoding>,
) -> (String, TextEncoding, Detection) {
    if let Some(e) = encoding {
        let text = e.decode(bytes);
        let detection = detect(&text);
        return (text, e, detection);
    }
    let body = without_bom(bytes);
    if let Ok(text) = std::str::from_utf8(body) {
        let detection = detect(text);
        return (text.to_string(), TextEncoding::UTF_8, detection);
    }
    let ascii: String = body
        .iter()
        .map(|&b| if b.is_ascii() { b as char } else { '?' })
        .collect();
    let detection = detect(&ascii);
    let (text, encoding) = decode(bytes, detection.dialect);
    (text, encoding, detection)
}

/// A decoded program: its text, the encoding it was read in, its dialect, and how the
/// dialect was chosen when it was not given.
pub struct Decoded {
    pub text: String,
    pub encoding: TextEncoding,
    pub dialect: DialectId,
    pub detection: Option<Detection>,
    /// The file's end-of-file mark (`^Z` and NUL padding of a DOS file), left out of `text`.
    pub eof_mark: Vec<u8>,
    /// Whether the legacy encoding was chosen from the bytes ([`legacy_choice`]): certain, or
    /// not (the file must be refused).
    pub guessed: Option<bool>,
    /// Why the bytes are binary, not a program's text ([`binary_evidence`]): then `text` is
    /// empty and the file must be refused.
    pub binary: Option<String>,
}

impl Decoded {
    /// The refusal of a binary file (INP003), or the note (or refusal) of a legacy encoding
    /// chosen from the bytes, for a file `name`.
    pub fn encoding_diagnostic(&self, name: &str) -> Option<Diagnostic> {
        if let Some(why) = &self.binary {
            return Some(
                Diagnostic::new(
                    codes::BINARY_INPUT,
                    format!("{name} is binary, not a program's text: {why}"),
                )
                .help("give the program's text (as the control's or the PC's software saves it); if it is text in UTF-16, say so with --encoding utf-16le or utf-16be"),
            );
        }
        self.guessed
            .map(|certain| legacy_diagnostic(name, self.encoding, certain))
    }
}

/// Why `body` (a file without its end-of-file mark) is binary rather than a program's text,
/// as git and ripgrep tell: a NUL byte, or more than 1 % control bytes other than tab, line
/// ends and form feed. `None`: it may be text (in any single-byte encoding or UTF-8).
pub fn binary_evidence(body: &[u8]) -> Option<String> {
    if let Some(at) = memchr::memchr(0, body) {
        return Some(format!("it holds NUL bytes (the first at byte {at})"));
    }
    // Counted in byte-wide lanes, 255 bytes at a time (so that a lane cannot overflow):
    // a pass the compiler vectorises, at memory speed on a large program.
    let control: usize = body
        .chunks(255)
        .map(|chunk| {
            chunk.iter().fold(0u8, |n, &b| {
                n + u8::from(b < 0x20 && !matches!(b, b'\t' | b'\n' | b'\r' | 0x0C))
            }) as usize
        })
        .sum();
    (control * 100 > body.len()).then(|| {
        format!(
            "{control} of its {} bytes are control characters",
            body.len()
        )
    })
}

/// Splits a file's trailing end-of-file mark off: a DOS `^Z` (0x1A) and the NUL padding of a
/// file written in fixed-size blocks are where the file ends, not part of the program.
pub fn split_eof_mark(bytes: &[u8]) -> (&[u8], &[u8]) {
    let end = bytes
        .iter()
        .rposition(|&b| b != 0x1A && b != 0)
        .map_or(0, |i| i + 1);
    bytes.split_at(end)
}

/// Decodes a program in dialect `from`, or (`None`) chooses the dialect from the text, and
/// from the file's name (`name`: an extension only one dialect's files have, such as `.ngc`)
/// when the text leaves it uncertain; `encoding` when given, else UTF-8 when valid, else the
/// dialect's legacy encoding.
pub fn decode_program(
    bytes: &[u8],
    from: Option<DialectId>,
    encoding: Option<TextEncoding>,
    name: Option<&std::path::Path>,
) -> Decoded {
    // A UTF-16 file's NUL bytes are half of its characters, not padding.
    let utf16 = encoding.is_some_and(|e| e.name().starts_with("UTF-16"));
    let (bytes, eof_mark) = if utf16 {
        (bytes, &b""[..])
    } else {
        split_eof_mark(bytes)
    };
    let eof_mark = eof_mark.to_vec();
    // Binary bytes are not decoded (nor their dialect guessed): the file is refused.
    if let Some(why) = binary_evidence(bytes).filter(|_| !utf16) {
        return Decoded {
            text: String::new(),
            encoding: encoding.unwrap_or(TextEncoding::UTF_8),
            dialect: from.unwrap_or(dialect::ALL[0].id()),
            detection: None,
            eof_mark,
            guessed: None,
            binary: Some(why),
        };
    }
    let mut decoded = match from {
        Some(dialect) => {
            let (text, encoding) = decode_as(bytes, encoding, dialect);
            Decoded {
                text,
                encoding,
                dialect,
                detection: None,
                eof_mark,
                guessed: None,
                binary: None,
            }
        }
        None => {
            let (mut text, mut encoding_used, mut detection) = decode_detect_as(bytes, encoding);
            if let Some(by_name) = named(&detection, name) {
                (text, encoding_used) = decode_as(bytes, encoding, by_name.dialect);
                detection = by_name;
            }
            let encoding = encoding_used;
            Decoded {
                text,
                encoding,
                dialect: detection.dialect,
                detection: Some(detection),
                eof_mark,
                guessed: None,
                binary: None,
            }
        }
    };
    let body = without_bom(bytes);
    if encoding.is_none() && std::str::from_utf8(body).is_err() {
        decoded.guessed = legacy_choice(body, decoded.dialect).1;
    }
    decoded
}

/// The dialect a file's name chooses where its text left the choice uncertain: an extension
/// only one other dialect's files have (`.ngc`).
fn named(detection: &Detection, name: Option<&std::path::Path>) -> Option<Detection> {
    let extension = name.and_then(|n| n.extension())?.to_string_lossy();
    let d = dialect::by_extension(&extension)?;
    (!detection.certain && d != detection.dialect).then(|| Detection {
        dialect: d,
        certain: false,
        reason: format!(
            "the text has no dialect's marks, and only {d}'s files are called .{extension}"
        ),
    })
}

/// [`decode_program`] of bytes the caller is done with: a program in UTF-8 (no BOM, no
/// encoding asked for) becomes its text without a copy, which for a large program is as much
/// memory again; any other is decoded as [`decode_program`] does.
pub fn decode_program_owned(
    mut bytes: Vec<u8>,
    from: Option<DialectId>,
    encoding: Option<TextEncoding>,
    name: Option<&std::path::Path>,
) -> Decoded {
    let (body, _) = split_eof_mark(&bytes);
    let plain = encoding.is_none()
        && without_bom(body).len() == body.len()
        && binary_evidence(body).is_none();
    if !plain {
        return decode_program(&bytes, from, encoding, name);
    }
    let n = body.len();
    let eof_mark = bytes.split_off(n);
    let text = match String::from_utf8(bytes) {
        Ok(text) => text,
        // Not UTF-8: read as any other file.
        Err(e) => {
            let mut bytes = e.into_bytes();
            bytes.extend_from_slice(&eof_mark);
            return decode_program(&bytes, from, encoding, name);
        }
    };
    let (dialect, detection) = match from {
        Some(d) => (d, None),
        None => {
            let detected = detect(&text);
            let detection = named(&detected, name).unwrap_or(detected);
            (detection.dialect, Some(detection))
        }
    };
    Decoded {
        text,
        encoding: TextEncoding::UTF_8,
        dialect,
        detection,
        eof_mark,
        guessed: None,
        binary: None,
    }
}

/// [`decode_detect_as`] without an encoding.
pub fn decode_detect(bytes: &[u8]) -> (String, TextEncoding, Detection) {
    decode_detect_as(bytes, None)
}

/// Line endings of an output.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Eol {
    /// The input's: CRLF when its first line ends with CRLF, else LF.
    #[default]
    Keep,
    Lf,
    CrLf,
}

/// How an output program becomes bytes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct OutputOptions {
    /// The output's encoding; `None`: the input's when the output is in the input's dialect
    /// (an editor's filter, a clean-up), else UTF-8.
    pub encoding: Option<TextEncoding>,
    /// Write a character the encoding lacks as its ASCII transliteration instead of refusing.
    pub transliterate: bool,
    pub eol: Eol,
}

/// What the output keeps of its input when asked to: line endings, encoding, and a DOS
/// end-of-file mark.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Input {
    pub crlf: bool,
    pub encoding: Option<TextEncoding>,
    pub eof_mark: Vec<u8>,
    /// The output is in the input's dialect.
    pub same_dialect: bool,
}

impl Input {
    /// The input `decoded` as text, converted to `to`.
    pub fn of(
        decoded_text: &str,
        encoding: TextEncoding,
        eof_mark: &[u8],
        same_dialect: bool,
    ) -> Input {
        Input {
            crlf: uses_crlf(decoded_text),
            encoding: Some(encoding),
            eof_mark: eof_mark.to_vec(),
            same_dialect,
        }
    }
}

impl OutputOptions {
    /// The encoding an output of `input` is written in.
    pub fn encoding_for(&self, input: &Input) -> TextEncoding {
        self.encoding.unwrap_or(match input.encoding {
            Some(e) if input.same_dialect && e.can_encode() => e,
            _ => TextEncoding::UTF_8,
        })
    }
}

/// Whether a text's lines end with CRLF (judged by its first line end).
pub fn uses_crlf(text: &str) -> bool {
    text.find('\n')
        .is_some_and(|i| i > 0 && text.as_bytes()[i - 1] == b'\r')
}

/// Encodes an output program (lines ending in LF) with the line endings and encoding asked
/// for, or the input's ([`Eol::Keep`]; [`OutputOptions::encoding_for`]). A same-dialect output
/// in the input's encoding ends with the input's end-of-file mark, as the input did. A
/// character the encoding lacks is an error located in the output (`output_name`), unless
/// transliterated.
pub fn encode_output(
    text: &str,
    output_name: &str,
    options: &OutputOptions,
    input: &Input,
) -> Result<Vec<u8>, Box<Diagnostic>> {
    let form = Form::of(options, input);
    let mut out = Vec::with_capacity(text.len() + text.len() / 16);
    encode_lines(&mut out, text, 0, output_name, options, &form)?;
    out.extend_from_slice(form.eof_mark);
    Ok(out)
}

/// Encodes `text`'s lines (the first of them line `first` of the output, 0-based) onto `out`;
/// the end-of-file mark is not added.
fn encode_lines(
    out: &mut Vec<u8>,
    text: &str,
    first: usize,
    output_name: &str,
    options: &OutputOptions,
    form: &Form,
) -> Result<(), Box<Diagnostic>> {
    // Where encoding changes nothing, the bytes as they are.
    if form.leaves(text) {
        out.extend_from_slice(text.as_bytes());
        return Ok(());
    }
    for (index, line) in text.split_inclusive('\n').enumerate() {
        let body = line.strip_suffix('\n').unwrap_or(line);
        let body = body.strip_suffix('\r').unwrap_or(body);
        // Every encoding ncthread writes is ASCII in its first 128 characters.
        if body.is_ascii() {
            out.extend_from_slice(body.as_bytes());
        } else {
            encode_line(
                out,
                body,
                first + index,
                output_name,
                options,
                form.encoding,
            )?;
        }
        if line.ends_with('\n') {
            out.extend_from_slice(if form.crlf { b"\r\n" } else { b"\n" });
        }
    }
    Ok(())
}

/// An output encoded: in memory, or (a mapped output, [`crate::source::Text`]) in a
/// temporary file, to be copied to where it goes.
#[derive(Debug)]
pub enum Encoded {
    Bytes(Vec<u8>),
    File(std::fs::File),
    /// A mapped text that encoding leaves as it is: written from its map, a stretch at a
    /// time, without a copy in between.
    Text(crate::source::Text),
}

impl Encoded {
    /// Writes its bytes to `to`.
    pub fn write_to(&mut self, to: &mut dyn std::io::Write) -> std::io::Result<()> {
        match self {
            Encoded::Bytes(b) => to.write_all(b),
            Encoded::File(f) => {
                use std::io::Seek as _;
                f.rewind()?;
                std::io::copy(f, to).map(drop)
            }
            Encoded::Text(t) => t
                .stretches(STRETCH)
                .try_for_each(|s| to.write_all(s.as_bytes())),
        }
    }

    /// Makes its bytes the file at `path` without a copy, where they are a whole temporary
    /// file made beside `path` ([`crate::files::spool_beside`]): see
    /// [`crate::files::link_into_place`]. `Ok(false)` when they are not (bytes in memory, a
    /// file made elsewhere, not Linux): the caller writes them ([`Encoded::write_to`]).
    pub fn link_into_place(
        &self,
        path: &std::path::Path,
    ) -> Result<bool, crate::files::WriteError> {
        #[cfg(unix)]
        let file = match self {
            Encoded::Bytes(_) => None,
            Encoded::File(f) => f.try_clone().ok(),
            Encoded::Text(t) => t.file(),
        };
        #[cfg(not(unix))]
        let file: Option<std::fs::File> = None;
        match file {
            Some(file) => crate::files::link_into_place(&file, path),
            None => Ok(false),
        }
    }

    /// Its bytes a buffer at a time, each handed to `each`.
    pub fn each_chunk(&mut self, each: &mut dyn FnMut(&[u8])) -> std::io::Result<()> {
        match self {
            Encoded::Bytes(b) => {
                each(b);
                Ok(())
            }
            Encoded::File(f) => {
                use std::io::{Read as _, Seek as _};
                f.rewind()?;
                let mut buffer = vec![0; 1 << 16];
                loop {
                    match f.read(&mut buffer) {
                        Ok(0) => return Ok(()),
                        Ok(n) => each(&buffer[..n]),
                        Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                        Err(e) => return Err(e),
                    }
                }
            }
            Encoded::Text(t) => {
                t.stretches(STRETCH).for_each(|s| each(s.as_bytes()));
                Ok(())
            }
        }
    }

    /// Its bytes, in memory.
    pub fn into_bytes(mut self) -> std::io::Result<Vec<u8>> {
        match self {
            Encoded::Bytes(b) => Ok(b),
            Encoded::Text(t) => Ok(t.into_string().into_bytes()),
            Encoded::File(_) => {
                let mut bytes = Vec::new();
                self.write_to(&mut bytes)?;
                Ok(bytes)
            }
        }
    }
}

/// [`encode_output`] of a text the caller is done with. Where encoding changes nothing (no
/// end-of-file mark to add, and [`Form::leaves`] every stretch) the text is handed over
/// without a copy: one in memory as its bytes (a copy would be as much memory again), a
/// mapped one to be written from its map; else a mapped text is encoded a stretch of lines
/// at a time into a temporary file, never held whole.
pub fn encode_output_owned(
    text: crate::source::Text,
    output_name: &str,
    options: &OutputOptions,
    input: &Input,
) -> Result<Encoded, Box<Diagnostic>> {
    let form = Form::of(options, input);
    if form.eof_mark.is_empty() && text.stretches(STRETCH).all(|s| form.leaves(s)) {
        return Ok(if text.is_mapped() {
            Encoded::Text(text)
        } else {
            Encoded::Bytes(text.into_string().into_bytes())
        });
    }
    encode_borrowed(&text, output_name, options, input, STRETCH)
}

/// How much of a mapped output is encoded at a time.
const STRETCH: usize = 1 << 20;

/// [`encode_output_owned`] of a text the caller keeps (a text in memory is encoded into
/// memory, a mapped one into a temporary file).
pub fn encode_output_text(
    text: &crate::source::Text,
    output_name: &str,
    options: &OutputOptions,
    input: &Input,
) -> Result<Encoded, Box<Diagnostic>> {
    encode_borrowed(text, output_name, options, input, STRETCH)
}

/// [`encode_output_text`], a mapped text encoded `stretch` bytes (rounded to whole lines) at
/// a time.
fn encode_borrowed(
    text: &crate::source::Text,
    output_name: &str,
    options: &OutputOptions,
    input: &Input,
    stretch: usize,
) -> Result<Encoded, Box<Diagnostic>> {
    if !text.is_mapped() {
        return encode_output(text, output_name, options, input).map(Encoded::Bytes);
    }
    let failed = |e: std::io::Error| {
        Box::new(
            Diagnostic::new(
                codes::OUTPUT_UNREADABLE,
                format!("{output_name} could not be encoded: its temporary file failed ({e})"),
            )
            .help(crate::files::MAKE_ROOM),
        )
    };
    use std::io::Write as _;
    let form = Form::of(options, input);
    let mut file =
        std::io::BufWriter::with_capacity(1 << 16, crate::files::spool_file().map_err(failed)?);
    let mut buffer = Vec::new();
    let mut line = 0;
    for stretch in text.stretches(stretch) {
        buffer.clear();
        encode_lines(&mut buffer, stretch, line, output_name, options, &form)?;
        file.write_all(&buffer).map_err(failed)?;
        line += memchr::memchr_iter(b'\n', stretch.as_bytes()).count();
    }
    file.write_all(form.eof_mark).map_err(failed)?;
    let file = file.into_inner().map_err(|e| failed(e.into_error()))?;
    Ok(Encoded::File(file))
}

/// What an output is written as: its line endings, its encoding, and the end-of-file mark
/// it ends with (the input's, for a same-dialect output in the input's encoding; else none).
struct Form<'a> {
    crlf: bool,
    encoding: TextEncoding,
    eof_mark: &'a [u8],
}

impl<'a> Form<'a> {
    /// Whether encoding `text` changes nothing but the end-of-file mark: LF endings (none
    /// written as CRLF, no CR to drop), and UTF-8 out or `text` all ASCII.
    fn leaves(&self, text: &str) -> bool {
        !self.crlf
            && memchr::memchr(b'\r', text.as_bytes()).is_none()
            && (self.encoding == TextEncoding::UTF_8 || text.is_ascii())
    }

    fn of(options: &OutputOptions, input: &'a Input) -> Form<'a> {
        let crlf = match options.eol {
            Eol::Keep => input.crlf,
            Eol::Lf => false,
            Eol::CrLf => true,
        };
        let encoding = options.encoding_for(input);
        let keeps_mark = input.same_dialect && input.encoding == Some(encoding);
        Form {
            crlf,
            encoding,
            eof_mark: if keeps_mark { &input.eof_mark } else { &[] },
        }
    }
}

/// Encodes one line's `body` (line `index` of the output) character by character.
fn encode_line(
    out: &mut Vec<u8>,
    body: &str,
    index: usize,
    output_name: &str,
    options: &OutputOptions,
    encoding: TextEncoding,
) -> Result<(), Box<Diagnostic>> {
    for (at, c) in body.char_indices() {
        if let Some(bytes) = encoding.encode_char(c) {
            out.extend_from_slice(&bytes);
            continue;
        }
        let ascii = deunicode::deunicode_char(c).filter(|t| !t.is_empty() && t.is_ascii());
        match ascii {
            Some(t) if options.transliterate => out.extend_from_slice(t.as_bytes()),
            None if options.transliterate => out.push(b'?'),
            _ => {
                // The line alone, numbered as the output's.
                let src = SourceFile::new(output_name, body);
                let line_number = index as u32 + 1;
                let span = src.span_in_line(src.line(1), at..at + c.len_utf8());
                let mut refusal = Diagnostic::new(
                    codes::ENCODING,
                    format!(
                        "`{c}` (U+{:04X}) in output line {line_number} cannot be written in {}",
                        c as u32,
                        encoding
                    ),
                )
                .at(&src, span)
                .help(format!(
                    "pass --transliterate to write it as `{}`, or choose an --output-encoding that has it (e.g. utf-8)",
                    ascii.unwrap_or("?")
                ));
                if let Some(location) = &mut refusal.location {
                    location.line = line_number;
                }
                return Err(Box::new(refusal));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The owned decoding gives what the borrowing one gives, for every kind of file.
    #[test]
    fn decoding_owned_bytes_gives_what_decoding_borrowed_ones_gives() {
        let files: [&[u8]; 8] = [
            b"N10 G33 Z-20. K1.5\n",
            b"\xEF\xBB\xBFN10 G00 X10.\n",
            b"G0 X1\n\x1A\x00\x00",
            "ROZTOČENÍ\n".as_bytes(),
            b"N10 \xC8\n",
            b"\x00\x01binary",
            b"",
            b"(no marks)\nX1\n",
        ];
        let froms = [None, Some(dialect::czech::ID), Some(dialect::iso::ID)];
        let names = [None, Some(std::path::Path::new("p.ngc"))];
        for bytes in files {
            for from in froms {
                for name in names {
                    for encoding in [None, Some(TextEncoding::UTF_8)] {
                        let a = decode_program(bytes, from, encoding, name);
                        let b = decode_program_owned(bytes.to_vec(), from, encoding, name);
                        let what = format!("{bytes:?} {from:?} {name:?} {encoding:?}");
                        assert_eq!(a.text, b.text, "{what}");
                        assert_eq!(a.encoding, b.encoding, "{what}");
                        assert_eq!(a.dialect, b.dialect, "{what}");
                        assert_eq!(a.detection, b.detection, "{what}");
                        assert_eq!(a.eof_mark, b.eof_mark, "{what}");
                        assert_eq!(a.guessed, b.guessed, "{what}");
                        assert_eq!(a.binary, b.binary, "{what}");
                    }
                }
            }
        }
    }

    #[test]
    fn decodes_utf8_with_and_without_bom_and_windows_1250() {
        assert_eq!(
            decode("ROZTOČENÍ".as_bytes(), dialect::czech::ID).0,
            "ROZTOČENÍ"
        );
        assert_eq!(decode(b"\xEF\xBB\xBFN10", dialect::czech::ID).0, "N10");
        let (text, enc) = decode(b"\"ROZTO\xC8EN\xCD", dialect::czech::ID);
        assert_eq!(text, "\"ROZTOČENÍ");
        assert_eq!(enc, TextEncoding::Standard(encoding_rs::WINDOWS_1250));
    }

    #[test]
    fn detects_then_decodes_legacy_bytes() {
        // IBM866 «Резьба» on an nc31 comment line.
        let (text, enc, d) =
            decode_detect(b"(\x90\xa5\xa7\xec\xa1\xa0\nN4 X10000 ~ *\nN5 Z5000 ~\n");
        assert_eq!(d.dialect, dialect::nc31::ID);
        assert_eq!(enc, TextEncoding::Standard(encoding_rs::IBM866));
        assert!(text.starts_with("(Резьба"), "{text}");
    }

    #[test]
    fn binary_bytes_are_refused_before_any_decoding() {
        let random: Vec<u8> = (0u32..4096)
            .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8)
            .collect();
        for from in [None, Some(dialect::nc31::ID), Some(dialect::czech::ID)] {
            let d = decode_program(&random, from, None, None);
            let refusal = d.encoding_diagnostic("r.bin").expect("refused");
            assert_eq!(refusal.code, codes::BINARY_INPUT, "{from:?}");
            assert!(
                refusal
                    .message
                    .starts_with("r.bin is binary, not a program's text: it holds NUL bytes"),
                "{}",
                refusal.message
            );
            assert!(d.text.is_empty() && d.detection.is_none());
        }
        // Control bytes without a NUL; a text with one escape is text.
        assert!(binary_evidence(b"\x01\x02\x03N10 G0 X1\n").is_some());
        assert_eq!(
            binary_evidence("N10 G00 X1.\r\n\x0c\tZ2.\n".as_bytes()),
            None
        );
        // A DOS file's ^Z and NUL padding end it; UTF-16 given is not binary.
        let d = decode_program(b"N10 G00 X1.\r\n\x1a\0\0", None, None, None);
        assert!(d.encoding_diagnostic("p").is_none());
        let utf16 = TextEncoding::for_label("utf-16le");
        let d = decode_program(b"N\x001\x000\x00\n\x00", None, utf16, None);
        assert!(d.binary.is_none());
    }

    #[test]
    fn labels_include_ibm852() {
        for label in ["IBM852", "cp852", " 852 "] {
            assert_eq!(TextEncoding::for_label(label), Some(TextEncoding::Ibm852));
        }
        assert_eq!(
            TextEncoding::for_label("CP1250").map(TextEncoding::name),
            Some("windows-1250")
        );
        assert_eq!(TextEncoding::for_label("klingon"), None);
        // DOS Latin 2: Č = 0xAC, Í = 0xD6 (Microsoft's cp852 table).
        assert_eq!(TextEncoding::Ibm852.decode(b"ROZTO\xACEN\xD6"), "ROZTOČENÍ");
        assert!(!TextEncoding::for_label("utf-16le").unwrap().can_encode());
    }

    #[test]
    fn output_takes_the_encoding_line_endings_and_transliteration() {
        let utf8 = OutputOptions::default();
        let crlf = Input {
            crlf: true,
            ..Input::default()
        };
        let lf = Input::default();
        assert_eq!(
            encode_output("A\nB\n", "o", &utf8, &crlf).unwrap(),
            b"A\r\nB\r\n"
        );
        assert_eq!(encode_output("A\nB", "o", &utf8, &lf).unwrap(), b"A\nB");
        let cp852 = OutputOptions {
            encoding: Some(TextEncoding::Ibm852),
            eol: Eol::CrLf,
            ..utf8
        };
        assert_eq!(
            encode_output("\"ROZTOČENÍ\n", "o", &cp852, &lf).unwrap(),
            b"\"ROZTO\xACEN\xD6\r\n"
        );
        let ascii = OutputOptions {
            encoding: TextEncoding::for_label("us-ascii"),
            ..utf8
        };
        // windows-1252 (WHATWG's "us-ascii") has no Č: refused with its output line.
        let d = encode_output("N10\nN20 \"ROZTOČENÍ\n", "out", &ascii, &lf).unwrap_err();
        assert!(
            d.message.starts_with("`Č` (U+010C) in output line 2"),
            "{}",
            d.message
        );
        assert_eq!(
            d.location.as_ref().map(|l| (l.line, l.column)),
            Some((2, 11))
        );
        let t = OutputOptions {
            transliterate: true,
            ..ascii
        };
        // Č becomes C; windows-1252 has Í.
        assert_eq!(
            encode_output("\"ROZTOČENÍ\n", "o", &t, &lf).unwrap(),
            b"\"ROZTOCEN\xCD\n"
        );
    }

    /// The owned form hands the bytes over where encoding changes nothing, and encodes
    /// exactly as [`encode_output`] everywhere: every combination of the cases below.
    #[test]
    fn the_owned_form_encodes_as_the_borrowed_one() {
        let texts = [
            "A\nB\n",
            "A\nB",
            "\"ROZTOČENÍ\n",
            "N1\r\nN2\n",
            "Č\rX\n",
            "N1\nN2\nN3 Č\nN4 Ž\n",
            "",
        ];
        let encodings = [
            None,
            Some(TextEncoding::UTF_8),
            Some(TextEncoding::Ibm852),
            TextEncoding::for_label("us-ascii"),
        ];
        let inputs = [
            Input::default(),
            Input {
                crlf: true,
                ..Input::default()
            },
            Input {
                crlf: false,
                encoding: Some(TextEncoding::Ibm852),
                eof_mark: b"\x1a".to_vec(),
                same_dialect: true,
            },
        ];
        for text in texts {
            for encoding in encodings {
                for eol in [Eol::Keep, Eol::Lf, Eol::CrLf] {
                    for input in &inputs {
                        let options = OutputOptions {
                            encoding,
                            eol,
                            ..OutputOptions::default()
                        };
                        let borrowed = encode_output(text, "o", &options, input)
                            .map_err(|d| (d.message, d.location));
                        let owned = encode_output_owned(text.into(), "o", &options, input);
                        let owned = owned.map(|e| e.into_bytes().expect("in memory"));
                        let what = format!("{text:?} {encoding:?} {eol:?} {input:?}");
                        assert_eq!(
                            borrowed,
                            owned.map_err(|d| (d.message, d.location)),
                            "{what}"
                        );
                        // Mapped from a file, encoded a few bytes (whole lines) at a time.
                        #[cfg(unix)]
                        for stretch in [1, 3, 1 << 20] {
                            use std::io::Write as _;
                            let mut file = tempfile::tempfile().expect("a temporary file");
                            file.write_all(text.as_bytes()).expect("written");
                            let mapped = crate::source::Text::mapped(file).expect("mapped");
                            let encoded = encode_borrowed(&mapped, "o", &options, input, stretch)
                                .map(|e| e.into_bytes().expect("read back"));
                            let encoded = encoded.map_err(|d| (d.message, d.location));
                            assert_eq!(borrowed, encoded, "{what} stretch {stretch}");
                        }
                        // Mapped and handed over (written from the map where encoding leaves
                        // it as it is), written out twice, and a chunk at a time.
                        #[cfg(unix)]
                        {
                            use std::io::Write as _;
                            let mut file = tempfile::tempfile().expect("a temporary file");
                            file.write_all(text.as_bytes()).expect("written");
                            let mapped = crate::source::Text::mapped(file).expect("mapped");
                            let handed = encode_output_owned(mapped, "o", &options, input);
                            let handed = handed.map(|mut e| {
                                let mut once = Vec::new();
                                e.write_to(&mut once).expect("written");
                                let mut chunks = Vec::new();
                                e.each_chunk(&mut |c| chunks.extend_from_slice(c))
                                    .expect("read");
                                assert_eq!(once, chunks, "{what}");
                                let whole = e.into_bytes().expect("read back");
                                assert_eq!(once, whole, "{what}");
                                whole
                            });
                            assert_eq!(
                                borrowed,
                                handed.map_err(|d| (d.message, d.location)),
                                "{what} handed over"
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn a_same_dialect_output_keeps_the_input_encoding_and_its_eof_mark() {
        let (body, mark) = split_eof_mark(b"N10\r\n\x1a\0\0");
        assert_eq!((body, mark), (&b"N10\r\n"[..], &b"\x1a\0\0"[..]));
        assert_eq!(split_eof_mark(b"\0\x1a"), (&b""[..], &b"\0\x1a"[..]));
        assert_eq!(split_eof_mark(b"N1\0N2"), (&b"N1\0N2"[..], &b""[..]));
        let input = Input {
            crlf: true,
            encoding: Some(TextEncoding::Ibm852),
            eof_mark: b"\x1a".to_vec(),
            same_dialect: true,
        };
        let keep = OutputOptions::default();
        assert_eq!(
            encode_output("\"Č\n", "o", &keep, &input).unwrap(),
            b"\"\xAC\r\n\x1a"
        );
        // Another dialect: UTF-8, no mark; an encoding asked for: no mark either.
        let other = Input {
            same_dialect: false,
            ..input.clone()
        };
        assert_eq!(
            encode_output("\"Č\n", "o", &keep, &other).unwrap(),
            "\"Č\r\n".as_bytes()
        );
        let utf8 = OutputOptions {
            encoding: Some(TextEncoding::UTF_8),
            ..keep
        };
        assert_eq!(
            encode_output("\"Č\n", "o", &utf8, &input).unwrap(),
            "\"Č\r\n".as_bytes()
        );
    }
}

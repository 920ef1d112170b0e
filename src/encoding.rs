//! Text encodings: encoding_rs's (every WHATWG label) plus IBM852 (DOS Latin 2, common on
//! Czech shop-floor PCs), which encoding_rs lacks: its tables come from `oem_cp`, generated
//! from Microsoft's code page definitions. Which encoding a dialect's files are in is the
//! dialect's to say ([`crate::dialect::Dialect::legacy_encoding`]); reading a program with it
//! is [`crate::text`]'s.

use encoding_rs::Encoding;

/// A text encoding.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TextEncoding {
    /// One of encoding_rs's.
    Standard(&'static Encoding),
    /// IBM852 / CP852.
    Ibm852,
}

impl TextEncoding {
    pub const UTF_8: TextEncoding = TextEncoding::Standard(encoding_rs::UTF_8);

    /// The encoding a label names: a WHATWG label (`windows-1250`, `cp1250`, `ibm866`,
    /// `utf-8`…) or `ibm852`/`cp852`/`852`. Labels are case-insensitive.
    pub fn for_label(label: &str) -> Option<TextEncoding> {
        let l = label.trim().to_ascii_lowercase();
        if matches!(
            l.as_str(),
            "ibm852" | "cp852" | "852" | "ibm-852" | "cp-852" | "cspcp852" | "x-cp852"
        ) {
            return Some(TextEncoding::Ibm852);
        }
        Encoding::for_label(l.as_bytes()).map(TextEncoding::Standard)
    }

    pub fn name(self) -> &'static str {
        match self {
            TextEncoding::Standard(e) => e.name(),
            TextEncoding::Ibm852 => "IBM852",
        }
    }

    /// Whether text can be written in it (encoding_rs writes UTF-16 and `replacement` as
    /// UTF-8, which would not be what was asked for).
    pub fn can_encode(self) -> bool {
        match self {
            TextEncoding::Standard(e) => e.output_encoding() == e,
            TextEncoding::Ibm852 => true,
        }
    }

    /// Decodes `bytes` (a UTF-8 BOM is removed; malformed bytes become U+FFFD).
    pub fn decode(self, bytes: &[u8]) -> String {
        match self {
            TextEncoding::Standard(e) if e == encoding_rs::UTF_8 => {
                String::from_utf8_lossy(without_bom(bytes)).into_owned()
            }
            TextEncoding::Standard(e) => e.decode_with_bom_removal(bytes).0.into_owned(),
            TextEncoding::Ibm852 => oem_cp::decode_string_complete_table(
                bytes,
                &oem_cp::code_table::DECODING_TABLE_CP852,
            ),
        }
    }

    /// The bytes of one character, or `None` when the encoding has no such character.
    pub(crate) fn encode_char(self, c: char) -> Option<Vec<u8>> {
        if c.is_ascii() {
            return Some(vec![c as u8]);
        }
        match self {
            TextEncoding::Standard(e) => {
                let mut buf = [0u8; 4];
                let (bytes, _, had_errors) = e.encode(c.encode_utf8(&mut buf));
                (!had_errors).then(|| bytes.into_owned())
            }
            TextEncoding::Ibm852 => {
                oem_cp::encode_char_checked(c, &oem_cp::code_table::ENCODING_TABLE_CP852)
                    .map(|b| vec![b])
            }
        }
    }
}

impl std::fmt::Display for TextEncoding {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// `bytes` without a leading UTF-8 byte order mark.
pub(crate) fn without_bom(bytes: &[u8]) -> &[u8] {
    bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes)
}

/// Decodes a file: UTF-8 (a BOM is removed) when the bytes are valid UTF-8, else `legacy`.
pub(crate) fn decode_or(bytes: &[u8], legacy: TextEncoding) -> (String, TextEncoding) {
    let body = without_bom(bytes);
    match std::str::from_utf8(body) {
        Ok(text) => (text.to_string(), TextEncoding::UTF_8),
        Err(_) => (legacy.decode(body), legacy),
    }
}

//! Bytes ↔ text: input decoding with each dialect's legacy default.

use encoding_rs::Encoding;

use crate::dialect::Dialect;
use crate::dialect::detect::{Detection, detect};

/// The legacy encoding of a dialect's files when they are not UTF-8.
pub fn legacy_encoding(dialect: Dialect) -> &'static Encoding {
    match dialect {
        Dialect::Czech => encoding_rs::WINDOWS_1250,
        Dialect::Nc31 => encoding_rs::IBM866,
        Dialect::Iso => encoding_rs::WINDOWS_1252,
    }
}

/// Decodes a program: UTF-8 (a BOM is removed) when the bytes are valid UTF-8, else the
/// dialect's legacy encoding. Returns the text and the encoding used.
pub fn decode(bytes: &[u8], dialect: Dialect) -> (String, &'static Encoding) {
    let body = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    match std::str::from_utf8(body) {
        Ok(text) => (text.to_string(), encoding_rs::UTF_8),
        Err(_) => {
            let encoding = legacy_encoding(dialect);
            let (text, _) = encoding.decode_without_bom_handling(body);
            (text.into_owned(), encoding)
        }
    }
}

/// Decodes a program whose dialect is not given, and chooses the dialect: the text is read
/// as UTF-8 when valid; otherwise the dialect is chosen from the ASCII part and the bytes are
/// decoded with that dialect's legacy encoding.
pub fn decode_detect(bytes: &[u8]) -> (String, &'static Encoding, Detection) {
    let body = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    if let Ok(text) = std::str::from_utf8(body) {
        let detection = detect(text);
        return (text.to_string(), encoding_rs::UTF_8, detection);
    }
    let ascii: String = body
        .iter()
        .map(|&b| if b.is_ascii() { b as char } else { '?' })
        .collect();
    let detection = detect(&ascii);
    let (text, encoding) = decode(bytes, detection.dialect);
    (text, encoding, detection)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decodes_utf8_with_and_without_bom_and_windows_1250() {
        assert_eq!(
            decode("ROZTOČENÍ".as_bytes(), Dialect::Czech).0,
            "ROZTOČENÍ"
        );
        assert_eq!(decode(b"\xEF\xBB\xBFN10", Dialect::Czech).0, "N10");
        let (text, enc) = decode(b"\"ROZTO\xC8EN\xCD", Dialect::Czech);
        assert_eq!(text, "\"ROZTOČENÍ");
        assert_eq!(enc, encoding_rs::WINDOWS_1250);
    }

    #[test]
    fn detects_then_decodes_legacy_bytes() {
        // IBM866 «Резьба» on an nc31 comment line.
        let (text, enc, d) =
            decode_detect(b"(\x90\xa5\xa7\xec\xa1\xa0\nN4 X10000 ~ *\nN5 Z5000 ~\n");
        assert_eq!(d.dialect, Dialect::Nc31);
        assert_eq!(enc, encoding_rs::IBM866);
        assert!(text.starts_with("(Резьба"), "{text}");
    }
}

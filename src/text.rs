//! Bytes ↔ text: input decoding with each dialect's legacy default.

use encoding_rs::Encoding;

use crate::dialect::Dialect;

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
}

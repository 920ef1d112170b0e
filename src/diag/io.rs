//! The one wording of an I/O error.

/// An I/O error in the one wording every command uses: `cannot ACTION PATH: reason`, the
/// reason as the system says it without the `(os error N)` tail (`cannot read P1.NC: no such
/// file or directory`).
pub fn io_error(action: &str, path: impl std::fmt::Display, e: &std::io::Error) -> String {
    format!("cannot {action} {path}: {}", io_reason(e))
}

/// What went wrong, as the system says it, without `(os error N)` and starting in lower case.
pub fn io_reason(e: &std::io::Error) -> String {
    let text = e.to_string();
    let text = match text.rfind(" (os error ") {
        Some(at) if text.ends_with(')') => &text[..at],
        _ => &text,
    };
    let mut chars = text.chars();
    match chars.next() {
        // Lower-case only a word's capital (`No such file`), not an acronym (`UTF-8`).
        Some(c) if chars.clone().next().is_some_and(char::is_lowercase) => {
            c.to_lowercase().chain(chars).collect()
        }
        _ => text.to_string(),
    }
}

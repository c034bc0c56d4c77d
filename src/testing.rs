//! Helpers shared by the core's unit tests.

/// Asserts that `parse` refuses every `(text, needle)` case with a message containing
/// `needle`: how the parsers' tables of bad spellings are checked.
pub(crate) fn assert_refused<T: std::fmt::Debug, E: std::fmt::Display>(
    cases: &[(&str, &str)],
    parse: impl Fn(&str) -> Result<T, E>,
) {
    for (text, needle) in cases {
        let msg = parse(text).unwrap_err().to_string();
        assert!(msg.contains(needle), "{text}: {msg}");
    }
}

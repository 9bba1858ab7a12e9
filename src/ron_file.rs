//! Parsing RON text with the position of any error, shared by fabric and scene files.

use serde::de::DeserializeOwned;

/// A RON syntax or schema error at a 1-based line and column.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RonError {
    /// 1-based line.
    pub line: usize,
    /// 1-based column.
    pub column: usize,
    /// What went wrong, naming the field where the parser knows it.
    pub message: String,
}

/// Parses `text` as `T`. `Some(..)` may be left out around optional values (RON's
/// `implicit_some`), so files read naturally.
pub fn parse<T: DeserializeOwned>(text: &str) -> Result<T, RonError> {
    ron::Options::default()
        .with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME)
        .from_str(text)
        .map_err(|e| RonError {
            line: e.span.start.line,
            column: e.span.start.col,
            message: e.code.to_string(),
        })
}

//! Input files: materials and experiments (TOML), recordings (CSV). Every error names the
//! file, the line and the field, and nothing is written when input is bad.

mod error;
pub mod material;
pub mod recording;

pub use error::InputError;

use serde::de::DeserializeOwned;
use std::path::Path;

/// Read a file to a string, naming it in the error.
pub fn read_text(path: &Path) -> Result<String, InputError> {
    std::fs::read_to_string(path).map_err(|error| InputError::Io {
        path: path.into(),
        message: error.to_string(),
    })
}

/// 1-based line of byte offset `offset` in `text`.
pub fn line_of(text: &str, offset: usize) -> usize {
    text[..offset.min(text.len())].matches('\n').count() + 1
}

/// 1-based line where `key = ...` is written (first match), if any.
pub fn line_of_key(text: &str, key: &str) -> Option<usize> {
    text.lines()
        .position(|line| {
            let line = line.trim_start();
            line.strip_prefix(key)
                .is_some_and(|rest| rest.trim_start().starts_with('='))
        })
        .map(|index| index + 1)
}

/// Parse TOML into `T`, turning serde/toml errors into [`InputError::Field`] with the line.
pub fn parse_toml<T: DeserializeOwned>(path: &Path, text: &str) -> Result<T, InputError> {
    toml::from_str(text).map_err(|error| {
        let message = error.message().to_string();
        // Name the field: toml reports unknown/missing fields in backticks.
        let field = message
            .split('`')
            .nth(1)
            .map(str::to_string)
            .unwrap_or_default();
        let line = error
            .span()
            .map(|span| line_of(text, span.start))
            .or_else(|| line_of_key(text, &field));
        InputError::Field {
            path: path.into(),
            line,
            field,
            message,
        }
    })
}

//! The typed input error.

use std::path::PathBuf;

/// What is wrong with an input file, and where.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum InputError {
    /// The file could not be read or written.
    #[error("{path}: {message}")]
    Io {
        /// File path.
        path: PathBuf,
        /// The operating system's message.
        message: String,
    },
    /// A field is missing, unknown, of the wrong type, or out of its physical range.
    #[error("{path}{}: {}", location(.line, .field), .message.trim_end())]
    Field {
        /// File path.
        path: PathBuf,
        /// 1-based line, when it could be located.
        line: Option<usize>,
        /// Field name (may be empty for syntax errors).
        field: String,
        /// What is wrong.
        message: String,
    },
}

/// What follows the path in [`InputError::Field`]'s message: `:line` when the line is known,
/// then ``: field `name` `` when the field is named.
fn location(line: &Option<usize>, field: &str) -> String {
    let mut text = String::new();
    if let Some(line) = line {
        text.push_str(&format!(":{line}"));
    }
    if !field.is_empty() {
        text.push_str(&format!(": field `{field}`"));
    }
    text
}

impl InputError {
    /// A field error located by its key in `text`.
    pub fn field(
        path: &std::path::Path,
        text: &str,
        field: &str,
        message: impl Into<String>,
    ) -> Self {
        InputError::Field {
            path: path.into(),
            line: super::line_of_key(text, field),
            field: field.into(),
            message: message.into(),
        }
    }

    /// An error about the value at `keys` (from the root; array entries by their 0-based
    /// index, see [`super::line_of_path`]), at its exact line from toml's spans. The field
    /// named is the last key.
    pub fn at(
        path: &std::path::Path,
        text: &str,
        keys: &[&str],
        message: impl Into<String>,
    ) -> Self {
        let field = keys.last().copied().unwrap_or_default();
        InputError::Field {
            path: path.into(),
            line: super::line_of_path(text, keys).or_else(|| super::line_of_key(text, field)),
            field: field.into(),
            message: message.into(),
        }
    }
}

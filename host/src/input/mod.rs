//! Input files: materials and experiments (TOML), recordings (CSV). Every error names the
//! file, the line and the field, and nothing is written when input is bad.

mod error;
pub mod material;
pub mod recording;
pub mod units;

pub use error::InputError;

use serde::de::DeserializeOwned;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

/// Set by `--force`: accept values outside their plausible range and runs above the size
/// limits.
static IMPLAUSIBLE_ALLOWED: AtomicBool = AtomicBool::new(false);

/// Accept (`true`, the `--force` flag) or refuse implausible values and oversized runs for the
/// rest of this process.
pub fn allow_implausible(allow: bool) {
    IMPLAUSIBLE_ALLOWED.store(allow, Ordering::Relaxed);
}

/// Whether `--force` was given.
pub fn implausible_allowed() -> bool {
    IMPLAUSIBLE_ALLOWED.load(Ordering::Relaxed)
}

/// Check every number of a parsed TOML tree: non-finite numbers are errors; a dimensioned
/// field ([`units::field_dimension`]) outside its plausible range ([`units::plausible_range`])
/// is an error unless `--force`. `prefix` is the dotted path of `table`.
fn check_numbers(
    path: &Path,
    text: &str,
    prefix: &str,
    table: &toml::Table,
) -> Result<(), InputError> {
    for (key, value) in table {
        let dotted = if prefix.is_empty() {
            key.clone()
        } else {
            format!("{prefix}.{key}")
        };
        let numbers: Vec<f64> = match value {
            toml::Value::Table(inner) => {
                check_numbers(path, text, &dotted, inner)?;
                continue;
            }
            toml::Value::Array(items) => {
                for item in items {
                    if let toml::Value::Table(inner) = item {
                        check_numbers(path, text, &dotted, inner)?;
                    }
                }
                items.iter().filter_map(toml::Value::as_float).collect()
            }
            toml::Value::Float(number) => vec![*number],
            toml::Value::Integer(number) => vec![*number as f64],
            _ => continue,
        };
        let error = |message: String| InputError::Field {
            path: path.into(),
            line: line_of_key(text, &dotted).or_else(|| line_of_key(text, key)),
            field: dotted.clone(),
            message,
        };
        let shown = |n: f64| {
            if (1e-3..1e6).contains(&n.abs()) {
                format!("{n}")
            } else {
                format!("{n:e}")
            }
        };
        if let Some(bad) = numbers.iter().find(|n| !n.is_finite()) {
            return Err(error(format!("{bad} is not a finite number")));
        }
        let Some(dimension) = units::field_dimension(key) else {
            continue;
        };
        let (least, most) = match units::plausible_range(dimension) {
            Some(range) if !implausible_allowed() => range,
            _ => continue,
        };
        if let Some(bad) = numbers
            .iter()
            .find(|n| **n != 0.0 && !(least..=most).contains(&n.abs()))
        {
            return Err(error(format!(
                "{} {} is outside the plausible range of {} ({least:e} to {most:e} {}): a \
                 unit slip? Give it with its unit (\"25.4 mm\", \"92 MPa\"; docs/formats.md), or \
                 pass --force to run it anyway",
                shown(*bad),
                dimension.si_unit(),
                dimension.name(),
                dimension.si_unit()
            )));
        }
    }
    Ok(())
}

/// Read a file to a string, naming it in the error.
pub fn read_text(path: &Path) -> Result<String, InputError> {
    if path.is_dir() {
        return Err(InputError::Io {
            path: path.into(),
            message: "is a folder, not a file".into(),
        });
    }
    let text = std::fs::read_to_string(path).map_err(|error| InputError::Io {
        path: path.into(),
        message: error.to_string(),
    })?;
    // A UTF-8 byte-order mark (spreadsheet exports write one) is not part of the text.
    Ok(match text.strip_prefix('\u{feff}') {
        Some(rest) => rest.to_string(),
        None => text,
    })
}

/// `text` as it is quoted in an error message: at most 40 characters, the rest elided (a
/// malformed cell may be a whole file's worth).
pub fn quoted(text: &str) -> String {
    const LONGEST: usize = 40;
    match text.char_indices().nth(LONGEST) {
        Some((cut, _)) => format!("{:?}... ({} bytes)", &text[..cut], text.len()),
        None => format!("{text:?}"),
    }
}

/// 1-based line of byte offset `offset` in `text`.
pub fn line_of(text: &str, offset: usize) -> usize {
    text[..offset.min(text.len())].matches('\n').count() + 1
}

/// 1-based line of the key at `path` in TOML `text`, from toml's own spans: `path` is the
/// keys from the root, with array entries by their 0-based index (`["models", "2",
/// "parameters", "yield_stress"]` is that key in the third `[[models]]`). For an array entry
/// that is the last element, the line where the entry starts. `None` if `text` does not parse
/// or has no such key.
pub fn line_of_path(text: &str, path: &[&str]) -> Option<usize> {
    use toml::de::{DeTable, DeValue};
    let root = DeTable::parse(text).ok()?;
    let mut table = root.get_ref();
    let mut segments = path.iter().peekable();
    while let Some(segment) = segments.next() {
        let (key, value) = table
            .iter()
            .find(|(k, _)| k.get_ref().as_ref() == *segment)?;
        if segments.peek().is_none() {
            return Some(line_of(text, key.span().start));
        }
        let mut value = value;
        // Array entries: the next segment is the index.
        while let DeValue::Array(items) = value.get_ref() {
            let index: usize = segments.next()?.parse().ok()?;
            value = items.get(index)?;
            if segments.peek().is_none() {
                return Some(line_of(text, value.span().start));
            }
        }
        match value.get_ref() {
            DeValue::Table(inner) => table = inner,
            _ => return None,
        }
    }
    None
}

/// 1-based line where `key = ...` is written (first match), if any. A dotted key
/// `table.leaf` not written as such is looked up as `leaf = ...` inside a `[table]` or
/// `[....table]` section.
pub fn line_of_key(text: &str, key: &str) -> Option<usize> {
    let assigns = |line: &str, key: &str| {
        line.trim_start()
            .strip_prefix(key)
            .is_some_and(|rest| rest.trim_start().starts_with('='))
    };
    if let Some(index) = text.lines().position(|line| assigns(line, key)) {
        return Some(index + 1);
    }
    let (table, leaf) = key.rsplit_once('.')?;
    let mut inside = false;
    for (index, line) in text.lines().enumerate() {
        // A table header may carry a comment after it (`[eos]  # table 5.2`).
        let trimmed = line.split('#').next().unwrap_or_default().trim();
        if let Some(header) = trimmed.strip_prefix('[') {
            let name = header.trim_end_matches(']').trim();
            inside = name == table || name.ends_with(&format!(".{table}"));
        } else if inside && assigns(line, leaf) {
            return Some(index + 1);
        }
    }
    None
}

/// For a message about a value (`invalid type: string "130 m/s"`, `invalid type: floating
/// point `-1.0``, `unknown variant `fast``): the key (and its 1-based line) of the first
/// `key = <value>` at or after line `from` (1-based) in `text`.
fn key_of_value(text: &str, message: &str, from: usize) -> Option<(String, usize)> {
    let value = match message.strip_prefix("invalid type: string \"") {
        Some(rest) => &rest[..rest.find('"')?],
        None => message.split('`').nth(1)?,
    };
    text.lines()
        .enumerate()
        .skip(from.saturating_sub(1))
        .find_map(|(index, line)| {
            let (key, rest) = line.split_once('=')?;
            let rest = rest.split('#').next().unwrap_or_default().trim();
            let unquoted = rest.trim_matches(['"', '\'']);
            (rest == value || unquoted == value).then(|| (key.trim().to_string(), index + 1))
        })
}

/// The quoted strings of one TOML line outside comments: `(byte range of the string with its
/// quotes, content)`; basic strings (`"..."`, with `\"` escapes) and literal strings (`'...'`).
fn quoted_strings(line: &str) -> Vec<(std::ops::Range<usize>, String)> {
    let bytes = line.as_bytes();
    let mut strings = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'#' => break,
            quote @ (b'"' | b'\'') => {
                let start = i;
                let mut content = String::new();
                i += 1;
                while i < bytes.len() && bytes[i] != quote {
                    if quote == b'"' && bytes[i] == b'\\' && i + 1 < bytes.len() {
                        i += 1;
                    }
                    let c = line[i..].chars().next().unwrap_or(' ');
                    content.push(c);
                    i += c.len_utf8();
                }
                if i >= bytes.len() {
                    break;
                }
                strings.push((start..i + 1, content));
            }
            _ => {}
        }
        i += 1;
    }
    strings
}

/// The key a value at byte `at` of `line` belongs to: the name before the last `=` before it
/// (`key = "..."`, `{ a = 1, key = "..." }`, `key = ["...", "..."]`).
fn key_before(line: &str, at: usize) -> Option<&str> {
    let before = &line[..at];
    let equals = before.rfind('=')?;
    let key = before[..equals]
        .rsplit(['{', ',', '['])
        .next()?
        .trim()
        .trim_matches('"');
    (!key.is_empty()).then_some(key)
}

/// `text` with every quoted quantity that carries a unit (`"25.4 mm"`, `["0.5 GPa", "2 GPa"]`)
/// replaced by its SI number, where the field's name gives a dimension
/// ([`units::field_dimension`]); every line stays where it was, so later errors keep their
/// line numbers. A unit of the wrong dimension or an unknown one is an error naming the line
/// and the field.
fn quantities_in_si<'t>(
    path: &Path,
    text: &'t str,
) -> Result<std::borrow::Cow<'t, str>, InputError> {
    if !text.contains('"') && !text.contains('\'') {
        return Ok(std::borrow::Cow::Borrowed(text));
    }
    let mut out = String::with_capacity(text.len());
    let mut changed = false;
    let mut in_multiline = false;
    for (index, line) in text.split_inclusive('\n').enumerate() {
        // Multi-line strings (`"""` or `'''`) are text, never quantities.
        let delimiters = line.matches("\"\"\"").count() + line.matches("'''").count();
        if in_multiline || delimiters > 0 {
            if delimiters % 2 == 1 {
                in_multiline = !in_multiline;
            }
            out.push_str(line);
            continue;
        }
        let mut rewritten = String::new();
        let mut last = 0;
        for (range, content) in quoted_strings(line) {
            let Some(key) = key_before(line, range.start) else {
                continue;
            };
            let Some(dimension) = units::field_dimension(key) else {
                continue;
            };
            match units::quantity_to_si(&content, dimension) {
                Ok(Some(value)) => {
                    rewritten.push_str(&line[last..range.start]);
                    rewritten.push_str(&format!("{value:?}"));
                    last = range.end;
                }
                Ok(None) => {}
                Err(message) => {
                    return Err(InputError::Field {
                        path: path.into(),
                        line: Some(index + 1),
                        field: key.into(),
                        message,
                    })
                }
            }
        }
        if last > 0 {
            changed = true;
            rewritten.push_str(&line[last..]);
            out.push_str(&rewritten);
        } else {
            out.push_str(line);
        }
    }
    Ok(if changed {
        std::borrow::Cow::Owned(out)
    } else {
        std::borrow::Cow::Borrowed(text)
    })
}

/// Parse TOML into `T`, turning serde/toml errors into [`InputError::Field`] with the line.
/// Quantities may be SI numbers or strings with a unit (`"25.4 mm"`, `"130 m/s"`, `"92 MPa"`),
/// converted to SI first ([`units`]).
pub fn parse_toml<T: DeserializeOwned>(path: &Path, text: &str) -> Result<T, InputError> {
    let document = parse_document(path, text)?;
    typed(path, &document.si)
}

/// A TOML file read once: its text with the quantities in SI ([`units`]) and its tree, whose
/// numbers are checked. Typed views of it ([`typed`]) parse the SI text again, for the line
/// numbers of their errors; everything else reads the tree.
pub struct Document<'a> {
    /// The text with every quantity in SI.
    pub si: std::borrow::Cow<'a, str>,
    /// Its tree.
    pub tree: toml::Table,
}

/// Read `text` (of `path`) once: quantities to SI, the tree, its numbers checked.
pub fn parse_document<'a>(path: &Path, text: &'a str) -> Result<Document<'a>, InputError> {
    let si = quantities_in_si(path, text)?;
    let tree: toml::Table = typed(path, &si)?;
    check_numbers(path, &si, "", &tree)?;
    Ok(Document { si, tree })
}

/// `T` from TOML text already in SI, its errors turned into [`InputError::Field`] with the
/// field and line.
pub fn typed<T: DeserializeOwned>(path: &Path, text: &str) -> Result<T, InputError> {
    toml::from_str(text).map_err(|error| {
        let message = error.message().to_string();
        // Name the field. toml puts a field's name in backticks only in "unknown field",
        // "missing field" and "duplicate field" messages; in "invalid type: floating point
        // `-1.0`" the backticks hold the value. Otherwise the field is the key written on the
        // error's line (`key = value`, or a table header `[a.b]`).
        let names_a_field = ["unknown field", "missing field", "duplicate field"]
            .iter()
            .any(|start| message.starts_with(start));
        let mut field = if names_a_field {
            message
                .split('`')
                .nth(1)
                .map(str::to_string)
                .unwrap_or_default()
        } else {
            String::new()
        };
        let mut line = error.span().map(|span| line_of(text, span.start));
        if field.is_empty() {
            let written = line
                .and_then(|n| text.lines().nth(n.saturating_sub(1)))
                .map(str::trim)
                .unwrap_or_default();
            if let Some(header) = written.strip_prefix('[') {
                // Reported at a table. A wrong value type inside a tagged table (an
                // experiment's [setup]) is reported there, not at its key: find the key whose
                // value is the quoted one (`invalid type: string "130 m/s"`).
                match key_of_value(text, &message, line.unwrap_or(1)) {
                    Some((key, key_line)) => {
                        field = key;
                        line = Some(key_line);
                    }
                    None => field = header.trim_matches(['[', ']']).trim().to_string(),
                }
            } else if let Some((key, _)) = written.split_once('=') {
                field = key.trim().trim_matches('"').to_string();
            } else if let Some((key, key_line)) = key_of_value(text, &message, 1) {
                field = key;
                line = Some(key_line);
            }
        }
        let line = line.or_else(|| line_of_key(text, &field));
        InputError::Field {
            path: path.into(),
            line,
            field,
            message,
        }
    })
}

//! Recordings (CSV): one measured point per line,
//!
//! ```text
//! # comments start with '#'
//! quantity,position,value,uncertainty
//! final_length,0,22.479e-3,0.05e-3
//! diameter,5.08e-3,8.32e-3,0.05e-3
//! ```
//!
//! `quantity` names what was measured (its meaning is set by the experiment kind), `position`
//! where or when (SI; 0 where it does not apply), `value` the measured value and
//! `uncertainty` its one-sigma uncertainty (SI).

use super::{read_text, InputError};
use std::path::Path;

/// One measured point.
#[derive(Clone, Debug, PartialEq)]
pub struct RecordedPoint {
    /// What was measured.
    pub quantity: String,
    /// Where or when (SI).
    pub position: f64,
    /// Measured value (SI).
    pub value: f64,
    /// One-sigma uncertainty (SI), > 0.
    pub uncertainty: f64,
}

/// The column names, in order.
pub const HEADER: [&str; 4] = ["quantity", "position", "value", "uncertainty"];

/// Parse recording CSV text.
pub fn parse(path: &Path, text: &str) -> Result<Vec<RecordedPoint>, InputError> {
    let mut points = Vec::new();
    let mut header_seen = false;
    for (index, raw) in text.lines().enumerate() {
        let line = raw.trim();
        let line_number = index + 1;
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let cells: Vec<&str> = line.split(',').map(str::trim).collect();
        let error = |field: &str, message: String| InputError::Field {
            path: path.into(),
            line: Some(line_number),
            field: field.into(),
            message,
        };
        if !header_seen {
            if cells != HEADER {
                return Err(error(
                    "",
                    format!("expected the header `{}`", HEADER.join(",")),
                ));
            }
            header_seen = true;
            continue;
        }
        if cells.len() != HEADER.len() {
            return Err(error(
                "",
                format!("{} cells, expected {}", cells.len(), HEADER.len()),
            ));
        }
        let number = |column: usize| -> Result<f64, InputError> {
            let value: f64 = cells[column].parse().map_err(|_| {
                error(
                    HEADER[column],
                    format!("{} is not a number", super::quoted(cells[column])),
                )
            })?;
            if value.is_finite() {
                Ok(value)
            } else {
                Err(error(HEADER[column], "must be finite".into()))
            }
        };
        if cells[0].is_empty() {
            return Err(error("quantity", "is empty".into()));
        }
        let uncertainty = number(3)?;
        if uncertainty <= 0.0 {
            return Err(error(
                "uncertainty",
                format!("must be > 0, got {uncertainty}"),
            ));
        }
        points.push(RecordedPoint {
            quantity: cells[0].into(),
            position: number(1)?,
            value: number(2)?,
            uncertainty,
        });
    }
    if points.is_empty() {
        return Err(InputError::Field {
            path: path.into(),
            line: None,
            field: String::new(),
            message: "the recording has no points".into(),
        });
    }
    Ok(points)
}

/// Load a recording file.
pub fn load(path: &Path) -> Result<Vec<RecordedPoint>, InputError> {
    parse(path, &read_text(path)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_cells_name_line_and_column() {
        // GOAL: CSV errors name file, line and column. REFERENCE: line 3, column `value`.
        let text =
            "quantity,position,value,uncertainty\nfinal_length,0,1e-3,1e-5\ndiameter,0,abc,1e-5\n";
        let error = parse(Path::new("r.csv"), text).unwrap_err().to_string();
        assert_eq!(error, "r.csv:3: field `value`: \"abc\" is not a number");
        let text = "quantity,position,value,uncertainty\nfinal_length,0,1e-3,0\n";
        let error = parse(Path::new("r.csv"), text).unwrap_err().to_string();
        assert!(error.starts_with("r.csv:2: field `uncertainty`"), "{error}");
    }

    #[test]
    fn a_byte_order_mark_is_dropped_and_a_huge_cell_is_not_echoed() {
        // GOAL: a spreadsheet's UTF-8 byte-order mark does not hide the header; a malformed
        //       cell of a megabyte is quoted by its first 40 characters and its size.
        // SETUP: a recording written with a BOM; a recording whose value cell is 1 MB of `x`.
        // REFERENCE: the points load; the message is shorter than 200 characters and names
        //   the line, the column and the size.
        let folder = std::env::temp_dir().join(format!("stoss-bom-{}", std::process::id()));
        std::fs::create_dir_all(&folder).unwrap();
        let path = folder.join("r.csv");
        std::fs::write(
            &path,
            "\u{feff}quantity,position,value,uncertainty\nfinal_length,0,1e-3,1e-5\n",
        )
        .unwrap();
        assert_eq!(load(&path).unwrap().len(), 1);
        let huge = "x".repeat(1 << 20);
        let text = format!("quantity,position,value,uncertainty\nq,0,{huge},1\n");
        let error = parse(Path::new("r.csv"), &text).unwrap_err().to_string();
        assert!(error.len() < 200, "{} characters", error.len());
        assert!(
            error.starts_with("r.csv:2: field `value`") && error.contains("1048576 bytes"),
            "{error}"
        );
        let _ = std::fs::remove_dir_all(&folder);
    }
}

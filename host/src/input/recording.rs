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
//!
//! A column header may carry a unit in brackets, and its column is then converted to SI on
//! load; an `uncertainty` without one is in the unit of `value`:
//!
//! ```text
//! quantity,position [%],value [MPa],uncertainty
//! true_stress,0.5,812,16
//! ```
//!
//! A unit of the wrong dimension for a row's quantity (a stress unit on a length, say) is an
//! error naming the line and the column (docs/formats.md lists every quantity's units).

use super::units::{self, Unit};
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

/// A header cell: its column name and unit (`value [MPa]` -> `("value", Some(MPa))`).
pub(crate) fn header_cell(cell: &str) -> Result<(&str, Option<Unit>), String> {
    let Some((name, rest)) = cell.split_once('[') else {
        return Ok((cell.trim(), None));
    };
    let symbol = rest
        .strip_suffix(']')
        .ok_or_else(|| format!("{} has no closing `]`", super::quoted(cell)))?
        .trim();
    let unit = units::unit(symbol).ok_or_else(|| {
        format!(
            "unknown unit {} in the header cell {}",
            super::quoted(symbol),
            super::quoted(cell)
        )
    })?;
    Ok((name.trim(), Some(unit)))
}

/// The 1-based line of the `index`-th (0-based) recorded point of the file at `path`: the
/// data rows after the header, skipping blank and `#` lines (for errors found after loading;
/// `None` if the file cannot be read again or has fewer points).
pub fn point_line(path: &Path, index: usize) -> Option<usize> {
    let text = std::fs::read_to_string(path).ok()?;
    text.lines()
        .enumerate()
        .filter(|(_, raw)| {
            let line = raw.trim();
            !line.is_empty() && !line.starts_with('#')
        })
        .nth(index + 1)
        .map(|(number, _)| number + 1)
}

/// Parse recording CSV text.
pub fn parse(path: &Path, text: &str) -> Result<Vec<RecordedPoint>, InputError> {
    let mut points = Vec::new();
    let mut header_seen = false;
    // Units of the position, value and uncertainty columns (None: SI).
    let mut column_units: [Option<Unit>; 3] = [None; 3];
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
            let parsed: Vec<(&str, Option<Unit>)> = cells
                .iter()
                .map(|cell| header_cell(cell))
                .collect::<Result<_, _>>()
                .map_err(|message| error("", message))?;
            let names: Vec<&str> = parsed.iter().map(|(name, _)| *name).collect();
            if names != HEADER {
                return Err(error(
                    "",
                    format!(
                        "expected the header `{}` (a column may carry a unit: `value [MPa]`)",
                        HEADER.join(",")
                    ),
                ));
            }
            if parsed[0].1.is_some() {
                return Err(error(
                    "quantity",
                    "the quantity column takes no unit".into(),
                ));
            }
            column_units = [parsed[1].1, parsed[2].1, parsed[3].1.or(parsed[2].1)];
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
        let (mut position, mut value, mut uncertainty) = (number(1)?, number(2)?, uncertainty);
        let dimensions = units::recorded_dimensions(cells[0]);
        for (column, unit) in column_units.iter().enumerate() {
            let Some(unit) = unit else { continue };
            if let Some((position_dimension, value_dimension)) = dimensions {
                // A position of 0 means "does not apply", whatever its column's unit.
                let expected = if column == 0 {
                    (position != 0.0).then_some(position_dimension)
                } else {
                    Some(value_dimension)
                };
                if let Some(expected) = expected.filter(|e| *e != unit.dimension) {
                    return Err(error(
                        HEADER[column + 1],
                        format!(
                            "the column's unit is {}, but the {} of {} is {} ({})",
                            unit.dimension.name(),
                            if column == 0 { "position" } else { "value" },
                            cells[0],
                            expected.name(),
                            units::symbols_of(expected).join(", ")
                        ),
                    ));
                }
            }
            // The cell was checked to be a finite number above.
            let cell = cells[column + 1];
            let converted = if column == 2 {
                unit.parse_difference_to_si(cell)
            } else {
                unit.parse_to_si(cell)
            };
            let converted = converted.filter(|v| v.is_finite()).ok_or_else(|| {
                error(
                    HEADER[column + 1],
                    format!("{} is out of range in SI", super::quoted(cell)),
                )
            })?;
            match column {
                0 => position = converted,
                1 => value = converted,
                _ => uncertainty = converted,
            }
        }
        points.push(RecordedPoint {
            quantity: cells[0].into(),
            position,
            value,
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
    fn units_in_the_header_give_the_same_points_as_si() {
        // GOAL: a recording in MPa and % gives the points of the same recording in Pa and
        //   plain strain, bit for bit (issue 17). SETUP: two flow-curve points and a Taylor
        //   length in mm, the uncertainty inheriting the value's unit.
        // REFERENCE: the SI file.
        let si = "quantity,position,value,uncertainty\ntrue_stress,0.005,812e6,16e6\n\
                  true_stress,0.125,1.05e9,2e7\n";
        let units = "quantity,position [%],value [MPa],uncertainty\ntrue_stress,0.5,812,16\n\
                     true_stress,12.5,1050,20\n";
        assert_eq!(
            parse(Path::new("a.csv"), si).unwrap(),
            parse(Path::new("b.csv"), units).unwrap()
        );
        let taylor =
            "quantity,position [mm],value [mm],uncertainty [um]\nfinal_length,0,22.48,50\n";
        let point = &parse(Path::new("t.csv"), taylor).unwrap()[0];
        assert_eq!(
            (point.position, point.value, point.uncertainty),
            (0.0, 22.48e-3, 50e-6)
        );
    }

    #[test]
    fn a_unit_of_the_wrong_dimension_names_line_and_column() {
        // GOAL: a stress unit on a length, an unknown unit and a unit on the quantity column
        //   are errors naming the line and the column. SETUP: three such headers.
        // REFERENCE: the messages.
        let text = "quantity,position,value [MPa],uncertainty\nfinal_length,0,22.48,0.05\n";
        let error = parse(Path::new("r.csv"), text).unwrap_err().to_string();
        assert!(error.starts_with("r.csv:2: field `value`"), "{error}");
        assert!(
            error.contains("a stress") && error.contains("a length"),
            "{error}"
        );
        let text = "quantity,position,value [furlong],uncertainty\nfinal_length,0,1,1\n";
        let error = parse(Path::new("r.csv"), text).unwrap_err().to_string();
        assert!(
            error.starts_with("r.csv:1:") && error.contains("unknown unit"),
            "{error}"
        );
        let text = "quantity [m],position,value,uncertainty\nfinal_length,0,1,1\n";
        let error = parse(Path::new("r.csv"), text).unwrap_err().to_string();
        assert!(error.contains("takes no unit"), "{error}");
    }

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

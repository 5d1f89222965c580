//! Golden histories, compared bit for bit. CI runs this in debug and in release: both must
//! produce the same bits (no FMA contraction, libm everywhere).

use std::path::PathBuf;
use stoss::verify::golden::{cases, compare, compare_grouped, parse, render};

fn golden_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/golden")
}

#[test]
fn every_golden_history_is_bit_identical() {
    // GOAL: detect any change of the kernel's arithmetic.
    // SETUP: every reference material through every single-element driver.
    // REFERENCE: fixtures/golden/*.golden (regenerate with `stoss verify --bless`).
    let all = cases();
    assert_eq!(all.len(), 69);
    let mut errors = Vec::new();
    for case in &all {
        if let Err(error) = compare(&golden_dir(), case) {
            errors.push(error.to_string());
        }
    }
    assert!(errors.is_empty(), "{}", errors.join("\n"));
}

#[test]
fn every_golden_history_is_bit_identical_through_the_group_update() {
    // GOAL: the group update (`PointModel::update_lanes`, the VUMAT's and the C ABI batch's
    //       path) gives every golden history's bits, whatever its lane-mates do.
    // SETUP: every golden case, each step taken in the first lane of a group whose lane-mates
    //        start from the same state with other increments: half, reversed, doubled, nearly
    //        equal, a hold, a NaN, a negative time step (`verify::golden::Grouped`).
    // REFERENCE: fixtures/golden/*.golden, the files the one-point update is checked against.
    let mut failures = Vec::new();
    for case in cases() {
        if let Err(error) = compare_grouped(&golden_dir(), &case) {
            failures.push(error.to_string());
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn a_flipped_bit_is_detected() {
    // GOAL: the comparison really compares bits (a test that cannot fail is a defect).
    // SETUP: flip the lowest bit of one stored stress value and compare.
    // REFERENCE: a Mismatch error naming the line and column.
    let case = cases()[0];
    let records = case.driver.run(&case.model).unwrap();
    let text = render(&case, &records);
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let mut words: Vec<String> = lines[10].split(' ').map(String::from).collect();
    let bits = u64::from_str_radix(&words[7], 16).unwrap() ^ 1;
    words[7] = format!("{bits:016x}");
    lines[10] = words.join(" ");
    let directory = std::env::temp_dir().join(format!("stoss-golden-{}", std::process::id()));
    std::fs::create_dir_all(&directory).unwrap();
    std::fs::write(directory.join(case.file_name()), lines.join("\n")).unwrap();
    let error = compare(&directory, &case).unwrap_err().to_string();
    std::fs::remove_dir_all(&directory).unwrap();
    assert!(error.contains(":11: column stress_xx"), "{error}");
}

#[test]
fn a_malformed_golden_file_names_file_and_line() {
    // GOAL: bad input gets an error naming the file and line.
    // SETUP: a golden text with a non-hex word on line 3.
    // REFERENCE: Parse error at line 3.
    let path = PathBuf::from("broken.golden");
    let text = "# stoss golden history v1\n# x\nzz 00\n";
    let error = parse(&path, text).unwrap_err().to_string();
    assert!(error.starts_with("broken.golden:3:"), "{error}");
}

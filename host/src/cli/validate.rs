//! `stoss validate`: re-run the headline figures of the documents and compare each with the
//! value it is quoted at ([`crate::validate`]).

use super::output::say;
use crate::validate::{self, Speed, Validation, ROWS};
use clap::Args;
use std::path::PathBuf;
use std::process::ExitCode;

/// Arguments of `stoss validate`.
#[derive(Debug, Args)]
pub struct ValidateArgs {
    /// Rows to run, by name (all if none; `--list` shows them).
    pub rows: Vec<String>,
    /// Only the fast rows (seconds to a minute each; what CI runs).
    #[arg(long, conflicts_with = "full")]
    pub fast: bool,
    /// Also the full rows (whole campaigns, an hour or more each), which are otherwise run
    /// only when named.
    #[arg(long)]
    pub full: bool,
    /// List the rows (name, speed, figure, where it is quoted, stated value) and stop.
    #[arg(long)]
    pub list: bool,
    /// The fixtures folder the rows' experiments are read from.
    #[arg(long, default_value = "fixtures")]
    pub fixtures: PathBuf,
    /// Worker threads per simulation (results do not depend on it).
    #[arg(long)]
    pub threads: Option<usize>,
}

/// Run `stoss validate`.
pub fn run(args: &ValidateArgs) -> ExitCode {
    let unknown: Vec<&String> = args
        .rows
        .iter()
        .filter(|name| !ROWS.iter().any(|row| row.name == name.as_str()))
        .collect();
    if !unknown.is_empty() {
        let known: Vec<&str> = ROWS.iter().map(|row| row.name).collect();
        eprintln!(
            "error: unknown row(s) {}; the rows are: {}",
            unknown
                .iter()
                .map(|n| format!("`{n}`"))
                .collect::<Vec<_>>()
                .join(", "),
            known.join(", ")
        );
        return ExitCode::FAILURE;
    }
    let most = crate::solver::explicit::MAXIMUM_THREADS;
    if let Some(threads) = args.threads {
        if !(1..=most).contains(&threads) {
            eprintln!("error: --threads must be in 1..={most}, got {threads}");
            return ExitCode::FAILURE;
        }
    }
    if !args.fixtures.is_dir() {
        eprintln!(
            "error: {}: the fixtures folder does not exist (give --fixtures)",
            args.fixtures.display()
        );
        return ExitCode::FAILURE;
    }
    let selected: Vec<_> = ROWS
        .iter()
        .filter(|row| args.rows.is_empty() || args.rows.iter().any(|n| n == row.name))
        .filter(|row| !args.fast || row.speed == Speed::Fast)
        .filter(|row| {
            args.full || row.speed != Speed::Full || args.rows.iter().any(|n| n == row.name)
        })
        .collect();
    if args.list {
        for row in &selected {
            say!(
                "{:<29} {:<5} {} = {} {} (+-{}) [{}]",
                row.name,
                match row.speed {
                    Speed::Fast => "fast",
                    Speed::Slow => "slow",
                    Speed::Full => "full",
                },
                row.figure,
                row.stated,
                row.unit,
                row.tolerance,
                row.quoted_in
            );
        }
        return ExitCode::SUCCESS;
    }
    say!(
        "{:<29} {:>12} {:>12} {:>10} {:<11} {:>8}  figure",
        "row",
        "stated",
        "measured",
        "tolerance",
        "unit",
        "wall s"
    );
    let mut results: Vec<Validation> = Vec::new();
    for row in selected {
        let result = validate::validate(row, &args.fixtures, args.threads);
        let measured = match &result.measured {
            Ok(value) => format!("{value:>12.4}"),
            Err(_) => format!("{:>12}", "error"),
        };
        say!(
            "{:<29} {:>12.4} {measured} {:>10} {:<11} {:>8.1}  {} {}",
            row.name,
            row.stated,
            row.tolerance,
            row.unit,
            result.seconds,
            if result.passed() { "pass" } else { "FAIL" },
            row.figure
        );
        if let Err(reason) = &result.measured {
            say!("{:<29} error: {reason}", "");
        }
        results.push(result);
    }
    let failed = results.iter().filter(|r| !r.passed()).count();
    let foi_tables = validate::predicted_foi_tables();
    for ((experiment, core, core_mesh), prediction) in &foi_tables {
        say!(
            "\n{experiment}, core {:.3} x {:.3} mm, nose {:.3} mm, core mesh {}: shots (impact, exit m/s) {}",
            core.length * 1e3,
            core.diameter * 1e3,
            core.nose_length * 1e3,
            core_mesh.map_or("as the file".to_string(), |size| format!("{:.2} mm", size * 1e3)),
            prediction
                .shots
                .iter()
                .map(|(impact, exit)| format!("{impact:.1} {exit:.1}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    super::output::json(&serde_json::json!({
        "command": "validate",
        "rows": results
            .iter()
            .map(|r| serde_json::json!({
                "row": r.row.name,
                "figure": r.row.figure,
                "stated": r.row.stated,
                "tolerance": r.row.tolerance,
                "unit": r.row.unit,
                "measured": r.measured.as_ref().ok(),
                "error": r.measured.as_ref().err(),
                "passed": r.passed(),
                "seconds": r.seconds,
            }))
            .collect::<Vec<_>>(),
        "passed": results.len() - failed,
        "failed": failed,
        "foi_tables": foi_tables
            .iter()
            .map(|((experiment, core, core_mesh), prediction)| serde_json::json!({
                "experiment": experiment,
                "core_length": core.length,
                "core_diameter": core.diameter,
                "nose_length": core.nose_length,
                "core_element_size": core_mesh,
                "shots": prediction.shots,
            }))
            .collect::<Vec<_>>(),
    }));
    say!(
        "\n{} row(s): {} pass, {failed} fail",
        results.len(),
        results.len() - failed
    );
    if failed > 0 {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}

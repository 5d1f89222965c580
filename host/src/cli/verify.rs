//! `stoss verify`: print the check table; compare (or, with `--bless`, rewrite) the golden
//! histories.

use super::output::say;
use crate::verify::{self, golden};
use clap::Args;
use std::path::PathBuf;
use std::process::ExitCode;

/// Arguments of `stoss verify`.
#[derive(Debug, Args)]
pub struct VerifyArgs {
    /// Rewrite the golden histories from the current kernel instead of comparing them. Commit
    /// the result with a message that says why the bits changed.
    #[arg(long)]
    pub bless: bool,
    /// Directory of the golden histories.
    #[arg(long, default_value = "fixtures/golden")]
    pub golden_dir: PathBuf,
}

/// Run `stoss verify`.
pub fn run(args: &VerifyArgs) -> ExitCode {
    let rows = verify::run_all();
    say!(
        "{:<26} {:<38} {:<50} {:>11} {:>11}  result",
        "material",
        "check",
        "quantity",
        "max error",
        "tolerance"
    );
    let mut failures = 0;
    for row in &rows {
        let relation = match row.expectation {
            verify::Expectation::AtMost => "<=",
            verify::Expectation::AtLeast => ">=",
        };
        let verdict = if row.passed() { "pass" } else { "FAIL" };
        if !row.passed() {
            failures += 1;
        }
        say!(
            "{:<26} {:<38} {:<50} {:>11.3e} {relation}{:>9.1e}  {verdict}",
            row.subject,
            row.check,
            row.quantity,
            row.max_error,
            row.tolerance
        );
    }
    say!();
    say!("seed 001 sec. 3.4.1 tension check, 4340 JC (A 792 MPa, B 510 MPa, n 0.26, C 0.014), true strain 0.2:");
    say!(
        "{:>8} {:>8} {:>16} {:>16} {:>16}",
        "rate/s",
        "eps_p",
        "JC analytical",
        "implicit (3.8)",
        "lagged (3.7)"
    );
    for row in verify::checks::seed001_table() {
        say!(
            "{:>8} {:>8.4} {:>12.1} MPa {:>12.1} MPa {:>12.1} MPa",
            row.rate,
            row.plastic_strain,
            row.analytical / 1e6,
            row.implicit / 1e6,
            row.lagged / 1e6
        );
    }
    say!();
    say!(
        "RHT HPC 92 MPa (seed 001 table 4.4), uniaxial compression peak / fc; F = (rate/30e-6)^0.01 (eq. 4.4),"
    );
    say!("expected DIF = root z of eq. 4.1 on the uniaxial path, z = F A (z/3 - p*_0 F)^N:");
    say!(
        "{:>8} {:>10} {:>12} {:>12}",
        "rate/s",
        "F",
        "eq. 4.1 z",
        "driver DIF"
    );
    for row in verify::rht_checks::dif_table() {
        say!(
            "{:>8} {:>10.4} {:>12.4} {:>12.4}",
            row.rate,
            row.rate_factor,
            row.surface,
            row.measured
        );
    }
    say!();
    if args.bless {
        match golden::bless(&args.golden_dir) {
            Ok(count) => say!(
                "blessed {count} golden histories in {}",
                args.golden_dir.display()
            ),
            Err(error) => {
                eprintln!("error: {error}");
                return ExitCode::FAILURE;
            }
        }
    } else if !args.golden_dir.is_dir() {
        // Not a failed comparison: there is nothing to compare with.
        eprintln!(
            "error: golden folder {} not found: run `stoss verify` from the repository's root, \
             or give the folder with --golden-dir",
            args.golden_dir.display()
        );
        say!("{} closed-form checks, {} failed", rows.len(), failures);
        return ExitCode::FAILURE;
    } else {
        let cases = golden::cases();
        let mut golden_failures = 0;
        for case in &cases {
            if let Err(error) = golden::compare(&args.golden_dir, case) {
                golden_failures += 1;
                eprintln!("golden: {error}");
            }
        }
        say!(
            "golden histories: {} of {} bit-identical ({})",
            cases.len() - golden_failures,
            cases.len(),
            args.golden_dir.display()
        );
        failures += golden_failures;
    }
    say!("{} checks, {} failed", rows.len(), failures);
    super::output::json(&serde_json::json!({
        "command": "verify",
        "checks": rows.len(),
        "failed": failures,
    }));
    if failures == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}

//! Every kernel check of `stoss verify` as a test: closed forms, the seed 001 tension check
//! (implicit agrees, lagged shows the defect), tangent by finite differences, heating, failure.

use std::sync::OnceLock;
use stoss::verify::{run_all, CheckResult, Expectation};

/// The table, computed once for all tests of this file (the RHT rows drive the concrete model
/// through thousands of steps; in the debug profile that is worth sharing).
fn table() -> &'static [CheckResult] {
    static ROWS: OnceLock<Vec<CheckResult>> = OnceLock::new();
    ROWS.get_or_init(run_all)
}

#[test]
fn every_closed_form_and_published_check_passes() {
    // GOAL: the kernel reproduces each closed form / published number within its tolerance.
    // SETUP: the reference materials (JC 4340, JC lagged, JC+failure, ZA BCC/FCC, MJC, TJC)
    //        through every single-element driver; every EoS; RHT concrete (HPC 92 MPa).
    // REFERENCE: closed forms listed per row (see stoss::verify::checks, eos_checks,
    //        rht_checks); seed 001 sec. 3.4.1; Rankine-Hugoniot; Dobratz & Crawford (1985)
    //        C-4 CJ state; seed 001 table 5.2; seed 001 eqs. 4.1-4.11.
    let rows = table();
    assert!(
        rows.len() > 80,
        "expected the full table, got {} rows",
        rows.len()
    );
    let failed: Vec<String> = rows
        .iter()
        .filter(|row| !row.passed())
        .map(|row| {
            format!(
                "{} / {} / {}: {:e} vs {:e}",
                row.subject, row.check, row.quantity, row.max_error, row.tolerance
            )
        })
        .collect();
    assert!(failed.is_empty(), "failed checks:\n{}", failed.join("\n"));
}

#[test]
fn lagged_rate_is_insensitive_to_rate_and_implicit_is_not() {
    // GOAL: reproduce seed 001 fig. 3.6 vs 3.7: lagged (eq. 3.7) flow stress stays on the
    //       1 /s curve, implicit (eq. 3.8) rises with rate as JC predicts.
    // SETUP: 4340 JC, uniaxial tension to 0.2, strain step 2e-5, 1 and 1000 /s.
    // REFERENCE: JC rate factor at 1000 /s = 1 + 0.014 ln 1000 = 1.0967.
    use stoss::verify::checks::seed001_tension;
    use stoss_kernel::RateTreatment;
    let (_, implicit_1) = seed001_tension(RateTreatment::Implicit, 1.0);
    let (_, implicit_1000) = seed001_tension(RateTreatment::Implicit, 1000.0);
    let (_, lagged_1) = seed001_tension(RateTreatment::Lagged, 1.0);
    let (_, lagged_1000) = seed001_tension(RateTreatment::Lagged, 1000.0);
    let expected_factor = 1.0 + 0.014 * 1000.0_f64.ln();
    assert!(((implicit_1000 / implicit_1) / expected_factor - 1.0).abs() < 1e-3);
    assert!(
        (lagged_1000 / lagged_1 - 1.0).abs() < 1e-3,
        "lagged must be rate-insensitive"
    );
}

#[test]
fn the_table_contains_a_defect_demonstration() {
    // GOAL: the lagged-rate rows are there and are demonstrations (error must be large).
    // SETUP/REFERENCE: row expectations.
    let rows = table();
    assert!(rows
        .iter()
        .any(|row| row.expectation == Expectation::AtLeast && row.passed()));
}

#[test]
fn every_equation_of_state_and_the_rht_model_are_in_the_table() {
    // GOAL: GitHub issue 3, "done when": the verification table lists every EoS and the RHT
    //       model with their checks.
    // SETUP: the subjects of the table's rows.
    // REFERENCE: the EoS variants of stoss_kernel::eos::Eos (linear, Mie-Grueneisen,
    //       polynomial, JWL, tabulated compaction, P-alpha) and RHT concrete; the RHT rows
    //       cover the uniaxial compression/tension peaks, the DIF at 1-1000 /s, uniaxial
    //       strain, the Lode factor and hydrostatic loading.
    let rows = table();
    let count = |prefix: &str| {
        rows.iter()
            .filter(|row| row.subject.starts_with(prefix))
            .count()
    };
    for (prefix, at_least) in [
        ("eos-linear", 1),
        ("eos-gruneisen-copper", 2),
        ("eos-gruneisen-4340", 2),
        ("eos-polynomial", 2),
        ("eos-jwl-c4", 3),
        ("eos-table-5-2", 3),
        ("eos-p-alpha", 5),
        ("rht-hpc-92", 11),
    ] {
        assert!(
            count(prefix) >= at_least,
            "{prefix}: {} rows, expected at least {at_least}",
            count(prefix)
        );
    }
    let rht_checks: Vec<&str> = rows
        .iter()
        .filter(|row| row.subject == "rht-hpc-92")
        .map(|row| row.check.as_str())
        .collect();
    for needle in [
        "uniaxial compression 1e-6/s",
        "uniaxial compression 1/s, DIF",
        "uniaxial compression 10/s, DIF",
        "uniaxial compression 100/s, DIF",
        "uniaxial compression 1000/s, DIF",
        "uniaxial tension",
        "uniaxial strain",
        "R3 on the compressive meridian",
        "R3 on the tensile meridian",
        "hydrostatic",
    ] {
        assert!(
            rht_checks.iter().any(|check| check.starts_with(needle)),
            "no RHT row for {needle}"
        );
    }
}

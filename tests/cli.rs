//! End-to-end tests of the `stoss` binary.

use std::process::Command;

fn stoss() -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_stoss"));
    command.current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."));
    command
}

#[test]
fn verify_prints_the_table_and_succeeds() {
    // GOAL: `stoss verify` (the README's command) runs on a fresh clone and passes.
    // SETUP: run from the workspace root with the bundled golden files.
    // REFERENCE: exit 0, a table with every model, all goldens bit-identical.
    let output = stoss().arg("verify").output().unwrap();
    let text = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{text}\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    for model in [
        "jc-4340",
        "za-bcc-armco",
        "za-fcc-copper",
        "mjc-hha",
        "tjc-hha",
        "ptw-tantalum",
        "khl-illustrative",
        "vk-illustrative",
        "mts-copper",
        "rht-hpc-92",
        "kc-hpc-100",
    ] {
        assert!(text.contains(model), "missing {model}");
    }
    assert!(text.contains("golden histories: 69 of 69 bit-identical"));
}

#[test]
fn verify_fails_with_a_clear_error_on_a_missing_golden_directory() {
    // GOAL: bad input gives a non-zero exit and names the file.
    // SETUP: point --golden-dir at a folder that does not exist.
    // REFERENCE: exit code 1, stderr names the missing folder (not 45 failed comparisons).
    let output = stoss()
        .args(["verify", "--golden-dir", "does/not/exist"])
        .output()
        .unwrap();
    assert!(!output.status.success());
    let errors = String::from_utf8_lossy(&output.stderr);
    assert!(
        errors.contains("golden folder does/not/exist not found"),
        "{errors}"
    );
}

#[test]
fn simulate_refuses_a_result_without_finite_predictions() {
    // GOAL: a simulation whose predictions are not numbers is an error, not a result.
    // SETUP: the 570 /s 4340 tension flow curve with yield_stress = 1e20 (a unit slip: the
    //        curve never yields, so no recorded plastic strain is reached), run with --force
    //        past the plausibility check that refuses it otherwise.
    // REFERENCE: non-zero exit; stderr names the experiment file and the first missing point;
    //        no output folder.
    let directory = std::env::temp_dir().join(format!("stoss-nan-{}", std::process::id()));
    std::fs::create_dir_all(&directory).unwrap();
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
    let text = std::fs::read_to_string(format!("{root}/fixtures/materials/4340-jc.toml")).unwrap();
    let bad: String = text
        .lines()
        .map(|l| {
            if l.starts_with("yield_stress") {
                "yield_stress = 1e20".to_string()
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    assert_ne!(bad, text);
    let material = directory.join("unit-slip.toml");
    std::fs::write(&material, bad).unwrap();
    let output = directory.join("out");
    let simulate = |force: bool| {
        let mut command = stoss();
        command
            .args([
                "simulate",
                "fixtures/experiments/flow-4340-jc-tension-570s-298K.toml",
            ])
            .arg("--material")
            .arg(&material)
            .arg("--output")
            .arg(&output);
        if force {
            command.arg("--force");
        }
        command.output().unwrap()
    };
    // Refused on load as implausible (a unit slip), naming the line and the field.
    let result = simulate(false);
    let errors = String::from_utf8_lossy(&result.stderr);
    assert!(!result.status.success());
    assert!(
        errors.contains("unit-slip.toml:") && errors.contains("field `strength.yield_stress`"),
        "{errors}"
    );
    // With --force it runs, and its NaN predictions are refused.
    let result = simulate(true);
    let errors = String::from_utf8_lossy(&result.stderr);
    assert!(!result.status.success(), "{errors}");
    assert!(
        errors.contains("flow-4340-jc-tension-570s-298K.toml")
            && errors.contains("no finite prediction")
            && errors.contains("true_stress at position"),
        "{errors}"
    );
    assert!(!output.exists());
    std::fs::remove_dir_all(&directory).unwrap();
}

#[test]
fn simulate_writes_outputs_and_reports_energy() {
    // GOAL: `stoss simulate` runs an experiment from a fresh clone and writes its outputs.
    // SETUP: the seed 001 tension cylinder at 1000 /s, output into a temporary folder.
    // REFERENCE: exit 0; the energy balance and the comparison table printed; measurements,
    //   states, energy and VTK files written; every summary.json value with its unit.
    let output = std::env::temp_dir().join(format!("stoss-sim-{}", std::process::id()));
    let result = stoss()
        .args([
            "simulate",
            "fixtures/experiments/tension-4340-1000.toml",
            "--output",
        ])
        .arg(&output)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&result.stdout);
    assert!(
        result.status.success(),
        "{text}{}",
        String::from_utf8_lossy(&result.stderr)
    );
    assert!(text.contains("energy error"));
    assert!(text.contains("axial_stress"));
    for file in [
        "measurements.csv",
        "states.csv",
        "energy.txt",
        "summary.json",
        "final.vtu",
    ] {
        assert!(output.join(file).is_file(), "missing {file}");
    }
    // Issue 51 item 4: summary.json says the unit of every value.
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(output.join("summary.json")).unwrap())
            .unwrap();
    let entries = summary.as_object().unwrap();
    assert!(!entries.is_empty());
    for (name, entry) in entries {
        assert!(
            entry["value"].is_number() && entry["unit"].is_string(),
            "{name}: {entry}"
        );
    }
    assert_eq!(summary["final_axial_stress"]["unit"], "Pa", "{summary}");
    std::fs::remove_dir_all(&output).unwrap();
}

#[test]
fn simulate_rejects_a_bad_experiment_without_writing_anything() {
    // GOAL: bad input gives file:line:field, a non-zero exit and no partial output.
    // SETUP: a copy of the 208 m/s Taylor file with a negative velocity.
    // REFERENCE: exit 1, the message names the file, line 12 and `velocity`; no output folder.
    let folder = std::env::temp_dir().join(format!("stoss-bad-{}", std::process::id()));
    std::fs::create_dir_all(&folder).unwrap();
    let source = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../fixtures/experiments/taylor-4340-208.toml"
    ))
    .unwrap();
    let bad = source.replace("velocity = 208.0", "velocity = -208.0");
    let line = bad.lines().position(|l| l.starts_with("velocity")).unwrap() + 1;
    let path = folder.join("bad.toml");
    std::fs::write(&path, bad).unwrap();
    let output = folder.join("out");
    let result = stoss()
        .arg("simulate")
        .arg(&path)
        .arg("--output")
        .arg(&output)
        .output()
        .unwrap();
    assert!(!result.status.success());
    let errors = String::from_utf8_lossy(&result.stderr);
    assert!(
        errors.contains(&format!("bad.toml:{line}: field `velocity`")),
        "{errors}"
    );
    assert!(!output.exists());
    std::fs::remove_dir_all(&folder).unwrap();
}

#[test]
fn diagnose_refuses_a_runaway_parallel_before_reading_anything() {
    // GOAL: `stoss diagnose --parallel 100000` is refused at once (issue 17: a runaway
    //       `parallel` spawned 1533 threads), before the calibration folder is read.
    // SETUP: a calibration folder that does not exist.
    // REFERENCE: non-zero exit; the message names `--parallel` and its range.
    let output = stoss()
        .args(["diagnose", "no-such-calibration", "--parallel", "100000"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(
        stderr.contains("--threads must be in 1..=256") && stderr.contains("100000"),
        "{stderr}"
    );
}

#[test]
fn verify_outside_the_repository_says_the_golden_folder_is_missing() {
    // GOAL: `stoss verify` run elsewhere names the missing golden folder instead of reporting
    //       45 failed comparisons (issue 17). SETUP: an empty temporary working directory.
    // REFERENCE: non-zero exit; stderr names the folder and --golden-dir; no "45 failed".
    let directory = std::env::temp_dir().join(format!("stoss-verify-{}", std::process::id()));
    std::fs::create_dir_all(&directory).unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_stoss"))
        .arg("verify")
        .current_dir(&directory)
        .output()
        .unwrap();
    let errors = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(
        errors.contains("golden folder fixtures/golden not found")
            && errors.contains("--golden-dir"),
        "{errors}"
    );
    assert!(!String::from_utf8_lossy(&output.stdout).contains("45 failed"));
    std::fs::remove_dir_all(&directory).unwrap();
}

#[test]
fn fit_jc_fits_the_bundled_tension_curves_and_refuses_other_kinds_without_output() {
    // GOAL: `stoss fit-jc` (seed 001 sec. 3.2 direct fit) runs on real flow curves and writes
    //       a material file that stoss reads; bad input writes nothing and says why.
    // SETUP: the four bundled Johnson & Cook (1985) 4340 tension curves; then a Taylor test
    //        given as a flow curve.
    // REFERENCE: exit 0, the constants printed, the written file loads as a material with
    //            the fitted C within 20 % of Johnson and Cook's 0.014 (docs/calibration.md);
    //            exit 1 naming the file for the Taylor test, and no output file.
    let dir = std::env::temp_dir().join(format!("stoss-fit-jc-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let written = dir.join("jc.toml");
    let curves = [
        "fixtures/experiments/flow-4340-jc-tension-0.002s-298K.toml",
        "fixtures/experiments/flow-4340-jc-tension-570s-298K.toml",
        "fixtures/experiments/flow-4340-jc-tension-604s-500K.toml",
        "fixtures/experiments/flow-4340-jc-tension-650s-735K.toml",
    ];
    let output = stoss()
        .arg("fit-jc")
        .args(curves)
        .arg("--output")
        .arg(&written)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{text}");
    assert!(
        text.contains("C from: 4340 flow curve, tension 570.0 /s, 298 K"),
        "{text}"
    );
    let material = std::fs::read_to_string(&written).unwrap();
    let rate_sensitivity: f64 = material
        .lines()
        .find_map(|l| l.strip_prefix("rate_sensitivity = "))
        .unwrap()
        .parse()
        .unwrap();
    assert!((rate_sensitivity / 0.014 - 1.0).abs() < 0.2, "{material}");
    let refused = dir.join("refused.toml");
    let output = stoss()
        .arg("fit-jc")
        .arg("fixtures/experiments/taylor-4340-208.toml")
        .arg("--output")
        .arg(&refused)
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(1));
    let error = String::from_utf8_lossy(&output.stderr);
    assert!(error.contains("taylor-4340-208.toml"), "{error}");
    assert!(!refused.exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn validate_runs_its_analytic_rows_and_refuses_unknown_rows_by_name() {
    // GOAL: `stoss validate` compares a quoted figure with a fresh measurement and says pass
    //       or fail; an unknown row is a clear error listing the rows; every row's experiment
    //       exists and loads (the simulation rows themselves run in `.ci/run`, in release).
    // SETUP: the two analytic rows (FOI tables 3.4 and 3.5) by name; a misspelt row; the
    //        rows' experiments loaded through the library.
    // REFERENCE: seed 001 sec. 3.5: 754 and 688 m/s, quoted within 2 m/s.
    let output = stoss()
        .args(["validate", "foi-t34-limit", "foi-t35-limit"])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{text}");
    assert!(text.contains("2 row(s): 2 pass, 0 fail"), "{text}");
    let bad = stoss().args(["validate", "foi-t34-limt"]).output().unwrap();
    let error = String::from_utf8_lossy(&bad.stderr);
    assert!(!bad.status.success());
    assert!(
        error.contains("unknown row(s) `foi-t34-limt`") && error.contains("euler-1250"),
        "{error}"
    );
    let fixtures = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../fixtures"));
    for row in stoss::validate::ROWS {
        match row.measure {
            stoss::validate::Measure::Summary { experiment, .. }
            | stoss::validate::Measure::Predicted { experiment, .. }
            | stoss::validate::Measure::LambertJonas { experiment }
            | stoss::validate::Measure::FoiCore { experiment, .. }
            | stoss::validate::Measure::FoiCoreMesh { experiment, .. }
            | stoss::validate::Measure::BlastLoad { experiment, .. } => {
                stoss::experiment::Experiment::load(&fixtures.join(experiment))
                    .unwrap_or_else(|e| panic!("{}: {e}", row.name));
            }
            stoss::validate::Measure::Calibration { campaign, .. } => {
                stoss::fit::Campaign::load(&fixtures.join(campaign))
                    .unwrap_or_else(|e| panic!("{}: {e}", row.name));
            }
            stoss::validate::Measure::Identification { case, .. } => {
                stoss::fit::Campaign::load(
                    &fixtures.join("diagnosis").join(case).join("campaign.toml"),
                )
                .unwrap_or_else(|e| panic!("{}: {e}", row.name));
            }
            stoss::validate::Measure::FoiPerforation { run } => {
                assert!(
                    stoss::validate::perforation::run(run).is_some(),
                    "{}: no FOI run {run}",
                    row.name
                );
            }
            stoss::validate::Measure::TntImpulse { height } => {
                assert!(height > 0.0, "{}", row.name);
            }
            stoss::validate::Measure::RecordingsRms {
                experiments: (first, second),
            } => {
                for experiment in [first, second] {
                    stoss::experiment::Experiment::load(&fixtures.join(experiment))
                        .unwrap_or_else(|e| panic!("{}: {e}", row.name));
                }
            }
            stoss::validate::Measure::EulerStrength { .. }
            | stoss::validate::Measure::EulerCrater { .. }
            | stoss::validate::Measure::RigidRod { .. }
            | stoss::validate::Measure::LagrangeStrength { .. } => {
                stoss::validate::semi_infinite::shot(fixtures)
                    .unwrap_or_else(|e| panic!("{}: {e}", row.name));
            }
            stoss::validate::Measure::EulerSmooth { .. } => {
                stoss::experiment::Experiment::load(
                    &fixtures.join("experiments/penetration-hzb-1250.toml"),
                )
                .unwrap_or_else(|e| panic!("{}: {e}", row.name));
            }
            stoss::validate::Measure::Finish { .. } | stoss::validate::Measure::Baseline { .. } => {
                stoss::fit::Campaign::load(&fixtures.join("campaigns/synthetic-flow.toml"))
                    .unwrap_or_else(|e| panic!("{}: {e}", row.name));
            }
        }
        assert!(
            row.tolerance > 0.0 && row.stated.is_finite(),
            "{}",
            row.name
        );
    }
}

#[test]
fn a_calibration_that_fails_before_its_first_simulation_leaves_no_folder() {
    // GOAL: issue 52 item 6: a run that fails after creating its output folder but before
    //       logging a simulation removes the folder it created (no empty run left behind); a
    //       folder that existed before is left alone.
    // SETUP: the synthetic-flow campaign with the Slurm executor on a machine without Slurm's
    //        client commands (skipped where `sbatch` is on PATH): the executor fails to start.
    // REFERENCE: non-zero exit, the error names sbatch; the new folder is gone, the existing
    //        one (with a file of the user's) is still there.
    let on_path = std::env::var_os("PATH")
        .is_some_and(|paths| std::env::split_paths(&paths).any(|dir| dir.join("sbatch").exists()));
    if on_path {
        eprintln!("sbatch is on PATH: skipped");
        return;
    }
    let fresh = std::env::temp_dir().join(format!("stoss-no-folder-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&fresh);
    let calibrate_into_fresh = || {
        stoss()
            .args([
                "calibrate",
                "fixtures/campaigns/synthetic-flow.toml",
                "--executor",
                "slurm",
            ])
            .arg("--output")
            .arg(&fresh)
            .output()
            .unwrap()
    };
    let output = calibrate_into_fresh();
    let error = String::from_utf8_lossy(&output.stderr);
    assert!(
        !output.status.success() && error.contains("sbatch"),
        "{error}"
    );
    assert!(!fresh.exists(), "the failed run left {}", fresh.display());
    std::fs::create_dir_all(&fresh).unwrap();
    std::fs::write(fresh.join("notes.txt"), "mine").unwrap();
    let again = calibrate_into_fresh();
    assert!(!again.status.success());
    assert!(
        fresh.join("notes.txt").exists(),
        "an existing folder was removed"
    );
    std::fs::remove_dir_all(&fresh).unwrap();
}

#[test]
fn every_validate_row_is_named_where_its_figure_is_quoted_and_every_named_row_exists() {
    // GOAL: issue 55: each figure in the documents names its `stoss validate` row, and no
    //       citation points nowhere: the first document a row says it is quoted in names the
    //       row, and every row named near "validate" in README.md or docs/*.md exists.
    // SETUP: the rows' `quoted_in`; every backticked hyphenated name within 160 characters
    //        after the word "validate" in the documents.
    // REFERENCE: the row list itself.
    let root = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."));
    let names: Vec<&str> = stoss::validate::ROWS.iter().map(|row| row.name).collect();
    for row in stoss::validate::ROWS {
        let document = row.quoted_in.split(',').next().unwrap().trim();
        let text = std::fs::read_to_string(root.join(document))
            .unwrap_or_else(|e| panic!("row {}: {document}: {e}", row.name));
        assert!(
            text.contains(&format!("`{}`", row.name))
                || text.contains(&format!("validate {}", row.name)),
            "row {} is quoted in {document}, which does not name it",
            row.name
        );
    }
    let mut documents = vec![root.join("README.md")];
    for entry in std::fs::read_dir(root.join("docs")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "md") {
            documents.push(path);
        }
    }
    let row_like = |token: &str| {
        token.contains('-')
            && token.starts_with(|c: char| c.is_ascii_lowercase())
            && token
                .chars()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-')
    };
    let mut cited = 0;
    for path in &documents {
        let text = std::fs::read_to_string(path).unwrap();
        for (at, _) in text.match_indices("validate") {
            let window: String = text[at..].chars().take(160).collect();
            // Segments between backticks (the window may start inside a code span, so
            // both parities are looked at; prose between spans is never row-like).
            let segments: Vec<&str> = window.split('`').collect();
            let inner = segments.len().saturating_sub(1);
            for &token in segments.iter().take(inner).skip(1) {
                if row_like(token) {
                    cited += 1;
                    assert!(
                        names.contains(&token),
                        "{} names `{token}` as a validate row; there is no such row",
                        path.display()
                    );
                }
            }
        }
    }
    assert!(cited > 0, "the scan found no row citation");
}

#[test]
fn every_subcommand_speaks_the_same_way_results_on_stdout_logs_on_stderr_json_on_request() {
    // GOAL: issue 51 item 6: results on stdout, progress and logs on stderr; `--quiet`,
    //       `--verbose` and `--json` are global flags every subcommand takes; one parallelism
    //       flag (`--threads`) that does not change a calibration's result; the run lock is
    //       removed at a clean end.
    // SETUP: `simulate` of the tension cylinder with `--json`; `calibrate` of the
    //        synthetic-flow campaign (6 simulations, one instance) with `--json --threads 1`,
    //        then the same with `--threads 2 --quiet` into another folder; `verify --json`.
    // REFERENCE: stdout parses as one JSON document naming its command (simulate: the
    //        recorded and predicted points; calibrate: the recommendation and each model's
    //        constants with units and symbols); the two calibrations' result.json are equal
    //        but for the simulations' wall times; `--quiet` leaves stderr without progress lines; no `.stoss-run.lock`
    //        is left in either folder.
    let folder = std::env::temp_dir().join(format!("stoss-conventions-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&folder);
    let simulated = stoss()
        .args([
            "simulate",
            "fixtures/experiments/tension-4340-1000.toml",
            "--json",
            "--output",
        ])
        .arg(folder.join("simulate"))
        .output()
        .unwrap();
    assert!(
        simulated.status.success(),
        "{}",
        String::from_utf8_lossy(&simulated.stderr)
    );
    let document: serde_json::Value = serde_json::from_slice(&simulated.stdout)
        .unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&simulated.stdout)));
    assert_eq!(document["command"], "simulate");
    let points = document["measurements"].as_array().unwrap();
    assert!(!points.is_empty() && points[0]["predicted"].is_number());
    let calibrate = |name: &str, flags: &[&str]| {
        let output = stoss()
            .args(["calibrate", "fixtures/campaigns/synthetic-flow.toml"])
            .args(["--budget", "6", "--instances", "1", "--polish", "0"])
            .args(flags)
            .arg("--output")
            .arg(folder.join(name))
            .output()
            .unwrap();
        assert!(
            output.status.success(),
            "{}",
            String::from_utf8_lossy(&output.stderr)
        );
        output
    };
    let one = calibrate("one", &["--json", "--threads", "1"]);
    let document: serde_json::Value = serde_json::from_slice(&one.stdout)
        .unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&one.stdout)));
    assert_eq!(document["command"], "calibrate");
    assert!(document["recommendation"]["reasons"]
        .as_array()
        .is_some_and(|r| !r.is_empty()));
    let constants = document["models"][0]["constants"].as_array().unwrap();
    assert!(constants
        .iter()
        .any(|c| c["symbol"] == "A" && c["unit"] == "Pa" && c["value"].is_number()));
    assert!(String::from_utf8_lossy(&one.stderr).contains("simulations,"));
    let two = calibrate("two", &["--threads", "2", "--quiet"]);
    assert!(
        !String::from_utf8_lossy(&two.stderr).contains("simulations,"),
        "--quiet: {}",
        String::from_utf8_lossy(&two.stderr)
    );
    assert!(String::from_utf8_lossy(&two.stdout).contains("recommended: use"));
    // The result without the simulations' wall times (the only thing a thread count may
    // change).
    fn without_wall_times(value: &mut serde_json::Value) {
        match value {
            serde_json::Value::Object(map) => {
                map.remove("wall_time");
                map.values_mut().for_each(without_wall_times);
            }
            serde_json::Value::Array(items) => items.iter_mut().for_each(without_wall_times),
            _ => {}
        }
    }
    let result = |name: &str| {
        let text = std::fs::read(folder.join(name).join("report/result.json")).unwrap();
        let mut value: serde_json::Value = serde_json::from_slice(&text).unwrap();
        without_wall_times(&mut value);
        value
    };
    assert!(
        result("one") == result("two"),
        "--threads changed the result"
    );
    for name in ["one", "two"] {
        assert!(
            !folder.join(name).join(".stoss-run.lock").exists(),
            "a lock was left in {name}"
        );
    }
    let verified = stoss().args(["--json", "verify"]).output().unwrap();
    let document: serde_json::Value = serde_json::from_slice(&verified.stdout)
        .unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&verified.stdout)));
    assert_eq!(document["command"], "verify");
    assert_eq!(document["failed"], 0);
    std::fs::remove_dir_all(&folder).unwrap();
}

//! Bad input, tried as a new user would make it (issue 17): over 150 malformed experiments,
//! materials, recordings and campaigns, each run through the `stoss` command line.
//!
//! GOAL: every malformed input ends quickly with a clear error: a non-zero exit (never a
//!       panic), a message naming the file and the field (and the line where the field is
//!       written on one), and no output folder left behind.
//! SETUP: mutations of bundled fixtures (the 208 m/s 4340 Taylor test, its material and
//!        recording; a 4340 flow curve; the synthetic flow-curve campaign), copied into a
//!        scratch folder per case: every set-up and material field set to a negative, infinite,
//!        NaN, textual, absurdly large and wrongly-united value; broken CSV; broken campaigns.
//! REFERENCE: the contract of the brief's "bad input" rule.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Longest a refused input may take.
const LIMIT: Duration = Duration::from_secs(30);

fn fixtures() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures")
}

fn read(name: &str) -> String {
    std::fs::read_to_string(fixtures().join(name)).unwrap()
}

/// One malformed input.
struct Case {
    name: String,
    /// Files written into the case's folder: (file name, content).
    files: Vec<(String, String)>,
    /// Command-line arguments; `{dir}` is the case's folder.
    args: Vec<String>,
    /// The file the message must name.
    file: String,
    /// What the message must name (a field, a column, a key).
    field: String,
    /// The message must give a line number (`file:N:`).
    line: bool,
}

/// `text` with the line `key = ...` (first match) replaced by `key = value`; a key not written
/// is added at the top of `[setup]`.
fn with_value(text: &str, key: &str, value: &str) -> String {
    if !text
        .lines()
        .any(|l| l.split('=').next().map(str::trim) == Some(key))
    {
        assert!(text.contains("[setup]\n"), "no `{key} =` line");
        return text.replacen("[setup]\n", &format!("[setup]\n{key} = {value}\n"), 1);
    }
    let mut done = false;
    let out: Vec<String> = text
        .lines()
        .map(|l| {
            if !done && l.split('=').next().map(str::trim) == Some(key) && l.contains('=') {
                done = true;
                format!("{key} = {value}")
            } else {
                l.to_string()
            }
        })
        .collect();
    assert!(done, "no `{key} =` line");
    out.join("\n") + "\n"
}

/// The Taylor experiment's files, paths local to the case folder.
fn taylor_files(experiment: &str, material: &str, recording: &str) -> Vec<(String, String)> {
    vec![
        ("experiment.toml".into(), experiment.into()),
        ("material.toml".into(), material.into()),
        ("recording.csv".into(), recording.into()),
    ]
}

fn taylor_experiment() -> String {
    read("experiments/taylor-4340-208.toml")
        .replace("\"taylor-4340-208.csv\"", "\"recording.csv\"")
        .replace("\"../materials/4340-jc.toml\"", "\"material.toml\"")
}

fn simulate_args() -> Vec<String> {
    ["simulate", "{dir}/experiment.toml", "--output", "{dir}/out"]
        .map(String::from)
        .to_vec()
}

fn cases() -> Vec<Case> {
    let mut cases = Vec::new();
    let experiment = taylor_experiment();
    let material = read("materials/4340-jc.toml");
    let recording = read("experiments/taylor-4340-208.csv");

    // 1. Every Taylor set-up field: negative, infinite, NaN, text, absurd, wrong unit.
    for (key, dimensioned) in [
        ("length", true),
        ("diameter", true),
        ("velocity", true),
        ("temperature", true),
        ("anvil_friction", false),
        ("radial_elements", false),
        ("end_time", true),
    ] {
        let mut values = vec!["-1.0", "inf", "nan", "\"abc\"", "-inf"];
        if dimensioned {
            values.extend(["1e30", "\"3 GPa\"", "\"3 furlongs\""]);
        }
        for value in values {
            cases.push(Case {
                name: format!("taylor {key} = {value}"),
                files: taylor_files(&with_value(&experiment, key, value), &material, &recording),
                args: simulate_args(),
                file: "experiment.toml".into(),
                field: key.into(),
                line: true,
            });
        }
    }

    // 2. Every material constant: negative, infinite, NaN, text.
    for key in [
        "density",
        "shear_modulus",
        "specific_heat",
        "yield_stress",
        "hardening_modulus",
        "hardening_exponent",
        "thermal_exponent",
        "reference_rate",
        "reference_temperature",
        "melting_temperature",
        "taylor_quinney",
        "bulk_modulus",
    ] {
        for value in ["-1.0", "inf", "nan", "\"abc\""] {
            cases.push(Case {
                name: format!("material {key} = {value}"),
                files: taylor_files(&experiment, &with_value(&material, key, value), &recording),
                args: simulate_args(),
                file: "material.toml".into(),
                field: key.into(),
                line: true,
            });
        }
    }
    // Dimensioned material constants: absurd and wrongly united.
    for key in [
        "density",
        "shear_modulus",
        "yield_stress",
        "melting_temperature",
        "bulk_modulus",
    ] {
        for value in ["1e40", "\"7 mm\""] {
            cases.push(Case {
                name: format!("material {key} = {value}"),
                files: taylor_files(&experiment, &with_value(&material, key, value), &recording),
                args: simulate_args(),
                file: "material.toml".into(),
                field: key.into(),
                line: true,
            });
        }
    }

    // 3. Broken recordings.
    let header = "quantity,position,value,uncertainty";
    for (name, csv, field, line) in [
        (
            "no header",
            "final_length,0,0.02,1e-4\n".to_string(),
            "",
            true,
        ),
        (
            "wrong header",
            "q,p,v,u\nfinal_length,0,0.02,1e-4\n".into(),
            "",
            true,
        ),
        (
            "header unit unknown",
            "quantity,position,value [parsec],uncertainty\nfinal_length,0,0.02,1e-4\n".into(),
            "",
            true,
        ),
        (
            "header unit wrong dimension",
            "quantity,position,value [MPa],uncertainty\nfinal_length,0,22,0.1\n".into(),
            "value",
            true,
        ),
        (
            "unit on quantity",
            "quantity [m],position,value,uncertainty\nfinal_length,0,0.02,1e-4\n".into(),
            "quantity",
            true,
        ),
        (
            "unclosed unit",
            "quantity,position,value [mm,uncertainty\nfinal_length,0,22,0.1\n".into(),
            "",
            true,
        ),
        (
            "text value",
            format!("{header}\nfinal_length,0,abc,1e-4\n"),
            "value",
            true,
        ),
        (
            "text position",
            format!("{header}\nfinal_length,x,0.02,1e-4\n"),
            "position",
            true,
        ),
        (
            "nan value",
            format!("{header}\nfinal_length,0,NaN,1e-4\n"),
            "value",
            true,
        ),
        (
            "inf uncertainty",
            format!("{header}\nfinal_length,0,0.02,inf\n"),
            "uncertainty",
            true,
        ),
        (
            "zero uncertainty",
            format!("{header}\nfinal_length,0,0.02,0\n"),
            "uncertainty",
            true,
        ),
        (
            "negative uncertainty",
            format!("{header}\nfinal_length,0,0.02,-1e-4\n"),
            "uncertainty",
            true,
        ),
        (
            "three cells",
            format!("{header}\nfinal_length,0,0.02\n"),
            "",
            true,
        ),
        (
            "five cells",
            format!("{header}\nfinal_length,0,0.02,1e-4,7\n"),
            "",
            true,
        ),
        (
            "empty quantity",
            format!("{header}\n,0,0.02,1e-4\n"),
            "quantity",
            true,
        ),
        (
            "unknown quantity",
            format!("{header}\ntrue_stress,0.1,1e9,1e7\n"),
            "true_stress",
            false,
        ),
        ("no points", format!("{header}\n"), "no points", false),
        ("only comments", "# nothing\n".into(), "no points", false),
        (
            "semicolons",
            "quantity;position;value;uncertainty\nfinal_length;0;0.02;1e-4\n".into(),
            "",
            true,
        ),
        (
            "huge cell",
            format!("{header}\nfinal_length,0,{},1e-4\n", "9".repeat(100_000)),
            "value",
            true,
        ),
        ("binary junk", "\u{0}\u{1}\u{2}garbage\n".into(), "", true),
    ] {
        cases.push(Case {
            name: format!("recording: {name}"),
            files: taylor_files(&experiment, &material, &csv),
            args: simulate_args(),
            file: "recording.csv".into(),
            field: field.into(),
            line,
        });
    }

    // 3b. Recordings their experiment could not have produced (issue 52, item 1): each rule of
    //     experiment::plausibility once, named with its line and column.
    let taylor_rules = [
        (
            "Lf above L0",
            format!("{header}\nfinal_length,0,0.0300,5e-5\n"),
            "value",
        ),
        (
            "negative final length",
            format!("{header}\nfinal_length,0,-0.02,5e-5\n"),
            "value",
        ),
        (
            "footprint narrower than the rod (a radius)",
            format!("{header}\nfinal_length,0,0.0225,5e-5\nfootprint_diameter,0,0.00555,1.5e-4\n"),
            "value",
        ),
        (
            "two final lengths",
            format!("{header}\nfinal_length,0,0.0225,5e-5\nfinal_length,0,0.0224,5e-5\n"),
            "value",
        ),
        (
            "station beyond the rod",
            format!("{header}\nfinal_length,0,0.0225,5e-5\ndiameter,0.03,0.008,1e-4\n"),
            "position",
        ),
    ];
    for (name, csv, field) in taylor_rules {
        cases.push(Case {
            name: format!("implausible Taylor recording: {name}"),
            files: taylor_files(&experiment, &material, &csv),
            args: simulate_args(),
            file: "recording.csv".into(),
            field: field.into(),
            line: true,
        });
    }
    let flow_in_mpa: String = read("experiments/flow-4340-jc-tension-570s-298K.csv")
        .lines()
        .map(|l| match l.split(',').collect::<Vec<_>>().as_slice() {
            [q, p, v, u] if *q == "true_stress" => format!(
                "{q},{p},{},{}",
                v.parse::<f64>().unwrap() / 1e6,
                u.parse::<f64>().unwrap() / 1e6
            ),
            _ => l.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n");
    let flow_for_rules = read("experiments/flow-4340-jc-tension-570s-298K.toml")
        .replace(
            "\"flow-4340-jc-tension-570s-298K.csv\"",
            "\"recording.csv\"",
        )
        .replace("\"../materials/4340-jc.toml\"", "\"material.toml\"");
    for (name, csv) in [
        ("flow curve in MPa read as Pa", flow_in_mpa),
        (
            "negative flow stress",
            format!("{header}\ntrue_stress,0.01,-8.0e8,1.6e7\n"),
        ),
    ] {
        cases.push(Case {
            name: format!("implausible flow curve: {name}"),
            files: taylor_files(&flow_for_rules, &material, &csv),
            args: simulate_args(),
            file: "recording.csv".into(),
            field: "value".into(),
            line: true,
        });
    }
    let penetration = read("experiments/penetration-hzb-1250.toml")
        .replace("\"penetration-hzb-1250.csv\"", "\"recording.csv\"")
        .replace("\"../materials/hzb-w-jc.toml\"", "\"material.toml\"")
        .replace("\"../materials/wha-jc.toml\"", "\"rod.toml\"");
    let rod = read("materials/wha-jc.toml");
    let target = read("materials/hzb-w-jc.toml");
    for (name, csv, field) in [
        (
            "nose depth falling with time",
            format!("{header}\nnose_depth,2.0e-5,1.2e-2,3e-4\nnose_depth,4.0e-5,0.8e-2,3e-4\n"),
            "value",
        ),
        (
            "negative nose depth",
            format!("{header}\nnose_depth,2.0e-5,-5e-3,3e-4\n"),
            "value",
        ),
        (
            "rod longer than it was",
            format!("{header}\nrod_length,2.0e-5,0.08,5e-4\n"),
            "value",
        ),
        (
            "residual velocity above the striking one",
            format!("{header}\nresidual_velocity,0,1400.0,10.0\n"),
            "value",
        ),
    ] {
        cases.push(Case {
            name: format!("implausible penetration recording: {name}"),
            files: vec![
                ("experiment.toml".into(), penetration.clone()),
                ("material.toml".into(), target.clone()),
                ("rod.toml".into(), rod.clone()),
                ("recording.csv".into(), csv),
            ],
            args: simulate_args(),
            file: "recording.csv".into(),
            field: field.into(),
            line: true,
        });
    }
    let ballistic = read("experiments/ballistic-hns-wc.toml")
        .replace("\"ballistic-hns-wc.csv\"", "\"recording.csv\"")
        .replace("\"../materials/hns-jc.toml\"", "\"material.toml\"")
        .replace("\"../materials/wc-core.toml\"", "\"core.toml\"");
    for (name, csv) in [
        (
            "residual velocity above the impact velocity",
            format!("{header}\nresidual_velocity,800.0,950.0,10.0\n"),
        ),
        (
            "residual mass above the projectile's",
            format!("{header}\nresidual_mass,800.0,1.0,1e-4\n"),
        ),
        (
            "non-positive ballistic limit",
            format!("{header}\nballistic_limit,0,-762.0,25.0\n"),
        ),
    ] {
        cases.push(Case {
            name: format!("implausible ballistic recording: {name}"),
            files: vec![
                ("experiment.toml".into(), ballistic.clone()),
                ("material.toml".into(), read("materials/hns-jc.toml")),
                ("core.toml".into(), read("materials/wc-core.toml")),
                ("recording.csv".into(), csv),
            ],
            args: simulate_args(),
            file: "recording.csv".into(),
            field: "value".into(),
            line: true,
        });
    }

    // 3c. A charge mass in grams written as kilograms: a disc metres tall (issue 52, item 3).
    let blast = read("experiments/blast-hha-37g-13mm.toml")
        .replace("\"blast-hha-37g-13mm.csv\"", "\"recording.csv\"")
        .replace(
            "\"../materials/synthetic-hha-truth.toml\"",
            "\"material.toml\"",
        );
    assert!(blast.contains("mass = 0.0375"));
    cases.push(Case {
        name: "blast charge mass in g written as kg".into(),
        files: vec![
            (
                "experiment.toml".into(),
                blast.replace("mass = 0.0375", "mass = 37.5"),
            ),
            (
                "material.toml".into(),
                read("materials/synthetic-hha-truth.toml"),
            ),
            (
                "recording.csv".into(),
                read("experiments/blast-hha-37g-13mm.csv"),
            ),
        ],
        args: simulate_args(),
        file: "experiment.toml".into(),
        field: "charge.mass".into(),
        line: true,
    });

    // 4. Broken experiment files beyond single fields.
    for (name, text, field, line) in [
        (
            "unknown setup field",
            experiment.replace("[setup]", "[setup]\nlenght = 0.02"),
            "lenght",
            true,
        ),
        (
            "unknown kind",
            experiment.replace("kind = \"taylor\"", "kind = \"tylor\""),
            "tylor",
            true,
        ),
        (
            "missing velocity",
            experiment.replace("velocity = 208.0\n", ""),
            "velocity",
            false,
        ),
        (
            "duplicate key",
            experiment.replace("velocity = 208.0", "velocity = 208.0\nvelocity = 209.0"),
            "velocity",
            true,
        ),
        (
            "unclosed table",
            experiment.replace("[setup]", "[setup"),
            "",
            true,
        ),
        (
            "unclosed string",
            experiment.replace("\"recording.csv\"", "\"recording.csv"),
            "",
            true,
        ),
        (
            "missing recording",
            experiment.replace("\"recording.csv\"", "\"nowhere.csv\""),
            "nowhere.csv",
            false,
        ),
        (
            "missing material",
            experiment.replace("\"material.toml\"", "\"nowhere.toml\""),
            "nowhere.toml",
            false,
        ),
        (
            "recording is a folder",
            experiment.replace("\"recording.csv\"", "\".\""),
            "",
            false,
        ),
        ("empty file", String::new(), "", false),
    ] {
        cases.push(Case {
            name: format!("experiment: {name}"),
            files: taylor_files(&text, &material, &recording),
            args: simulate_args(),
            file: if field.ends_with(".csv") || field.ends_with(".toml") {
                field.into()
            } else {
                "experiment.toml".into()
            },
            field: field.into(),
            line,
        });
    }

    // 5. A uniaxial flow curve: its fields and a curve in percent.
    let flow = read("experiments/flow-4340-jc-tension-570s-298K.toml")
        .replace(
            "\"flow-4340-jc-tension-570s-298K.csv\"",
            "\"recording.csv\"",
        )
        .replace("\"../materials/4340-jc.toml\"", "\"material.toml\"");
    let flow_csv = read("experiments/flow-4340-jc-tension-570s-298K.csv");
    for (key, value) in [
        ("strain_rate", "-570.0"),
        ("strain_rate", "0.0"),
        ("strain_rate", "inf"),
        ("strain_rate", "\"fast\""),
        ("strain_rate", "1e30"),
        ("strain_rate", "\"570 m/s\""),
        ("temperature", "-5.0"),
        ("temperature", "0.0"),
        ("temperature", "\"hot\""),
        ("temperature", "\"298 MPa\""),
        ("compression", "\"yes\""),
        ("isothermal", "2"),
        ("recorded_strain", "\"engineering\""),
    ] {
        cases.push(Case {
            name: format!("flow {key} = {value}"),
            files: taylor_files(&with_value(&flow, key, value), &material, &flow_csv),
            args: simulate_args(),
            file: "experiment.toml".into(),
            field: key.into(),
            line: true,
        });
    }
    let percent: String = flow_csv
        .lines()
        .map(|l| match l.split(',').collect::<Vec<_>>().as_slice() {
            [q, p, v, u] if *q == "true_stress" => {
                format!("{q},{},{v},{u}", p.parse::<f64>().unwrap() * 100.0)
            }
            _ => l.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n");
    cases.push(Case {
        name: "flow curve in percent".into(),
        files: taylor_files(&flow, &material, &percent),
        args: simulate_args(),
        file: "recording.csv".into(),
        field: "position".into(),
        line: false,
    });

    // 6. Broken campaigns (the synthetic flow-curve campaign, experiments by absolute path).
    let root = fixtures();
    let campaign =
        read("campaigns/synthetic-flow.toml").replace("\"../", &format!("\"{}/", root.display()));
    let calibrate_args: Vec<String> = ["calibrate", "{dir}/campaign.toml", "--output", "{dir}/out"]
        .map(String::from)
        .to_vec();
    // The campaign with its first experiment fitted and every other held out.
    let one_fitted = {
        let (head, rest) = campaign.split_once("[[experiments]]").unwrap();
        let (first, others) = rest.split_once("[[experiments]]").unwrap();
        let others = others
            .replace("holdout = true\n", "")
            .replace("[[experiments]]", "[[experiments]]\nholdout = true");
        let (others, optimiser) = others.split_once("[optimiser]").unwrap();
        format!(
            "{head}[[experiments]]{first}[[experiments]]\nholdout = true{others}[optimiser]{optimiser}"
        )
    };
    let campaign_cases: Vec<(&str, String, &str, bool)> = vec![
        ("three bounds", campaign.replace("yield_stress = [0.5e9, 2.0e9]", "yield_stress = [0.5e9, 1.0e9, 2.0e9]"), "yield_stress", true),
        ("one bound", campaign.replace("yield_stress = [0.5e9, 2.0e9]", "yield_stress = [0.5e9]"), "yield_stress", true),
        ("reversed bounds", campaign.replace("yield_stress = [0.5e9, 2.0e9]", "yield_stress = [2.0e9, 0.5e9]"), "yield_stress", true),
        ("equal bounds", campaign.replace("yield_stress = [0.5e9, 2.0e9]", "yield_stress = [1.0e9, 1.0e9]"), "yield_stress", true),
        ("infinite bound", campaign.replace("yield_stress = [0.5e9, 2.0e9]", "yield_stress = [0.5e9, inf]"), "yield_stress", true),
        ("nan bound", campaign.replace("yield_stress = [0.5e9, 2.0e9]", "yield_stress = [nan, 2.0e9]"), "yield_stress", true),
        ("text bound", campaign.replace("yield_stress = [0.5e9, 2.0e9]", "yield_stress = [\"low\", 2.0e9]"), "yield_stress", true),
        ("bound in the wrong unit", campaign.replace("yield_stress = [0.5e9, 2.0e9]", "yield_stress = [\"0.5 mm\", \"2 mm\"]"), "yield_stress", true),
        ("implausible bound", campaign.replace("yield_stress = [0.5e9, 2.0e9]", "yield_stress = [0.5e9, 2.0e19]"), "yield_stress", true),
        ("unknown constant", campaign.replace("yield_stress = [0.5e9, 2.0e9]", "yeild_stress = [0.5e9, 2.0e9]"), "yeild_stress", true),
        ("no parameters", campaign.replace("[models.parameters]", "[models.parameter]"), "parameter", true),
        ("no models", campaign.replace("[[models]]\nname = \"jc\"", "[[nomodels]]\nname = \"jc\""), "models", true),
        ("duplicate model", campaign.replacen("[[experiments]]", "[[models]]\nname = \"jc\"\n[models.parameters]\nyield_stress = [0.5e9, 2.0e9]\n\n[[experiments]]", 1), "jc", true),
        ("budget 0", with_value(&campaign, "budget", "0"), "budget", true),
        ("budget negative", with_value(&campaign, "budget", "-3"), "budget", true),
        ("budget text", with_value(&campaign, "budget", "\"many\""), "budget", true),
        ("instances 0", with_value(&campaign, "instances", "0"), "instances", true),
        ("parallel huge", with_value(&campaign, "parallel", "100000"), "parallel", true),
        ("parallel 0", with_value(&campaign, "parallel", "0"), "parallel", true),
        ("seed negative", with_value(&campaign, "seed", "-1"), "seed", true),
        ("weight negative", campaign.replacen("file = ", "weight = -1.0\nfile = ", 1), "weight", true),
        ("weight nan", campaign.replacen("file = ", "weight = nan\nfile = ", 1), "weight", true),
        ("missing experiment", campaign.replacen("synthetic-flow-hha-1s.toml", "nowhere.toml", 1), "nowhere.toml", false),
        ("missing material", campaign.replace("materials/4340-jc.toml", "materials/nowhere.toml"), "nowhere.toml", false),
        ("unknown top-level field", format!("budgett = 3\n{campaign}"), "budgett", true),
        ("unknown optimiser field", campaign.replace("[optimiser]", "[optimiser]\nbugdet = 3"), "bugdet", true),
        ("constraint negative", format!("{campaign}\n[constraints]\nmax_flow_stress = -1.0\n"), "max_flow_stress", true),
        ("constraints leaving no feasible band", format!("{campaign}\n[constraints]\nmin_flow_stress = 3.0e9\nmax_flow_stress = 2.0e9\n"), "max_flow_stress", true),
        ("executor kind", format!("{campaign}\n[executor]\nkind = \"cloud\"\n"), "cloud", true),
        ("executor time limit", format!("{campaign}\n[executor]\nkind = \"slurm\"\ntime_limit = \"soon\"\n"), "time_limit", true),
        ("executor cpus 0", format!("{campaign}\n[executor]\ncpus_per_task = 0\n"), "cpus_per_task", true),
        ("executor concurrency 0", format!("{campaign}\n[executor]\nmax_concurrent = 0\n"), "max_concurrent", true),
        ("executor poll nan", format!("{campaign}\n[executor]\npoll_interval = nan\n"), "poll_interval", true),
        ("executor retries huge", format!("{campaign}\n[executor]\nretries = 1000\n"), "retries", true),
        ("executor partition blank", format!("{campaign}\n[executor]\npartition = \"two words\"\n"), "partition", true),
        ("executor unknown field", format!("{campaign}\n[executor]\npartitoin = \"x\"\n"), "partitoin", true),
        ("syntax error", campaign.replace("[optimiser]", "[optimiser"), "", true),
        ("fold budget without leave-one-out", campaign.replace("[optimiser]", "[optimiser]\nfold_budget = 2"), "fold_budget", true),
        ("parallel 0 named as parallel", campaign.replace("parallel = 2", "parallel = 0"), "parallel", true),
        ("bounds spanning a negative exponent", campaign.replace("hardening_exponent = [0.05, 1.0]", "hardening_exponent = [-0.5, 0.9]"), "hardening_exponent", true),
        ("experiment listed twice", campaign.replacen("[[experiments]]", &format!("[[experiments]]{}[[experiments]]", campaign.split("[[experiments]]").nth(1).unwrap()), 1), "listed twice", true),
        ("instances 0 named as instances", campaign.replace("instances = 1", "instances = 0"), "instances", true),
        ("budget costing weeks", campaign.replace("budget = 40", "budget = 1000000000"), "budget", false),
        ("leave-one-out with one fitted experiment", one_fitted.replace("[optimiser]", "[optimiser]\nleave_one_out = true"), "leave_one_out", true),
        ("set-up field not calibratable", campaign.replacen("[[experiments]]", "[models.setup]\n\"synthetic-flow-hha-1s.isothermal\" = [0.0, 1.0]\n\n[[experiments]]", 1), "isothermal", true),
        ("set-up bounds invalid at a corner", campaign.replacen("[[experiments]]", "[models.setup]\n\"uniaxial.temperature\" = [\"-10 K\", \"400 K\"]\n\n[[experiments]]", 1), "uniaxial.temperature", true),
    ];
    for (name, text, field, line) in campaign_cases {
        cases.push(Case {
            name: format!("campaign: {name}"),
            files: vec![("campaign.toml".into(), text)],
            args: calibrate_args.clone(),
            file: if field.ends_with(".toml") {
                field.into()
            } else {
                "campaign.toml".into()
            },
            field: field.into(),
            line,
        });
    }

    // 7. The drop-weight beam (issue 19): bars outside the concrete, a drop height or mass
    //    <= 0, a damage table that is not monotone in lambda.
    let beam = read("experiments/rc-beam-drop-weight.toml")
        .replace("\"rc-beam-drop-weight.csv\"", "\"recording.csv\"")
        .replace("\"../materials/hpc-100-kc.toml\"", "\"material.toml\"")
        .replace(
            "\"../materials/drop-weight-steel-elastic.toml\"",
            "\"steel.toml\"",
        );
    let beam_material = read("materials/hpc-100-kc.toml");
    let beam_files = |experiment: &str, material: &str| -> Vec<(String, String)> {
        vec![
            ("experiment.toml".into(), experiment.into()),
            ("material.toml".into(), material.into()),
            (
                "steel.toml".into(),
                read("materials/drop-weight-steel-elastic.toml"),
            ),
            (
                "recording.csv".into(),
                read("experiments/rc-beam-drop-weight.csv"),
            ),
        ]
    };
    let by_height = beam.replace("impact_velocity = 6.7", "drop_height = 2.29");
    for (name, experiment, field) in [
        (
            "bottom bar below the beam",
            with_value(&beam, "bottom_bar_cover", "-0.01"),
            "bottom_bar_cover",
        ),
        (
            "bottom bar above the beam",
            with_value(&beam, "bottom_bar_cover", "0.5"),
            "bottom_bar_cover",
        ),
        (
            "top bar outside",
            with_value(&beam, "top_bar_cover", "0.4"),
            "top_bar_cover",
        ),
        (
            "bar outside the side",
            with_value(&beam, "bar_side_cover", "0.1"),
            "bar_side_cover",
        ),
        (
            "stirrups beyond the beam",
            with_value(&beam, "stirrup_count", "40"),
            "first_stirrup",
        ),
        (
            "drop height 0",
            with_value(&by_height, "drop_height", "0.0"),
            "drop_height",
        ),
        (
            "drop height negative",
            with_value(&by_height, "drop_height", "-2.0"),
            "drop_height",
        ),
        (
            "height and velocity",
            with_value(&beam, "drop_height", "2.0"),
            "impact_velocity",
        ),
        (
            "drop mass 0",
            with_value(&beam, "drop_mass", "0.0"),
            "drop_mass",
        ),
        (
            "drop mass negative",
            with_value(&beam, "drop_mass", "-718.0"),
            "drop_mass",
        ),
        (
            "velocity in km/h",
            with_value(&beam, "impact_velocity", "\"24 km/h\""),
            "impact_velocity",
        ),
        (
            "records every nanosecond",
            with_value(&beam, "output_interval", "1e-9"),
            "output_interval",
        ),
        (
            "stirrups a micrometre apart",
            with_value(
                &with_value(&beam, "stirrup_spacing", "1e-6"),
                "first_stirrup",
                "0.5",
            ),
            "stirrup_spacing",
        ),
        (
            "non-local radius of many elements",
            with_value(&beam, "nonlocal_radius", "0.08"),
            "nonlocal_radius",
        ),
        (
            "element size in mm",
            with_value(&beam, "element_size", "1e-5"),
            "end_time",
        ),
    ] {
        cases.push(Case {
            name: format!("drop-weight beam: {name}"),
            files: beam_files(&experiment, &beam_material),
            args: simulate_args(),
            file: "experiment.toml".into(),
            field: field.into(),
            line: true,
        });
    }
    // A bar 0.5 mm above the bottom face: a sliver element that would set a runaway step.
    cases.push(Case {
        name: "drop-weight beam: a sliver element under the bottom bars".into(),
        files: beam_files(
            &with_value(&beam, "bottom_bar_cover", "0.0005"),
            &beam_material,
        ),
        args: simulate_args(),
        file: "experiment.toml".into(),
        field: "element_size".into(),
        line: false,
    });
    let non_monotone = beam_material.replace(
        "lambda = [0.0, 5.5e-6, 1.4e-5,",
        "lambda = [0.0, 1.4e-5, 5.5e-6,",
    );
    assert_ne!(non_monotone, beam_material);
    cases.push(Case {
        name: "drop-weight beam: damage table not increasing in lambda".into(),
        files: beam_files(&beam, &non_monotone),
        args: simulate_args(),
        file: "material.toml".into(),
        field: "lambda".into(),
        line: true,
    });

    // 8. Command-line slips.
    for (name, args, field) in [
        ("threads 0", vec!["--threads", "0"], "threads"),
        ("threads huge", vec!["--threads", "100000"], "threads"),
        ("threads text", vec!["--threads", "many"], "threads"),
    ] {
        let mut all = simulate_args();
        all.extend(args.iter().map(|s| s.to_string()));
        cases.push(Case {
            name: format!("simulate {name}"),
            files: taylor_files(&experiment, &material, &recording),
            args: all,
            file: String::new(),
            field: field.into(),
            line: false,
        });
    }
    for (name, args, field) in [
        ("budget 0", vec!["--budget", "0"], "budget"),
        (
            "time limit",
            vec!["--executor", "slurm", "--time-limit", "later"],
            "time-limit",
        ),
        (
            "cpus 0",
            vec!["--executor", "slurm", "--cpus-per-task", "0"],
            "cpus-per-task",
        ),
        ("executor unknown", vec!["--executor", "cloud"], "executor"),
    ] {
        let mut all = calibrate_args.clone();
        all.extend(args.iter().map(|s| s.to_string()));
        cases.push(Case {
            name: format!("calibrate {name}"),
            files: vec![("campaign.toml".into(), campaign.clone())],
            args: all,
            file: String::new(),
            field: field.into(),
            line: false,
        });
    }
    cases
}

/// Run one case; `Err` says what it got wrong.
fn run(case: &Case, folder: &Path) -> Result<(), String> {
    std::fs::create_dir_all(folder).unwrap();
    for (name, content) in &case.files {
        std::fs::write(folder.join(name), content).unwrap();
    }
    let dir = folder.display().to_string();
    let args: Vec<String> = case.args.iter().map(|a| a.replace("{dir}", &dir)).collect();
    let started = Instant::now();
    let mut child = Command::new(env!("CARGO_BIN_EXE_stoss"))
        .args(&args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if started.elapsed() > LIMIT {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!("still running after {} s", LIMIT.as_secs()));
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    let first_line = stderr.lines().next().unwrap_or_default().to_string();
    if status.success() {
        return Err("exit 0".into());
    }
    if status.code() == Some(101) || stderr.contains("panicked") {
        return Err(format!("panic: {first_line}"));
    }
    if !case.file.is_empty() && !stderr.contains(&case.file) {
        return Err(format!("does not name {}: {first_line}", case.file));
    }
    if !case.field.is_empty() && !stderr.contains(&case.field) {
        return Err(format!("does not name `{}`: {first_line}", case.field));
    }
    if case.line {
        let named = stderr
            .split(&format!("{}:", case.file))
            .skip(1)
            .any(|rest| {
                rest.split(':')
                    .next()
                    .is_some_and(|n| n.parse::<usize>().is_ok())
            });
        if !named {
            return Err(format!("gives no line: {first_line}"));
        }
    }
    if folder.join("out").exists() {
        return Err(format!("left an output folder: {first_line}"));
    }
    Ok(())
}

#[test]
fn every_malformed_input_is_refused_cleanly() {
    let cases = cases();
    let scratch = std::env::temp_dir().join(format!("stoss-bad-input-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&scratch);
    let mut failures = Vec::new();
    for (index, case) in cases.iter().enumerate() {
        if let Err(problem) = run(case, &scratch.join(index.to_string())) {
            failures.push(format!("{}: {problem}", case.name));
        }
    }
    let _ = std::fs::remove_dir_all(&scratch);
    println!(
        "bad input: {} malformed inputs, {} refused cleanly",
        cases.len(),
        cases.len() - failures.len()
    );
    assert!(cases.len() >= 150, "only {} cases", cases.len());
    assert!(
        failures.is_empty(),
        "{} of {} cases:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}

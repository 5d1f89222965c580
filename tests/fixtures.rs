//! The bundled recordings derived from real data are exactly the raw numbers in SI units.

use std::path::PathBuf;
use stoss::input::recording;

fn fixtures() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures")
}

/// A raw data file's rows (space or comma separated).
fn raw_table(path: &std::path::Path) -> Vec<Vec<f64>> {
    std::fs::read_to_string(path)
        .unwrap()
        .replace(',', " ")
        .lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.split_whitespace().map(|w| w.parse().unwrap()).collect())
        .collect()
}

/// The bundled experiment file that names the raw file `name`.
fn experiment_naming(name: &str) -> PathBuf {
    std::fs::read_dir(fixtures().join("experiments"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| {
            p.extension().is_some_and(|e| e == "toml")
                && std::fs::read_to_string(p).unwrap().contains(name)
        })
        .unwrap_or_else(|| panic!("no experiment names {name}"))
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-6 * b.abs().max(1e-12)
}

#[test]
fn taylor_recordings_are_the_published_numbers() {
    // GOAL: Lf, Df and W of each Taylor recording equal StJohnson.dat (SI).
    // SETUP: fixtures/real/4340-taylor/StJohnson.dat lines 1, 4, 7 (columns 6, 10, 11).
    // REFERENCE: the raw file; 1e-6 relative (6 significant digits written).
    let raw = raw_table(&fixtures().join("real/4340-taylor/StJohnson.dat"));
    for (line, velocity) in [(0, 208), (3, 282), (6, 343)] {
        let row = &raw[line];
        let points =
            recording::load(&fixtures().join(format!("experiments/taylor-4340-{velocity}.csv")))
                .unwrap();
        let value = |quantity: &str| {
            points
                .iter()
                .find(|p| p.quantity == quantity)
                .unwrap()
                .value
        };
        assert!(close(value("final_length"), row[5]));
        assert!(close(value("footprint_diameter"), row[9]));
        let w = points.iter().find(|p| p.quantity == "diameter").unwrap();
        assert!(close(w.value, row[10]) && close(w.position, 0.2 * row[4]));
    }
}

#[test]
fn copper_taylor_recordings_are_the_published_numbers() {
    // GOAL: Lf, Df and W of each copper Taylor recording equal CuZerilli.dat (SI), and the
    //       set-up's L0, D0, velocity and temperature its columns.
    // SETUP: fixtures/real/copper-taylor/CuZerilli.dat lines 1, 4, 7 (columns 3-6 and 9-11).
    // REFERENCE: the raw file; 1e-6 relative.
    let raw = raw_table(&fixtures().join("real/copper-taylor/CuZerilli.dat"));
    for line in [0, 3, 6] {
        let row = &raw[line];
        let stem = format!("experiments/taylor-cu-za-{}", row[3] as i64);
        let points = recording::load(&fixtures().join(format!("{stem}.csv"))).unwrap();
        let value = |quantity: &str| {
            points
                .iter()
                .find(|p| p.quantity == quantity)
                .unwrap()
                .value
        };
        assert!(close(value("final_length"), row[5]));
        assert!(close(value("footprint_diameter"), row[9]));
        let w = points.iter().find(|p| p.quantity == "diameter").unwrap();
        assert!(close(w.value, row[10]) && close(w.position, 0.2 * row[4]));
        let experiment =
            stoss::experiment::Experiment::load(&fixtures().join(format!("{stem}.toml"))).unwrap();
        let stoss::experiment::Setup::Taylor(spec) = &experiment.file.setup else {
            panic!("{stem} is not a Taylor test");
        };
        assert!(close(spec.length, row[4]) && close(spec.diameter, row[8]));
        assert!(close(spec.velocity, row[3]) && close(spec.temperature, row[2]));
    }
}

#[test]
fn flow_recordings_are_the_published_numbers() {
    // GOAL: every flow-curve recording is its raw .dat in SI (percent strain -> strain for
    //       Lee-Yeh, MPa -> Pa).
    // REFERENCE: fixtures/real/4340-flow/*.dat, 1e-6 relative.
    let mut checked = 0;
    for entry in std::fs::read_dir(fixtures().join("real/4340-flow")).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if !name.ends_with(".dat") {
            continue;
        }
        let percent = name.ends_with("LY.dat");
        let raw = raw_table(&path);
        let csv = experiment_naming(&name).with_extension("csv");
        let points = recording::load(&csv).unwrap();
        assert_eq!(points.len(), raw.len(), "{name}");
        for (point, row) in points.iter().zip(&raw) {
            let strain = if percent { row[0] / 100.0 } else { row[0] };
            assert!(
                close(point.position, strain.max(0.0))
                    || (strain.abs() < 1e-9 && point.position == 0.0),
                "{name}"
            );
            assert!(close(point.value, row[1] * 1e6), "{name}");
        }
        checked += 1;
    }
    assert_eq!(checked, 10);
}

#[test]
fn aluminium_flow_recordings_are_the_digitised_numbers() {
    // GOAL: every 6061-T6 recording is its raw .dat (the points from 1 % strain on), read in
    //       the unit its header names; the uncertainty is 2 % of the stress.
    // SETUP: fixtures/real/6061-t6-flow/*.dat (space or comma separated) and the experiments
    //        that name them (fixtures/experiments/flow-6061-*.toml).
    // REFERENCE: the raw files; ksi = 6894757.293168361 Pa (Hoge), MPa (the others); 1e-6
    //        relative.
    let mut checked = 0;
    for entry in std::fs::read_dir(fixtures().join("real/6061-t6-flow")).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if !name.ends_with(".dat") {
            continue;
        }
        let raw: Vec<Vec<f64>> = raw_table(&path)
            .into_iter()
            .filter(|row| row[0] >= 0.01)
            .collect();
        let experiment = experiment_naming(&name);
        let scale = if name.contains("Hoge") {
            6_894_757.293_168_361
        } else {
            1e6
        };
        let points = recording::load(&experiment.with_extension("csv")).unwrap();
        assert_eq!(points.len(), raw.len(), "{name}");
        for (point, row) in points.iter().zip(&raw) {
            assert!(close(point.position, row[0]), "{name}");
            assert!(close(point.value, row[1] * scale), "{name}");
            assert!(
                (point.uncertainty / (0.02 * point.value) - 1.0).abs() < 1e-5,
                "{name}"
            );
        }
        checked += 1;
    }
    assert_eq!(checked, 21);
}

#[test]
fn every_bundled_experiment_passes_its_input_checks() {
    // GOAL: the up-front size and unit checks refuse no bundled experiment.
    // SETUP: every fixtures/experiments/*.toml, loaded (parsed, validated, recording read).
    // REFERENCE: Experiment::load succeeds for each.
    let mut count = 0;
    for entry in std::fs::read_dir(fixtures().join("experiments")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) == Some("toml") {
            if let Err(error) = stoss::experiment::Experiment::load(&path) {
                panic!("{}: {error}", path.display());
            }
            count += 1;
        }
    }
    assert!(count >= 20, "{count} experiments");
}

#[test]
fn every_bundled_campaign_and_material_passes_its_input_checks() {
    // GOAL: the plausibility ranges and unit rules refuse no bundled campaign or material
    //       (issue 17). SETUP: every fixtures/campaigns/*.toml and fixtures/materials/*.toml,
    //       and the diagnosis cases' campaigns. REFERENCE: each loads.
    let mut count = 0;
    let mut campaigns: Vec<PathBuf> = std::fs::read_dir(fixtures().join("campaigns"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().and_then(|e| e.to_str()) == Some("toml"))
        .collect();
    for entry in std::fs::read_dir(fixtures().join("diagnosis")).unwrap() {
        let path = entry.unwrap().path().join("campaign.toml");
        if path.exists() {
            campaigns.push(path);
        }
    }
    for path in campaigns {
        if let Err(error) = stoss::fit::Campaign::load(&path) {
            panic!("{}: {error}", path.display());
        }
        count += 1;
    }
    for entry in std::fs::read_dir(fixtures().join("materials")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) == Some("toml") {
            if let Err(error) = stoss::input::material::load_part(&path) {
                panic!("{}: {error}", path.display());
            }
            count += 1;
        }
    }
    assert!(count >= 15, "{count} files");
}

/// A fixture's text with `from` replaced by `to` (each must occur).
fn edited(text: &str, edits: &[(&str, &str)]) -> String {
    let mut text = text.to_string();
    for (from, to) in edits {
        assert!(text.contains(from), "{from} not in the fixture");
        text = text.replacen(from, to, 1);
    }
    text
}

#[test]
fn quantities_with_units_load_as_the_same_si_numbers() {
    // GOAL: a user's experiment, material and recording written with units (mm, m/s, MPa,
    //       GPa, g/cc, a CSV header in mm) load bit for bit as the bundled SI files, and a
    //       unit of the wrong dimension is an error naming file, line and field (issue 17).
    // SETUP: the 4340 Taylor test at 208 m/s and the 4340 JC material, rewritten with units
    //        in a temporary folder.
    // REFERENCE: the bundled SI files: equal set-up, material and recorded points (so equal
    //        simulations).
    use stoss::experiment::Experiment;
    use stoss::input::material;
    let folder = std::env::temp_dir().join(format!("stoss-units-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&folder);
    std::fs::create_dir_all(folder.join("experiments")).unwrap();
    std::fs::create_dir_all(folder.join("materials")).unwrap();
    let read = |name: &str| std::fs::read_to_string(fixtures().join(name)).unwrap();
    let material_text = edited(
        &read("materials/4340-jc.toml"),
        &[
            ("density = 7830.0", "density = \"7.83 g/cc\""),
            ("shear_modulus = 81.8e9", "shear_modulus = \"81.8 GPa\""),
            ("yield_stress = 792.0e6", "yield_stress = \"792.0 MPa\""),
            (
                "hardening_modulus = 510.0e6",
                "hardening_modulus = '510 MPa'",
            ),
            (
                "melting_temperature = 1793.0",
                "melting_temperature = \"1793 K\"",
            ),
            ("bulk_modulus = 159.0e9", "bulk_modulus = \"159 GPa\""),
        ],
    );
    std::fs::write(folder.join("materials/4340-jc.toml"), &material_text).unwrap();
    let experiment_text = edited(
        &read("experiments/taylor-4340-208.toml"),
        &[
            ("length = 2.540000e-02", "length = \"25.4 mm\""),
            ("diameter = 7.620000e-03", "diameter = \"7.62 mm\""),
            ("velocity = 208.0", "velocity = \"0.208 km/s\""),
        ],
    );
    std::fs::write(
        folder.join("experiments/taylor-4340-208.toml"),
        &experiment_text,
    )
    .unwrap();
    // The recording with its lengths in mm (the header carries the units).
    let csv = read("experiments/taylor-4340-208.csv");
    let mut in_mm = String::new();
    for line in csv.lines() {
        let cells: Vec<&str> = line.split(',').collect();
        if line.starts_with('#') || cells.len() != 4 {
            in_mm.push_str(line);
        } else if cells[0] == "quantity" {
            in_mm.push_str("quantity,position [mm],value [mm],uncertainty [mm]");
        } else {
            // Shift the decimal exponent by hand: 2.2479e-02 m -> 2.2479e1 mm.
            let mm = |cell: &str| {
                let (mantissa, exponent) = cell.split_once(['e', 'E']).unwrap_or((cell, "0"));
                format!("{mantissa}e{}", exponent.parse::<i32>().unwrap() + 3)
            };
            in_mm.push_str(&format!(
                "{},{},{},{}",
                cells[0],
                mm(cells[1]),
                mm(cells[2]),
                mm(cells[3])
            ));
        }
        in_mm.push('\n');
    }
    std::fs::write(folder.join("experiments/taylor-4340-208.csv"), &in_mm).unwrap();

    let si = Experiment::load(&fixtures().join("experiments/taylor-4340-208.toml")).unwrap();
    let with_units = Experiment::load(&folder.join("experiments/taylor-4340-208.toml")).unwrap();
    assert_eq!(
        format!("{:?}", si.file.setup),
        format!("{:?}", with_units.file.setup)
    );
    assert_eq!(si.recording, with_units.recording);
    let (_, si_material) = material::load(&fixtures().join("materials/4340-jc.toml")).unwrap();
    let (_, unit_material) = material::load(&folder.join("materials/4340-jc.toml")).unwrap();
    assert_eq!(format!("{si_material:?}"), format!("{unit_material:?}"));

    // A length given as a stress: file, line and field.
    let bad = experiment_text.replace("\"25.4 mm\"", "\"25.4 MPa\"");
    let line = bad.lines().position(|l| l.contains("25.4 MPa")).unwrap() + 1;
    let path = folder.join("experiments/bad.toml");
    std::fs::write(&path, bad).unwrap();
    let error = Experiment::load(&path).unwrap_err().to_string();
    assert!(
        error.contains(&format!("bad.toml:{line}: field `length`")) && error.contains("a stress"),
        "{error}"
    );
    let _ = std::fs::remove_dir_all(&folder);
}

#[test]
fn every_bundled_metal_simulates_and_johnson_cook_ones_match_their_closed_form() {
    // GOAL: the bundled starting materials load and simulate (issue 54, item 7), and a
    //       Johnson-Cook file's constants are what the kernel uses.
    // SETUP: every fixtures/materials/*.toml with a J2 strength, in an isothermal uniaxial
    //        compression at 1000 /s and 298 K recorded at plastic strain 0.1.
    // REFERENCE: for `model = "johnson-cook"` files, the closed form (A + B 0.1^n)(1 + C
    //        ln(1000/e0)) at the reference temperature 298 K, from the file's own numbers;
    //        within 0.2 % (the driver's plastic rate is the imposed rate less the elastic
    //        part's, which at this strain is a fraction of a percent); for the MTS copper file,
    //        the kernel's `MechanicalThresholdStress::COPPER` at the same point, within 0.2 %.
    let folder = std::env::temp_dir().join(format!("stoss-bundled-{}", std::process::id()));
    std::fs::create_dir_all(&folder).unwrap();
    std::fs::write(
        folder.join("flow.toml"),
        "name = \"compression 1000 /s, 298 K\"\nrecording = \"flow.csv\"\n\n[setup]\n\
         kind = \"uniaxial\"\nstrain_rate = 1000.0\ntemperature = 298.0\ncompression = true\n\
         isothermal = true\n",
    )
    .unwrap();
    std::fs::write(
        folder.join("flow.csv"),
        "quantity,position,value,uncertainty\ntrue_stress,0.1,1e8,1e6\n",
    )
    .unwrap();
    let experiment = stoss::experiment::Experiment::load(&folder.join("flow.toml")).unwrap();
    let (mut simulated, mut closed, mut mts) = (0, 0, 0);
    for entry in std::fs::read_dir(fixtures().join("materials")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) != Some("toml") {
            continue;
        }
        let (_, material) = stoss::input::material::load_part(&path).unwrap();
        if material.j2().is_none() {
            continue;
        }
        let outcome = experiment
            .simulate(&material, &stoss::solver::SolverSettings::default())
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let stress = outcome.predicted[0];
        assert!(stress.is_finite() && stress > 0.0, "{}", path.display());
        simulated += 1;
        let text = std::fs::read_to_string(&path).unwrap();
        let file: toml::Table = toml::from_str(&text).unwrap();
        let strength = file["strength"].as_table().unwrap();
        if strength.get("model").and_then(|m| m.as_str()) == Some("mechanical-threshold-stress") {
            // The file transcribes the kernel's published copper set (Follansbee & Kocks).
            let expected = stoss_kernel::strength::MechanicalThresholdStress::COPPER
                .flow_stress(0.1, 1000.0, 298.0)
                .value;
            assert!(
                (stress / expected - 1.0).abs() < 2e-3,
                "{}: simulated {stress:.6e}, the kernel's copper set {expected:.6e}",
                path.display()
            );
            mts += 1;
        }
        if strength.get("model").and_then(|m| m.as_str()) != Some("johnson-cook")
            || strength["reference_temperature"].as_float() != Some(298.0)
        {
            continue;
        }
        let number = |key: &str| strength[key].as_float().unwrap();
        let expected = (number("yield_stress")
            + number("hardening_modulus") * 0.1f64.powf(number("hardening_exponent")))
            * (1.0 + number("rate_sensitivity") * (1000.0 / number("reference_rate")).ln());
        assert!(
            (stress / expected - 1.0).abs() < 2e-3,
            "{}: simulated {stress:.6e}, closed form {expected:.6e}",
            path.display()
        );
        closed += 1;
    }
    assert!(
        simulated >= 16 && closed >= 7 && mts >= 1,
        "{simulated} simulated, {closed} closed forms, {mts} MTS"
    );
    std::fs::remove_dir_all(&folder).unwrap();
}

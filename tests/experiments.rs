//! Experiments against published numbers and closed forms.

use std::path::PathBuf;
use stoss::experiment::Experiment;
use stoss::input::material;
use stoss::solver::SolverSettings;

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../fixtures")
        .join(name)
}

fn run(name: &str) -> (Experiment, stoss::experiment::Outcome) {
    let experiment = Experiment::load(&fixture(&format!("experiments/{name}.toml"))).unwrap();
    let (_, material) = material::load(&experiment.default_material_path().unwrap()).unwrap();
    let outcome = experiment
        .simulate(&material.into(), &SolverSettings::default())
        .unwrap();
    (experiment, outcome)
}

fn predicted(
    experiment: &Experiment,
    outcome: &stoss::experiment::Outcome,
    quantity: &str,
) -> (f64, f64) {
    let index = experiment
        .recording
        .iter()
        .position(|p| p.quantity == quantity)
        .unwrap();
    (outcome.predicted[index], experiment.recording[index].value)
}

#[test]
fn real_4340_taylor_tests_with_the_published_johnson_cook_constants() {
    // GOAL: the solver with the published JC constants reproduces Johnson & Cook's (1983) 4340
    //       Taylor tests: final length Lf, footprint Df and diameter W at 0.2 L0.
    // SETUP: fixtures/experiments/taylor-4340-{208,282,343}.toml, 8 elements across the radius
    //        (mesh-converged to < 0.1 % in Lf), frictionless anvil, adiabatic heating.
    // REFERENCE: measured Lf 22.479 / 10.706 / 6.545 mm, W 8.32 / 8.70 / 9.50 mm.
    //   Measured here: Lf +0.3 %, -3.4 %, -7.0 %; W -1.3 %, +0.6 %, -0.5 %. The 208 m/s rod
    //   (L/D 3.3) is within the 3 % aim; the short, faster rods (L/D 1.7 and 1.1, plastic rates
    //   ~1e5 /s) come out too short: JC's log-rate term is too soft there (see docs/solver.md).
    //   Tolerances encode that measured state so that a regression cannot hide.
    let cases = [
        ("taylor-4340-208", 0.03),
        ("taylor-4340-282", 0.045),
        ("taylor-4340-343", 0.08),
    ];
    for (name, length_tolerance) in cases {
        let (experiment, outcome) = run(name);
        let (lf, lf_measured) = predicted(&experiment, &outcome, "final_length");
        assert!(
            (lf / lf_measured - 1.0).abs() < length_tolerance,
            "{name}: Lf {lf} vs {lf_measured}"
        );
        let w_index = 2; // the third recorded point is W at 0.2 L0
        let (w, w_measured) = (
            outcome.predicted[w_index],
            experiment.recording[w_index].value,
        );
        assert!(
            (w / w_measured - 1.0).abs() < 0.03,
            "{name}: W {w} vs {w_measured}"
        );
        let energy = outcome.energy.unwrap();
        assert!(
            energy.error_percent().abs() <= 1.0,
            "{name}: energy error {}",
            energy.error_percent()
        );
    }
}

#[test]
fn seed_001_tension_cylinder_reproduces_the_analytical_flow_stress() {
    // GOAL: seed 001 sec. 3.4.1: the FE cylinder's mid-section stress follows the analytical
    //       JC flow stress at 1, 10, 100 and 1000 /s (implicit rate treatment).
    // SETUP: 4 mm x 1 mm radius, 0.2 mm elements; mass scaling at low rates.
    // REFERENCE: JC at the nominal rate (fixtures/experiments/tension-4340-*.csv), true strain
    //   0.02-0.10 (uniform deformation). Tolerance 0.2 % (measured <= 0.02 %).
    for rate in [1, 10, 100, 1000] {
        let (experiment, outcome) = run(&format!("tension-4340-{rate}"));
        for (point, value) in experiment.recording.iter().zip(&outcome.predicted) {
            assert!(
                (value / point.value - 1.0).abs() < 2e-3,
                "{rate}/s at {}: {value} vs {}",
                point.position,
                point.value
            );
        }
        assert!(outcome.energy.unwrap().error_percent().abs() <= 1.0);
    }
}

#[test]
fn the_published_constants_fit_the_johnson_cook_dynamic_tension_curves() {
    // GOAL: the uniaxial kind reproduces the dynamic curves the constants were fitted to.
    // SETUP: JC 4340 constants against the Johnson & Cook (1985) tension curves at 570 /s
    //        (298 K), 604 /s (500 K) and 650 /s (735 K), adiabatic, kernel uniaxial driver.
    // REFERENCE: the digitised curves for plastic strain >= 0.05, where the published fit holds
    //   to 5.2 % (570 /s), 4.5 % (604 /s), 5.0 % (650 /s). Below 0.05 JC's B eps^0.26 rises far
    //   faster than the measured yield transient (up to +21 % at 0.002).
    //   (Not tested here, reported in docs/solver.md: the 0.002 /s curve lies up to 21 % from
    //   JC, whose rate factor is 1 below 1 /s, and the Lee-Yeh compression curves 12-26 %,
    //   a different temper.)
    for name in [
        "flow-4340-jc-tension-570s-298K",
        "flow-4340-jc-tension-604s-500K",
        "flow-4340-jc-tension-650s-735K",
    ] {
        let (experiment, outcome) = run(name);
        let window = experiment
            .recording
            .iter()
            .zip(&outcome.predicted)
            .filter(|(p, _)| p.position >= 0.05);
        for (point, value) in window {
            assert!(
                (value / point.value - 1.0).abs() < 0.06,
                "{name} at {}: {value} vs {}",
                point.position,
                point.value
            );
        }
    }
}

#[test]
fn a_value_with_a_unit_in_an_experiment_is_read_or_named_with_its_line() {
    // GOAL: a number given with a unit is read in SI; one of the wrong dimension, or text that
    //       is no quantity, is an error naming the field and its line, not only the [setup]
    //       table (issue 17).
    // SETUP: the 343 m/s Taylor fixture with `velocity = "130 m/s"`, `"130 MPa"` and `"fast"`.
    // REFERENCE: 130.0 m/s; errors naming the file, the line of `velocity` and the field.
    let text = std::fs::read_to_string(fixture("experiments/taylor-4340-343.toml"))
        .unwrap()
        .replace(
            "\"taylor-4340-343.csv",
            &format!("\"{}", fixture("experiments/taylor-4340-343.csv").display()),
        )
        .replace("\"../", &format!("\"{}/", fixture("").display()));
    let line_of_velocity = text
        .lines()
        .position(|l| l.starts_with("velocity"))
        .unwrap()
        + 1;
    let directory = std::env::temp_dir().join(format!("stoss-unit-{}", std::process::id()));
    std::fs::create_dir_all(&directory).unwrap();
    let path = directory.join("taylor.toml");
    let load_with = |velocity: &str| {
        let edited: String = text
            .lines()
            .map(|l| {
                if l.starts_with("velocity") {
                    format!("velocity = {velocity}")
                } else {
                    l.to_string()
                }
            })
            .collect::<Vec<_>>()
            .join("\n");
        std::fs::write(&path, edited).unwrap();
        Experiment::load(&path)
    };
    let experiment = load_with("\"130 m/s\"").unwrap();
    assert!(format!("{:?}", experiment.file.setup).contains("velocity: 130.0"));
    let error = load_with("\"130 MPa\"").unwrap_err().to_string();
    assert!(
        error.contains(&format!("taylor.toml:{line_of_velocity}: field `velocity`"))
            && error.contains("a stress")
            && error.contains("m/s"),
        "{error}"
    );
    let error = load_with("\"fast\"").unwrap_err().to_string();
    assert!(
        error.contains(&format!(
            "taylor.toml:{line_of_velocity}: field `velocity`: invalid type: string \"fast\""
        )),
        "{error}"
    );
    std::fs::remove_dir_all(&directory).unwrap();
}

/// The 4340 JC 570 /s tension curve, whose experiment file the recording tests copy.
const TENSION: &str = "flow-4340-jc-tension-570s-298K";

/// A fresh temporary folder and the tension experiment's file text with its paths absolute
/// and its recording renamed to `recording` (a file of that folder).
fn tension_copy(tag: &str, recording: &str) -> (PathBuf, String) {
    let directory = std::env::temp_dir().join(format!("stoss-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&directory).unwrap();
    let toml = std::fs::read_to_string(fixture(&format!("experiments/{TENSION}.toml"))).unwrap();
    let toml = toml
        .replace("\"../", &format!("\"{}/", fixture("").display()))
        .replace(
            &format!("recording = \"{TENSION}.csv\""),
            &format!("recording = \"{recording}\""),
        );
    (directory, toml)
}

#[test]
fn a_necking_tail_is_trimmed_on_request_and_the_run_says_so() {
    // GOAL: issue 54, item 4: `trim_at_maximum = true` leaves out the `true_stress` points
    //       recorded after the largest stress (necking), and the run's report says how many.
    // SETUP: the 4340 JC 570 /s tension curve with three points appended beyond its last
    //        strain, falling to 90 %, 80 % and 70 % of its largest stress; loaded with and
    //        without the option.
    // REFERENCE: without it every point is kept; with it the three are dropped (the largest
    //            stress is the original curve's) and the report counts 3.
    let (directory, toml) = tension_copy("trim", "necking.csv");
    let name = TENSION;
    let original = Experiment::load(&fixture(&format!("experiments/{name}.toml"))).unwrap();
    let (last, peak) = original
        .recording
        .iter()
        .fold((0.0_f64, 0.0_f64), |(e, s), p| {
            (e.max(p.position), s.max(p.value))
        });
    let mut csv = std::fs::read_to_string(fixture(&format!("experiments/{name}.csv"))).unwrap();
    for (k, fraction) in [0.9, 0.8, 0.7].iter().enumerate() {
        csv.push_str(&format!(
            "true_stress,{:e},{:e},{:e}\n",
            last + 0.02 * (k + 1) as f64,
            fraction * peak,
            0.02 * peak
        ));
    }
    std::fs::write(directory.join("necking.csv"), csv).unwrap();
    let kept_path = directory.join("kept.toml");
    std::fs::write(&kept_path, &toml).unwrap();
    let kept = Experiment::load(&kept_path).unwrap();
    assert_eq!(kept.recording.len(), original.recording.len() + 3);
    let trimmed_path = directory.join("trimmed.toml");
    std::fs::write(
        &trimmed_path,
        toml.replace("[setup]\n", "[setup]\ntrim_at_maximum = true\n"),
    )
    .unwrap();
    let trimmed = Experiment::load(&trimmed_path).unwrap();
    assert_eq!(trimmed.recording.len(), original.recording.len());
    let (_, material) = material::load(&trimmed.default_material_path().unwrap()).unwrap();
    let outcome = trimmed
        .simulate(&material.into(), &SolverSettings::default())
        .unwrap();
    let report = outcome.report.expect("a report").text;
    assert!(
        report.contains("3 recorded points after the largest stress were left out"),
        "{report}"
    );
    std::fs::remove_dir_all(&directory).unwrap();
}

#[test]
fn an_engineering_curve_is_read_as_true_stress_and_strain() {
    // GOAL: issue 54, item 4: a curve recorded as engineering stress and strain
    //       (`recorded_measure = "engineering"`) is converted on load to true stress and true
    //       total strain, and the run says so; without `recorded_strain = "total"` it is
    //       refused naming the field.
    // SETUP: true total strains 0.01..0.20 and stresses 800..1000 MPa written as engineering
    //        points e = exp(eps) - 1, s = sigma / (1 + e), in tension.
    // REFERENCE: the true points back to 1e-12 relative (Dieter sec. 8-2).
    let (directory, toml) = tension_copy("engineering", "engineering.csv");
    assert!(toml.contains("compression = false") || !toml.contains("compression = true"));
    let truth: Vec<(f64, f64)> = (1..=20)
        .map(|k| (0.01 * k as f64, 800.0e6 + 10.0e6 * k as f64))
        .collect();
    let mut csv = String::from("quantity,position,value,uncertainty\n");
    for (strain, stress) in &truth {
        let e = strain.exp() - 1.0;
        csv.push_str(&format!(
            "true_stress,{:e},{:e},{:e}\n",
            e,
            stress / (1.0 + e),
            1.0e7
        ));
    }
    std::fs::write(directory.join("engineering.csv"), csv).unwrap();
    let path = directory.join("engineering.toml");
    std::fs::write(
        &path,
        toml.replace(
            "[setup]\n",
            "[setup]\nrecorded_measure = \"engineering\"\nrecorded_strain = \"total\"\n",
        ),
    )
    .unwrap();
    let experiment = Experiment::load(&path).unwrap();
    for (point, (strain, stress)) in experiment.recording.iter().zip(&truth) {
        assert!((point.position / strain - 1.0).abs() < 1e-12, "{point:?}");
        assert!((point.value / stress - 1.0).abs() < 1e-12, "{point:?}");
    }
    let (_, material) = material::load(&experiment.default_material_path().unwrap()).unwrap();
    let outcome = experiment
        .simulate(&material.into(), &SolverSettings::default())
        .unwrap();
    assert!(outcome
        .report
        .expect("a report")
        .text
        .contains("converted on load to true stress"));
    std::fs::write(
        &path,
        toml.replace("[setup]\n", "[setup]\nrecorded_measure = \"engineering\"\n"),
    )
    .unwrap();
    let error = Experiment::load(&path).unwrap_err().to_string();
    assert!(
        error.contains("recorded_measure") && error.contains("total strain"),
        "{error}"
    );
    // A compressive engineering strain of 0.995 is a true strain of 5.3: above the range that
    // bounds the driver's steps, refused at its line rather than run.
    std::fs::write(
        directory.join("engineering.csv"),
        "quantity,position,value,uncertainty\ntrue_stress,0.1,9e8,1e7\ntrue_stress,0.995,9e8,1e7\n",
    )
    .unwrap();
    std::fs::write(
        &path,
        toml.replace(
            "[setup]\n",
            "[setup]\nrecorded_measure = \"engineering\"\nrecorded_strain = \"total\"\n",
        )
        .replace("compression = false", "compression = true"),
    )
    .unwrap();
    let error = Experiment::load(&path).unwrap_err().to_string();
    assert!(
        error.contains("engineering.csv:3: field `position`")
            && error.contains("true strain of 5.298"),
        "{error}"
    );
    std::fs::remove_dir_all(&directory).unwrap();
}

#[test]
fn a_flow_curve_in_total_strain_gives_the_plastic_strain_curve() {
    // GOAL: a flow curve recorded against true total strain (what a test machine gives), with
    //       `recorded_strain = "total"`, is compared at the right points (issue 17).
    // SETUP: the 4340 JC 570 /s tension curve, isothermal; its predictions at the recorded
    //        plastic strains; the same stresses placed at total strain eps_p + sigma/E
    //        (E = 9KG/(3K+G) of the material's linear EoS and shear modulus).
    // REFERENCE: the plastic-strain predictions, within 0.1 % (the driver's strain step).
    let directory = std::env::temp_dir().join(format!("stoss-total-{}", std::process::id()));
    std::fs::create_dir_all(&directory).unwrap();
    let name = "flow-4340-jc-tension-570s-298K";
    let toml = std::fs::read_to_string(fixture(&format!("experiments/{name}.toml"))).unwrap();
    let root = fixture("");
    let toml = toml.replace("\"../", &format!("\"{}/", root.display()));
    let plastic_path = directory.join("plastic.toml");
    std::fs::write(
        &plastic_path,
        toml.replace("isothermal = false", "isothermal = true")
            .replace(
                &format!("recording = \"{name}.csv\""),
                "recording = \"plastic.csv\"",
            ),
    )
    .unwrap();
    std::fs::copy(
        fixture(&format!("experiments/{name}.csv")),
        directory.join("plastic.csv"),
    )
    .unwrap();
    let plastic = Experiment::load(&plastic_path).unwrap();
    let (_, material) = material::load(&plastic.default_material_path().unwrap()).unwrap();
    let material: stoss_kernel::PartMaterial = material.into();
    let reference = plastic
        .simulate(&material, &SolverSettings::default())
        .unwrap()
        .predicted;
    // E of the 4340 file: G 81.8 GPa, K 159 GPa.
    let (g, k) = (81.8e9, 159.0e9);
    let youngs = 9.0 * k * g / (3.0 * k + g);
    let mut csv = String::from("quantity,position,value,uncertainty\n");
    for (point, stress) in plastic.recording.iter().zip(&reference) {
        csv.push_str(&format!(
            "true_stress,{:e},{:e},{:e}\n",
            point.position + stress / youngs,
            stress,
            point.uncertainty
        ));
    }
    std::fs::write(directory.join("total.csv"), csv).unwrap();
    let total_path = directory.join("total.toml");
    std::fs::write(
        &total_path,
        toml.replace(
            "isothermal = false",
            "isothermal = true\nrecorded_strain = \"total\"",
        )
        .replace(
            &format!("recording = \"{name}.csv\""),
            "recording = \"total.csv\"",
        ),
    )
    .unwrap();
    let total = Experiment::load(&total_path).unwrap();
    let outcome = total
        .simulate(&material, &SolverSettings::default())
        .unwrap();
    for ((point, value), expected) in total
        .recording
        .iter()
        .zip(&outcome.predicted)
        .zip(&reference)
    {
        assert!(
            (value / expected - 1.0).abs() < 1e-3,
            "at total strain {}: {value} vs {expected}",
            point.position
        );
    }
    assert!(outcome.report.unwrap().text.contains("total strain"));
    std::fs::remove_dir_all(&directory).unwrap();
}

#[test]
fn a_rod_or_bar_in_the_wrong_length_unit_is_refused_before_it_runs() {
    // GOAL: a unit slip in a Taylor rod or Hopkinson bar is an error up front, not a runaway.
    // SETUP: the 208 m/s Taylor fixture with `length = 25.4` (m for mm); the 1000 /s SHPB
    //        fixture with `incident_length = 500.0` (mm for m); the Taylor fixture with
    //        a 2 m rod with `radial_elements = 200` (plausible lengths, ten million elements);
    //        the SHPB fixture with a 2 m specimen of 64 radial elements (plausible lengths,
    //        three million specimen elements at a fifth of the bars' step).
    // REFERENCE: Experiment::load fails, naming the field: the slips as outside the plausible
    //        range of a length, the huge mesh by its estimated run size.
    let directory = std::env::temp_dir().join(format!("stoss-slip-{}", std::process::id()));
    std::fs::create_dir_all(&directory).unwrap();
    // (fixture, edits (key, value), what the error says)
    type Case<'a> = (&'a str, &'a [(&'a str, &'a str)], &'a str);
    let cases: [Case; 4] = [
        (
            "taylor-4340-208",
            &[("length", "25.4")],
            "plausible range of a length",
        ),
        (
            "shpb-4340-1000",
            &[("incident_length", "500.0")],
            "plausible range of a length",
        ),
        // Too fine a mesh on a rod of the right length: the error names the mesh, not the
        // length (issue 52, item 3: it once named `length`).
        (
            "taylor-4340-208",
            &[("radial_elements", "200")],
            "needs at least",
        ),
        (
            "shpb-4340-1000",
            &[
                ("specimen_length", "2.0"),
                ("specimen_radial_elements", "64"),
            ],
            "needs at least",
        ),
    ];
    for (case, (name, edits, says)) in cases.iter().enumerate() {
        let text = std::fs::read_to_string(fixture(&format!("experiments/{name}.toml"))).unwrap();
        let bad: String = text
            .lines()
            .map(|l| {
                let key = l.split('=').next().map(str::trim);
                match edits.iter().find(|(k, _)| Some(*k) == key) {
                    Some((k, v)) => format!("{k} = {v}"),
                    None => l.to_string(),
                }
            })
            .collect::<Vec<_>>()
            .join("\n");
        assert_ne!(bad, text, "{name}");
        let path = directory.join(format!("{name}-{case}.toml"));
        std::fs::write(&path, bad).unwrap();
        let error = Experiment::load(&path).unwrap_err().to_string();
        let field = edits[0].0;
        assert!(
            error.contains(&format!("{field}`: ")) && error.contains(says),
            "{name}: {error}"
        );
    }
    std::fs::remove_dir_all(&directory).unwrap();
}

#[test]
fn the_quarter_3d_taylor_model_agrees_with_the_axisymmetric_one_and_writes_hexahedra() {
    // GOAL: the Taylor kind's 3D option (geometry = "quarter-3d") measures the same final
    //       shape as the axisymmetric model, and its final state renders as VTK hexahedra
    //       (issue 17: 3D runs write VTK too).
    // SETUP: the 4340 Taylor test at 208 m/s, 4 elements across the radius, both models.
    // REFERENCE: the axisymmetric model: final length within 0.5 %, footprint within 2 %
    //   (measured at 8 elements: 22.559 vs 22.554 mm, 10.648 vs 10.686 mm); the .vtu holds
    //   one VTK_HEXAHEDRON (type 12) per element and a 3D displacement per node.
    let directory = std::env::temp_dir().join(format!("stoss-3d-{}", std::process::id()));
    std::fs::create_dir_all(&directory).unwrap();
    let text = std::fs::read_to_string(fixture("experiments/taylor-4340-208.toml"))
        .unwrap()
        .replace(
            "\"taylor-4340-208.csv",
            &format!("\"{}", fixture("experiments/taylor-4340-208.csv").display()),
        )
        .replace("\"../", &format!("\"{}/", fixture("").display()))
        .replace("radial_elements = 8", "radial_elements = 4");
    let outcome_of = |geometry: &str| {
        let path = directory.join(format!("{geometry}.toml"));
        std::fs::write(
            &path,
            text.replace(
                "radial_elements = 4",
                &format!("radial_elements = 4\ngeometry = \"{geometry}\""),
            ),
        )
        .unwrap();
        let experiment = Experiment::load(&path).unwrap();
        let (_, material) = material::load(&experiment.default_material_path().unwrap()).unwrap();
        experiment
            .simulate(&material.into(), &SolverSettings::default())
            .unwrap()
    };
    let flat = outcome_of("axisymmetric");
    let solid = outcome_of("quarter-3d");
    let summary = |o: &stoss::experiment::Outcome, name: &str| o.summary_value(name).unwrap();
    for (name, tolerance) in [("final_length", 0.005), ("footprint_diameter", 0.02)] {
        let (a, b) = (summary(&flat, name), summary(&solid, name));
        assert!(
            (b / a - 1.0).abs() < tolerance,
            "{name}: 3D {b} vs axisymmetric {a}"
        );
    }
    let field = solid.field_3d.as_ref().unwrap();
    let vtu = stoss::report::vtk::render_hexahedral(field);
    assert!(vtu.contains(&format!(
        "NumberOfPoints=\"{}\" NumberOfCells=\"{}\"",
        field.mesh.nodes.len(),
        field.mesh.elements.len()
    )));
    let types = vtu
        .split("Name=\"types\" format=\"ascii\">")
        .nth(1)
        .and_then(|rest| rest.split("</DataArray>").next())
        .unwrap();
    let types: Vec<&str> = types.split_whitespace().collect();
    assert_eq!(types.len(), field.mesh.elements.len());
    assert!(types.iter().all(|t| *t == "12"));
    assert!(flat.field_3d.is_none() && solid.field.is_none());
    std::fs::remove_dir_all(&directory).unwrap();
}

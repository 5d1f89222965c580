//! The split Hopkinson compression bar (`shpb` experiments) and the penalty contact between
//! parts it rests on.

use std::path::PathBuf;
use stoss::experiment::shpb::{Analysis, ShpbResult, ShpbSpec};
use stoss::experiment::{Experiment, Setup};
use stoss::input::{material, recording};
use stoss::measure::interpolate;
use stoss::mesh::{Grading, QuadMesh};
use stoss::solver::{
    Amplitude, AxisymmetricModel, AxisymmetricRun, ContactPair, SolverSettings, VelocityConstraint,
};

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../fixtures")
        .join(name)
}

/// Mean of `values` over the analysis grid points with `start <= t <= end`.
fn mean_over(time: &[f64], values: &[f64], start: f64, end: f64) -> f64 {
    let window: Vec<f64> = time
        .iter()
        .zip(values)
        .filter(|(t, _)| **t >= start && **t <= end)
        .map(|(_, v)| *v)
        .collect();
    window.iter().sum::<f64>() / window.len() as f64
}

#[test]
fn an_impedance_matched_elastic_specimen_transmits_the_incident_pulse() {
    // GOAL: with a "specimen" that is a piece of bar (same material, same diameter), the bar
    //       system is one long bar cut twice: the transmitted pulse equals the incident one and
    //       nothing is reflected, so wave separation, gauges and the two contact interfaces are
    //       transparent.
    // SETUP: default bars (12.7 mm, E 200 GPa, 8000 kg/m^3, nu 0.29, 500 mm, gauges at 250 mm),
    //        specimen of the bar material 12.7 mm x 4 mm, friction 0.05, striker 17 m/s x 200 mm
    //        (pulse 80 us, 5 us rise).
    // REFERENCE: 1D elastic waves: eps_T = eps_I = V / (2 c0) = 1.7e-3, eps_R = 0.
    //   Measured: incident plateau (arrival + 15 us .. + 75 us) 0.01 % from theory, the
    //   transmitted one 0.06 % below it, the impulses (integrals of the pulses) 0.5 % apart,
    //   the reflected plateau 0.04 % of the incident; tolerances 2 %, 2 %, 3 % and 3 %
    //   (Pochhammer-Chree ringing is not corrected). Energy error <= 1 % (measured 0.044 %).
    let mut spec = ShpbSpec::new(17.0);
    spec.specimen_diameter = spec.bar_diameter;
    let bar = spec.bar_material();
    let (result, run, _) = spec.run(&bar, &SolverSettings::default()).unwrap();
    let w = &result.waves;
    let arrival = spec.arrival_time();
    let (start, end) = (arrival + 15.0e-6, arrival + 75.0e-6);
    let incident = mean_over(&w.time, &w.incident, start, end);
    let transmitted = mean_over(&w.time, &w.transmitted, start, end);
    let reflected = mean_over(&w.time, &w.reflected, start, end);
    let theory = 0.5 * spec.striker_velocity / spec.bar_wave_speed();
    let impulse = |values: &[f64]| values.iter().sum::<f64>();
    let (impulse_i, impulse_t) = (impulse(&w.incident), impulse(&w.transmitted));
    eprintln!(
        "incident {incident:.5e} (theory {theory:.5e}), transmitted {transmitted:.5e}, reflected {reflected:.3e}, impulse ratio {:.5}, energy error {:.4} %",
        impulse_t / impulse_i,
        run.energy().error_percent()
    );
    assert!(
        (incident / theory - 1.0).abs() < 0.02,
        "{incident} vs {theory}"
    );
    assert!(
        (transmitted / incident - 1.0).abs() < 0.02,
        "{transmitted} vs {incident}"
    );
    assert!((impulse_t / impulse_i - 1.0).abs() < 0.03);
    assert!(reflected.abs() < 0.03 * incident, "reflected {reflected}");
    assert!(run.energy().error_percent().abs() <= 1.0);
}

/// Load a bundled SHPB experiment and run it with its default (truth) material.
fn run_fixture(name: &str) -> (Experiment, ShpbSpec, ShpbResult, AxisymmetricRun) {
    let experiment = Experiment::load(&fixture(&format!("experiments/{name}.toml"))).unwrap();
    let Setup::Shpb(spec) = experiment.file.setup.clone() else {
        panic!("{name} is not an shpb experiment");
    };
    let (_, material) = material::load(&experiment.default_material_path().unwrap()).unwrap();
    let (result, run, _) = spec.run(&material, &SolverSettings::default()).unwrap();
    (experiment, spec, result, run)
}

/// The analysis window after the ring-up: 25 us after the pulse reaches the specimen, to
/// 5 us before its plateau ends.
fn settled(spec: &ShpbSpec) -> (f64, f64) {
    let arrival = spec.arrival_time();
    (arrival + 25.0e-6, arrival + spec.pulse_duration() - 5.0e-6)
}

/// Largest relative difference of two analyses' stresses over the settled window (relative
/// to the 3-wave stress), and the mean absolute one.
fn stress_difference(result: &ShpbResult, a: &[f64], b: &[f64], spec: &ShpbSpec) -> (f64, f64) {
    let (start, end) = settled(spec);
    let t = &result.three_wave.time;
    let deviations: Vec<f64> = (0..t.len())
        .filter(|&k| t[k] >= start && t[k] <= end)
        .map(|k| ((a[k] - b[k]) / result.three_wave.stress[k]).abs())
        .collect();
    (
        deviations.iter().copied().fold(0.0, f64::max),
        deviations.iter().sum::<f64>() / deviations.len() as f64,
    )
}

/// The specimen's own mid-plane engineering stress on the 3-wave time grid.
fn specimen_engineering_stress(result: &ShpbResult) -> Vec<f64> {
    let three = &result.three_wave;
    three
        .time
        .iter()
        .map(|&t| interpolate(&result.specimen_stress, t))
        .collect()
}

/// The predictions at the recorded points, from the spec's analysis.
fn predictions(experiment: &Experiment, spec: &ShpbSpec, result: &ShpbResult) -> Vec<f64> {
    let curve = result.analysis(spec.analysis).curve();
    experiment
        .recording
        .iter()
        .map(|p| interpolate(&curve, p.position))
        .collect()
}

/// Check the synthetic recording against the run: the noise-free truth beside it equals the
/// prediction, and the noisy recording scatters about it by about the stated 1 %.
fn check_against_truth(name: &str, experiment: &Experiment, predicted: &[f64]) {
    let truth = recording::load(&fixture(&format!("experiments/{name}.truth.csv"))).unwrap();
    assert_eq!(truth.len(), predicted.len());
    let mut squares = 0.0;
    for ((point, truth), predicted) in experiment.recording.iter().zip(&truth).zip(predicted) {
        assert_eq!(point.position, truth.position);
        assert!(
            (predicted / truth.value - 1.0).abs() < 1e-3,
            "{name} at {}: {predicted} vs truth {}",
            truth.position,
            truth.value
        );
        squares += ((point.value - truth.value) / point.uncertainty).powi(2);
    }
    let rms = (squares / truth.len() as f64).sqrt();
    assert!(
        (0.3..2.0).contains(&rms),
        "{name}: noise rms {rms} sigma (stated 1 %)"
    );
}

#[test]
fn the_4340_bar_at_1000_per_s_is_in_equilibrium_and_its_analyses_agree() {
    // GOAL: the full SHPB with a plastically flowing 4340 specimen: the bar-gauge analysis gives
    //       the specimen's own stress (force equilibrium), the 1- and 2-wave stresses agree after
    //       the ring-up, the test runs near its nominal rate, and the bundled synthetic recording
    //       is this simulation plus its stated noise.
    // SETUP: fixtures/experiments/shpb-4340-1000.toml (published JC 4340, striker 16.5 m/s x
    //        200 mm, specimen 6 x 4 mm, friction 0.05); window arrival + 25 us .. + 75 us.
    // REFERENCE: the force through the specimen's mid-plane element row over its initial area
    //   (ShpbResult::specimen_stress). Measured: 3-wave within 1.70 % (max) and 0.49 % (mean);
    //   |1-wave - 2-wave| <= 3.37 % (max), 0.90 % (mean), both relative to the 3-wave stress
    //   (the bars' Pochhammer-Chree ringing is not corrected); mean rate 981 /s. Tolerances:
    //   3 % / 1 %, 5 % / 2 %, rate within 20 % of 1000 /s; energy error <= 1 % (measured
    //   0.018 %); truth CSV within 0.1 %.
    let name = "shpb-4340-1000";
    let (experiment, spec, result, run) = run_fixture(name);
    let specimen = specimen_engineering_stress(&result);
    let (equilibrium_max, equilibrium_mean) =
        stress_difference(&result, &result.three_wave.stress, &specimen, &spec);
    let (waves_max, waves_mean) = stress_difference(
        &result,
        &result.one_wave.stress,
        &result.two_wave.stress,
        &spec,
    );
    let rate = result.analysis(spec.analysis).mean_strain_rate();
    eprintln!(
        "{name}: 3-wave vs specimen max {:.2} % mean {:.2} %; 1- vs 2-wave max {:.2} % mean {:.2} %; rate {rate:.0} /s; max strain {:.4}; energy error {:.4} %",
        100.0 * equilibrium_max,
        100.0 * equilibrium_mean,
        100.0 * waves_max,
        100.0 * waves_mean,
        result.analysis(spec.analysis).max_strain(),
        run.energy().error_percent()
    );
    assert!(equilibrium_max < 0.03 && equilibrium_mean < 0.01);
    assert!(waves_max < 0.05 && waves_mean < 0.02);
    assert!((rate / 1000.0 - 1.0).abs() < 0.2, "rate {rate}");
    assert!(run.energy().error_percent().abs() <= 1.0);
    check_against_truth(name, &experiment, &predictions(&experiment, &spec, &result));
}

#[test]
fn the_4340_bar_at_2500_per_s_runs_at_its_nominal_rate() {
    // GOAL: the high-rate fixture reaches its nominal rate, stays in equilibrium and matches
    //       its synthetic recording.
    // SETUP: fixtures/experiments/shpb-4340-2500.toml (striker 25 m/s, 3-wave analysis).
    // REFERENCE: nominal 2500 /s and the specimen's mid-plane force as above. Measured: mean
    //   rate 2555 /s; 3-wave vs specimen 3.44 % (max, the early ringing) and 0.70 % (mean);
    //   1- vs 2-wave 3.98 % / 1.05 %. Tolerances: rate within 20 %, 5 % / 1.5 %, 6 % / 2 %,
    //   energy error <= 1 % (measured 0.011 %), truth CSV within 0.1 %.
    let name = "shpb-4340-2500";
    let (experiment, spec, result, run) = run_fixture(name);
    assert_eq!(spec.analysis, Analysis::ThreeWave);
    let specimen = specimen_engineering_stress(&result);
    let (equilibrium_max, equilibrium_mean) =
        stress_difference(&result, &result.three_wave.stress, &specimen, &spec);
    let rate = result.analysis(spec.analysis).mean_strain_rate();
    let (waves_max, waves_mean) = stress_difference(
        &result,
        &result.one_wave.stress,
        &result.two_wave.stress,
        &spec,
    );
    eprintln!(
        "{name}: 3-wave vs specimen max {:.2} % mean {:.2} %; 1- vs 2-wave max {:.2} % mean {:.2} %; rate {rate:.0} /s; max strain {:.4}; energy error {:.4} %",
        100.0 * equilibrium_max,
        100.0 * equilibrium_mean,
        100.0 * waves_max,
        100.0 * waves_mean,
        result.analysis(spec.analysis).max_strain(),
        run.energy().error_percent()
    );
    assert!((rate / 2500.0 - 1.0).abs() < 0.2, "rate {rate}");
    assert!(equilibrium_max < 0.05 && equilibrium_mean < 0.015);
    assert!(waves_max < 0.06 && waves_mean < 0.02);
    assert!(run.energy().error_percent().abs() <= 1.0);
    check_against_truth(name, &experiment, &predictions(&experiment, &spec, &result));
}

#[test]
fn a_pulse_too_long_for_the_gauges_is_rejected_with_file_line_and_field() {
    // GOAL: wave separation needs non-overlapping pulses at the gauges; a spec that breaks
    //       this is an input error, not a wrong curve.
    // SETUP: the 1000 /s fixture with a 300 mm striker (pulse 120 us > 2 d_i / c0 = 100 us).
    // REFERENCE: the error names the file, the line of `striker_length` and the field.
    let text = std::fs::read_to_string(fixture("experiments/shpb-4340-1000.toml")).unwrap();
    let bad = text.replace("striker_length = 0.2", "striker_length = 0.3");
    assert_ne!(bad, text);
    let directory = std::env::temp_dir().join(format!("stoss-shpb-{}", std::process::id()));
    std::fs::create_dir_all(&directory).unwrap();
    let path = directory.join("bad.toml");
    std::fs::write(&path, &bad).unwrap();
    let error = Experiment::load(&path).unwrap_err().to_string();
    let line = bad
        .lines()
        .position(|l| l.starts_with("striker_length"))
        .unwrap()
        + 1;
    assert!(
        error.contains(&format!("bad.toml:{line}: field `striker_length`")),
        "{error}"
    );
    let _ = std::fs::remove_dir_all(&directory);
}

/// Two elastic bars of the default bar steel, radius 5 mm and 50 mm long, on the z axis: bar A
/// (4 elements across, z in [-50, 0] mm) moving at `speed` towards bar B (6 elements across,
/// z in [0, 50] mm) at rest. B's end face (slave, finer) against A's end face (master).
fn bar_on_bar(speed: f64, friction: f64, threads: Option<usize>) -> (AxisymmetricModel, f64) {
    let spec = ShpbSpec::new(1.0);
    let bar = spec.bar_material();
    let (radius, length) = (5.0e-3, 50.0e-3);
    let block = |name: &str, z: (f64, f64), nr: usize| {
        QuadMesh::block(
            name,
            0,
            (0.0, radius),
            z,
            nr,
            (length / (radius / nr as f64)).round() as usize,
            Grading::UNIFORM,
            Grading::UNIFORM,
        )
    };
    let mut mesh = block("a", (-length, 0.0), 4);
    mesh.append(block("b", (0.0, length), 6));
    let a_nodes = (length / (radius / 4.0)).round() as usize * 5 + 5;
    let initial_velocity = (0..mesh.nodes.len())
        .map(|n| [0.0, if n < a_nodes { speed } else { 0.0 }, 0.0])
        .collect();
    let top = mesh.node_set("a.top").unwrap();
    let master = top.windows(2).map(|w| [w[1], w[0]]).collect();
    let slave = mesh.node_set("b.bottom").unwrap().to_vec();
    let axis = [
        mesh.node_set("a.axis").unwrap(),
        mesh.node_set("b.axis").unwrap(),
    ]
    .concat();
    let model = AxisymmetricModel {
        mesh,
        materials: vec![bar],
        initial_temperature: 298.0,
        initial_velocity,
        constraints: vec![VelocityConstraint {
            nodes: axis,
            dof: 0,
            velocity: Amplitude::constant(0.0),
        }],
        walls: Vec::new(),
        contacts: vec![ContactPair::new(slave, master).with_friction(friction)],
        eroding_contact: None,
        rigid_parts: Vec::new(),
        pressure_loads: Vec::new(),
        body_acceleration: None,
        trusses: Vec::new(),
        node_contacts: Vec::new(),
        settings: SolverSettings {
            end_time: 30.0e-6,
            output_interval: 0.5e-6,
            threads,
            ..SolverSettings::default()
        },
        tracked_elements: Vec::new(),
    };
    (model, spec.bar_wave_speed())
}

/// Lumped nodal masses per radian (`rho V / 4` per element node), as the solver builds them.
fn nodal_masses(model: &AxisymmetricModel) -> Vec<f64> {
    let mesh = &model.mesh;
    let mut mass = vec![0.0; mesh.nodes.len()];
    for (e, element) in mesh.elements.iter().enumerate() {
        let radius = element.iter().map(|&n| mesh.nodes[n][0]).sum::<f64>() / 4.0;
        let density = model.materials[mesh.parts[mesh.element_part[e]].material].density;
        for &n in element {
            mass[n] += density * mesh.area(e) * radius / 4.0;
        }
    }
    mass
}

#[test]
fn a_bar_striking_an_equal_bar_hands_over_its_momentum_through_contact() {
    // GOAL: penalty contact between deformable parts conserves momentum exactly and energy to
    //       the balance's tolerance, and reproduces the 1D impact of equal bars.
    // SETUP: bar_on_bar: 10 m/s, frictionless and mu 0.3, non-matching meshes (4 vs 6 across),
    //        run to 30 us (contact lasts 2 L / c0 = 20 us).
    // REFERENCE: 1D wave theory: after 2 L / c0 the striking bar is at rest and the struck bar
    //   moves at 10 m/s with all the kinetic energy; contact stress rho c0 v / 2. Axial
    //   momentum: conserved to round-off (balanced contact forces), tolerance 1e-9 relative.
    //   Measured (both frictions): momentum error 6e-16; struck bar's mean velocity 98.5 % of
    //   v, striking bar 1.5 % (lateral inertia: the 1D picture is not exact), kinetic energy
    //   of the struck bar 97.8 % of the initial, contact energy after separation 2e-4 / 4e-4
    //   of the initial energy, energy error 0.008 %. Tolerances: 3 %, 3 %, > 95 %, 0.5 %, 1 %.
    for friction in [0.0, 0.3] {
        let speed = 10.0;
        let (model, _) = bar_on_bar(speed, friction, None);
        let run = model.run(&mut |_, _| {}).unwrap();
        let mass = nodal_masses(&model);
        let a_nodes = model.mesh.node_set("a.top").unwrap()[4] + 1;
        let momentum = |range: std::ops::Range<usize>| {
            range.map(|n| mass[n] * run.velocities[n][1]).sum::<f64>()
        };
        let total_mass = |range: std::ops::Range<usize>| mass[range].iter().sum::<f64>();
        let nodes = mass.len();
        let initial = total_mass(0..a_nodes) * speed;
        let a_speed = momentum(0..a_nodes) / total_mass(0..a_nodes);
        let b_speed = momentum(a_nodes..nodes) / total_mass(a_nodes..nodes);
        let energy = run.energy();
        let kinetic_b: f64 = 2.0
            * std::f64::consts::PI
            * (a_nodes..nodes)
                .map(|n| {
                    0.5 * mass[n] * (run.velocities[n][0].powi(2) + run.velocities[n][1].powi(2))
                })
                .sum::<f64>();
        eprintln!(
            "mu {friction}: momentum error {:.2e}, a {a_speed:.4} m/s, b {b_speed:.4} m/s, kinetic of b {:.4} of initial, contact {:.2e} of initial, energy error {:.4} %",
            (momentum(0..nodes) - initial) / initial,
            kinetic_b / energy.initial,
            energy.contact / energy.initial,
            energy.error_percent()
        );
        assert!(((momentum(0..nodes) - initial) / initial).abs() < 1e-9);
        assert!((b_speed / speed - 1.0).abs() < 0.03, "b {b_speed}");
        assert!(a_speed.abs() < 0.03 * speed, "a {a_speed}");
        assert!(kinetic_b > 0.95 * energy.initial);
        assert!(energy.contact.abs() < 0.005 * energy.initial);
        assert!(energy.error_percent().abs() <= 1.0, "{}", energy.report());
    }
}

#[test]
fn contact_results_are_bit_identical_for_one_and_two_threads() {
    // GOAL: contact keeps the solver's thread-count independence.
    // SETUP: bar_on_bar at 10 m/s with friction 0.3, 1 and 2 worker threads.
    // REFERENCE: every final coordinate and velocity bit-identical.
    let (one, _) = bar_on_bar(10.0, 0.3, Some(1));
    let (two, _) = bar_on_bar(10.0, 0.3, Some(2));
    let one = one.run(&mut |_, _| {}).unwrap();
    let two = two.run(&mut |_, _| {}).unwrap();
    for (a, b) in one
        .positions
        .iter()
        .chain(&one.velocities)
        .zip(two.positions.iter().chain(&two.velocities))
    {
        assert_eq!(a[0].to_bits(), b[0].to_bits());
        assert_eq!(a[1].to_bits(), b[1].to_bits());
    }
}

#[test]
fn analyse_shpb_on_the_simulated_gauges_gives_the_bars_own_analysis() {
    // GOAL: `stoss analyse-shpb` (a real bar's recorded gauges: no clock of the pulse, units
    //       in the CSV header) gives the curve the simulated bar's own analysis gives.
    // SETUP: the FE bar (defaults, 4340 JC specimen, striker 15 m/s); its two gauge signals
    //        written as `time [us],incident [microstrain],transmitted [microstrain]`; the CLI
    //        run with the bar's constants in mixed units.
    // REFERENCE: the FE bar's 1-wave curve (its pulse timing known from the model): the
    //        recording's stresses within 1 % of it from 2 % strain to 90 % of the largest
    //        strain. Measured: the pulse start found on the signal is 1.3 us before the
    //        nominal one (the dispersed front), so the reflected wave's foot is integrated
    //        where the model's own analysis cuts it: strains 0.0004 larger, which moves the
    //        stress by 2 % on the elastic-plastic knee (1 % strain, before equilibrium) and
    //        by < 0.1 % on the plastic branch.
    let spec = ShpbSpec::new(15.0);
    let (_, jc) = material::load(&fixture("materials/4340-jc.toml")).unwrap();
    let (result, _, _) = spec.run(&jc, &SolverSettings::default()).unwrap();
    let dir = std::env::temp_dir().join(format!("stoss-analyse-shpb-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut csv = String::from(
        "# gauges of the FE bar\ntime [us],incident [microstrain],transmitted [microstrain]\n",
    );
    for ((t, i), (_, tr)) in result.incident_gauge.iter().zip(&result.transmitter_gauge) {
        csv.push_str(&format!("{:e},{:e},{:e}\n", t * 1e6, i * 1e6, tr * 1e6));
    }
    let gauges = dir.join("gauges.csv");
    std::fs::write(&gauges, csv).unwrap();
    let (d_i, d_t) = result.gauge_distances;
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_stoss"))
        .arg("analyse-shpb")
        .arg(&gauges)
        .args(["--bar-modulus", "200 GPa", "--bar-density", "8000"])
        .args(["--bar-diameter", "12.7 mm", "--specimen-diameter", "6 mm"])
        .args(["--specimen-length", "4 mm"])
        .args([
            "--incident-gauge",
            &format!("{d_i}"),
            "--transmitter-gauge",
            &format!("{d_t}"),
        ])
        .arg("--output")
        .arg(dir.join("curve"))
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let recorded = recording::load(&dir.join("curve.recording.csv")).unwrap();
    let own = result.analysis(Analysis::OneWave).curve();
    let largest = result.analysis(Analysis::OneWave).max_strain();
    let mut compared = 0;
    for point in &recorded {
        if point.position < 0.02 || point.position > 0.9 * largest {
            continue;
        }
        let expected = interpolate(&own, point.position);
        assert!(
            (point.value / expected - 1.0).abs() < 0.01,
            "strain {}: {} vs the bar's own {expected}",
            point.position,
            point.value
        );
        compared += 1;
    }
    assert!(compared > 20, "{compared} points compared");
    // Bad input: a header without `transmitted`, and a gauge outside the record.
    std::fs::write(&gauges, "time,incident\n0,0\n").unwrap();
    let bad = std::process::Command::new(env!("CARGO_BIN_EXE_stoss"))
        .arg("analyse-shpb")
        .arg(&gauges)
        .args(["--bar-modulus", "200 GPa", "--bar-density", "8000"])
        .args(["--bar-diameter", "12.7 mm", "--specimen-diameter", "6 mm"])
        .args(["--specimen-length", "4 mm", "--incident-gauge", "0.25"])
        .args(["--transmitter-gauge", "0.25", "--output"])
        .arg(dir.join("bad"))
        .output()
        .unwrap();
    let message = String::from_utf8_lossy(&bad.stderr);
    assert!(
        !bad.status.success() && message.contains("gauges.csv:1: field ``: expected the header"),
        "{message}"
    );
    assert!(!dir.join("bad.csv").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

//! Long-rod penetration: eroding contact, energy, threads, the Walker–Anderson cross-check and
//! bad input. The 0.2 / 0.1 mm meshes and the full seed 000 runs are in the benchmark
//! (`cargo bench -p stoss --bench penetration`, docs/solver.md), not here.

use std::path::{Path, PathBuf};
use stoss::analytic::penetration::{
    spherical_cavity_pressure, walker_anderson_quasi_steady_penetration_velocity,
};
use stoss::experiment::penetration::Nose;
use stoss::experiment::{Experiment, PenetrationSpec, Setup};
use stoss::input::material;
use stoss::solver::{HourglassControl, SolverError, SolverSettings};
use stoss_kernel::eos::Eos;
use stoss_kernel::{Material, PartMaterial};

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../fixtures")
        .join(name)
}

/// The seed 000 1700 m/s experiment, its spec and the target material.
fn seed_experiment() -> (Experiment, PenetrationSpec, Material) {
    let experiment = Experiment::load(&fixture("experiments/penetration-hzb-1700.toml")).unwrap();
    let (_, target) = material::load(&experiment.default_material_path().unwrap()).unwrap();
    let Setup::Penetration(spec) = &experiment.file.setup else {
        panic!("not a penetration experiment");
    };
    let spec = spec.clone();
    (experiment, spec, target)
}

/// The material file `name` made elastic-perfectly plastic at `yield_stress`, isothermal and
/// rate-independent (its elasticity, EoS and erosion unchanged).
fn perfectly_plastic(name: &str, yield_stress: f64) -> Material {
    let path = fixture(&format!("materials/{name}"));
    let text: String = std::fs::read_to_string(&path)
        .unwrap()
        .lines()
        .filter(|line| !line.starts_with("taylor_quinney"))
        .map(|line| {
            if line.starts_with("yield_stress") {
                format!("yield_stress = {yield_stress:e}")
            } else if line.starts_with("hardening_modulus") {
                "hardening_modulus = 0.0".to_string()
            } else if line.starts_with("rate_sensitivity") {
                "rate_sensitivity = 0.0".to_string()
            } else if line == "kind = \"adiabatic\"" {
                "kind = \"isothermal\"".to_string()
            } else {
                line.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    material::parse(&path, &text).unwrap().1
}

#[test]
fn penetration_is_thread_independent_balances_energy_and_keeps_surfaces_apart() {
    // GOAL: the first 15 us of seed 000's 1700 m/s shot at the 0.4 mm calibration mesh:
    //       (a) 1 and 2 threads give bit-identical results; (b) the energy balance closes to
    //       1 % with erosion on (eroded energy, contact work, eroded mass kept); (c) the
    //       eroding contact's surface interpenetration (the issue asks for < 15 % of the
    //       smallest element); (d) elements erode and the nose advances.
    // SETUP: fixtures/experiments/penetration-hzb-1700.toml with end_time 15 us; its final
    //        field rendered as the `.vtu` `stoss simulate` writes.
    // REFERENCE: (a) exact; (b) |error| <= 1 %; (c) < 15 % of the smallest element (the
    //   issue's bound; the kinematic stop holds surface nodes at 10 %; measured 10.1 %), and
    //   the overlap it leaves out, tolerated where erosion exposes a face behind a node
    //   (measured 2.62 elements, asserted < 4); (d) Walker–Anderson's depth at 15 us with the
    //   same constants (13.19 mm; measured 13.40 mm, +1.6 %, asserted within 3.5 %); (e) the
    //   `.vtu` holds exactly the cells not eroded, each with a positive area (counter-
    //   clockwise corners in r-z), a part and material id, the final time and the eroded count.
    let (_, mut spec, target) = seed_experiment();
    spec.end_time = 15.0e-6;
    let run = |threads: usize| {
        spec.run(
            &PartMaterial::from(target),
            &SolverSettings {
                threads: Some(threads),
                ..SolverSettings::default()
            },
        )
        .unwrap()
    };
    let (one, run_one, built) = run(1);
    let (two, run_two, _) = run(2);
    let bits = |v: &[[f64; 3]]| v.iter().flatten().map(|c| c.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&run_one.positions), bits(&run_two.positions));
    assert_eq!(bits(&run_one.velocities), bits(&run_two.velocities));
    assert_eq!(one, two);
    let energy = run_one.energy();
    assert!(
        energy.error_percent().abs() <= 1.0,
        "energy error {:.3} %\n{}",
        energy.error_percent(),
        energy.report()
    );
    assert!(energy.eroded > 0.0 && energy.contact > 0.0);
    let eroded = run_one.eroded.iter().filter(|&&e| e).count();
    assert!(eroded > 20, "{eroded} elements eroded");
    let ratio = run_one.contact.largest_penetration / built.smallest_element;
    assert!(
        ratio < 0.15,
        "interpenetration {ratio:.3} of the smallest element"
    );
    let tolerated = run_one.contact.largest_initial_penetration / built.smallest_element;
    let depth = one.nose_depth.last().unwrap().1;
    let check = spec.cross_check(&target).unwrap();
    let walker_anderson = stoss::analytic::penetration::depth_at(&check.walker_anderson, 15.0e-6);
    eprintln!(
        "15 us: nose {:.3} mm, Walker-Anderson {:.3} mm ({:+.1} %); interpenetration {ratio:.3}, \
         tolerated exposure {tolerated:.2} of the smallest element",
        depth * 1e3,
        walker_anderson * 1e3,
        100.0 * (depth / walker_anderson - 1.0)
    );
    assert!(
        tolerated < 4.0,
        "tolerated exposure {tolerated:.2} of the smallest element"
    );
    assert!(
        (depth / walker_anderson - 1.0).abs() < 0.035,
        "nose depth {depth} after 15 us against Walker-Anderson's {walker_anderson}"
    );
    // (e) Issue 51 item 4: the `.vtu` a user opens shows the crater without filtering: the
    //     eroded cells are left out, no written cell is inverted, every cell has its part and
    //     material id, and the time is in the file.
    let field = stoss::figure::FieldOutput {
        time: run_one.final_time(),
        mesh: built.model.mesh.clone(),
        positions: run_one.positions.clone(),
        states: run_one.states.clone(),
        eroded: run_one.eroded.clone(),
        cell_data: Vec::new(),
    };
    let vtu = stoss::report::vtk::render(&field);
    let array = |name: &str| -> Vec<f64> {
        let start = vtu.find(&format!("Name=\"{name}\"")).unwrap();
        let body = &vtu[start..];
        let body = &body[body.find('>').unwrap() + 1..body.find("</DataArray>").unwrap()];
        body.split_whitespace()
            .map(|v| v.parse().unwrap())
            .collect()
    };
    let points_start = vtu.find("<Points>").unwrap();
    let points = &vtu[points_start..];
    let points =
        &points[points.find("ascii\">").unwrap() + 7..points.find("</DataArray>").unwrap()];
    let xyz: Vec<f64> = points
        .split_whitespace()
        .map(|v| v.parse().unwrap())
        .collect();
    let connectivity = array("connectivity");
    let written = connectivity.len() / 4;
    assert_eq!(
        written,
        run_one.eroded.len() - eroded,
        "eroded cells are left out"
    );
    let corner = |n: f64| [xyz[3 * n as usize], xyz[3 * n as usize + 1]];
    let inverted = connectivity
        .chunks(4)
        .filter(|quad| {
            let c: Vec<[f64; 2]> = quad.iter().map(|&n| corner(n)).collect();
            let area: f64 = (0..4)
                .map(|k| c[k][0] * c[(k + 1) % 4][1] - c[(k + 1) % 4][0] * c[k][1])
                .sum();
            area <= 0.0
        })
        .count();
    assert_eq!(inverted, 0, "{inverted} inverted cells written");
    let parts = array("part_id");
    assert_eq!(parts.len(), written);
    assert!(parts.iter().all(|&p| p >= 1.0) && parts.iter().any(|&p| p >= 2.0));
    assert_eq!(array("material_id").len(), written);
    assert_eq!(array("TimeValue"), vec![run_one.final_time()]);
    assert_eq!(array("eroded_cells"), vec![eroded as f64]);
}

#[test]
fn the_whole_1700_m_per_s_shot_keeps_the_surfaces_apart_and_balances_energy() {
    // GOAL: over the whole of seed 000's 1700 m/s shot (60.3 us, 0.4 mm), through the crater's
    //       growth, the rod's erosion and the debris piling up, the eroding contact keeps the
    //       surfaces apart and the energy balance closes.
    // SETUP: fixtures/experiments/penetration-hzb-1700.toml as bundled, at the 0.4 mm
    //        calibration mesh, 2 threads.
    // REFERENCE: the issue: surface interpenetration < 15 % of the smallest element (measured
    //   10.8 %), energy error <= 1 % with erosion on; what that bound leaves out: the overlap
    //   tolerated where erosion exposes a face behind a node (measured 3.32 elements, asserted
    //   < 6) and the debris' depth (0.10, asserted < 0.3).
    let (_, spec, target) = seed_experiment();
    let (_, run, built) = spec
        .run(
            &PartMaterial::from(target),
            &SolverSettings {
                threads: Some(2),
                ..SolverSettings::default()
            },
        )
        .unwrap();
    let ratio = run.contact.largest_penetration / built.smallest_element;
    let tolerated = run.contact.largest_initial_penetration / built.smallest_element;
    let debris = run.contact.largest_free_node_penetration / built.smallest_element;
    eprintln!(
        "whole shot: interpenetration {ratio:.3}, tolerated exposure {tolerated:.2}, debris \
         {debris:.2} of the smallest element"
    );
    assert!(
        ratio < 0.15,
        "interpenetration {ratio:.3} of the smallest element"
    );
    // What the bound above leaves out, bounded too: the overlap a surface node already has
    // when erosion exposes the face it lies behind (kept, not pushed out) and the depth of
    // free mass points (debris).
    assert!(
        tolerated < 6.0,
        "tolerated exposure {tolerated:.2} of the smallest element"
    );
    assert!(debris < 0.3, "debris {debris:.2} of the smallest element");
    let energy = run.energy();
    assert!(
        energy.error_percent().abs() <= 1.0,
        "energy error {:.3} %\n{}",
        energy.error_percent(),
        energy.report()
    );
}

#[test]
fn quasi_steady_penetration_rate_agrees_with_walker_anderson() {
    // GOAL: with the same constant strengths, the FE penetration rate of a semi-infinite
    //       target agrees with Walker & Anderson's (1995) model in the quasi-steady phase.
    // SETUP: seed 000's rod (WHA, 5 x 50 mm, 1700 m/s) into an 80 mm thick HzB-W target
    //        (36 mm radius, clamped rim), both elastic-perfectly plastic and isothermal: rod
    //        1.5 GPa, target 1.45 GPa; 0.4 mm mesh; geometric-strain erosion 1.5 in both.
    //        u = mean nose velocity while the rod's remaining length falls from 70 % to 30 %
    //        of L0 (the window of analytic::quasi_steady_penetration_velocity).
    // REFERENCE: Walker–Anderson with the same strengths, the target's K and G, default
    //   crater radius: u_WA; |u_FE / u_WA - 1| <= 10 % (the bound). Measured: u_FE
    //   0.83 mm/us against u_WA 0.78 (+6 %). (At 1250 m/s the same comparison gives +29 %
    //   at this mesh and +21 % at 0.2 mm: docs/solver.md, "Hourglass control under a
    //   penetrator".)
    let (_, mut spec, _) = seed_experiment();
    spec.rod = Some(Box::new(perfectly_plastic("wha-jc.toml", 1.5e9).into()));
    spec.target_thickness = 80.0e-3;
    spec.end_time = 48.0e-6;
    let target = perfectly_plastic("hzb-w-jc.toml", 1.45e9);
    let (result, run, _) = spec
        .run(&PartMaterial::from(target), &SolverSettings::default())
        .unwrap();
    assert!(run.energy().error_percent().abs() <= 1.0);
    let crossing = |fraction: f64| {
        let length = fraction * spec.rod_length;
        let k = result
            .rod_length
            .iter()
            .position(|&(_, l)| l <= length)
            .expect("the rod erodes that far");
        (result.rod_length[k].0, result.nose_depth[k].1)
    };
    let (t0, p0) = crossing(0.7);
    let (t1, p1) = crossing(0.3);
    let fe = (p1 - p0) / (t1 - t0);
    let check = spec.cross_check(&target).unwrap();
    let wa = walker_anderson_quasi_steady_penetration_velocity(&check.case, None).unwrap();
    assert!(
        (fe / wa - 1.0).abs() <= 0.10,
        "FE {fe:.1} m/s against Walker-Anderson {wa:.1} m/s"
    );
}

#[test]
fn an_element_inverting_before_it_erodes_is_a_typed_error() {
    // GOAL: without erosion a Lagrangian cavity cannot open: the run stops with a typed error
    //       naming the element, its part and the time, never a NaN carried on.
    // SETUP: the 1700 m/s shot with erosion switched off in both materials.
    // REFERENCE: SolverError::InvertedElement (or a kernel update error) within 20 us.
    let (_, mut spec, mut target) = seed_experiment();
    let mut rod = *spec.rod.unwrap().j2().unwrap();
    rod.failure.erosion_geometric_strain = None;
    target.failure.erosion_geometric_strain = None;
    spec.rod = Some(Box::new(rod.into()));
    spec.end_time = 20.0e-6;
    match spec.run(&PartMaterial::from(target), &SolverSettings::default()) {
        Err(SolverError::InvertedElement { part, time, .. }) => {
            assert!(part == "target" || part == "rod");
            assert!(time > 0.0 && time < 21.0e-6);
        }
        Err(SolverError::Update { part, time, .. }) => {
            assert!(part == "target" || part == "rod");
            assert!(time > 0.0);
        }
        other => panic!("expected an inverted element, got {:?}", other.map(|r| r.0)),
    }
}

/// Write `experiment.toml` (with `setup` lines replaced) and its recording into `folder`.
fn write_variant(folder: &Path, replace: &[(&str, &str)]) -> PathBuf {
    std::fs::create_dir_all(folder).unwrap();
    let mut text =
        std::fs::read_to_string(fixture("experiments/penetration-hzb-1700.toml")).unwrap();
    let materials = fixture("materials");
    let materials = materials.display().to_string();
    text = text.replace("../materials", &materials);
    text = text.replace(
        "recording = \"penetration-hzb-1700.csv\"",
        "recording = \"recording.csv\"",
    );
    for (from, to) in replace {
        assert!(text.contains(from), "{from}");
        text = text.replace(from, to);
    }
    std::fs::copy(
        fixture("experiments/penetration-hzb-1700.csv"),
        folder.join("recording.csv"),
    )
    .unwrap();
    let path = folder.join("experiment.toml");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn bad_penetration_input_names_the_file_line_and_field() {
    // GOAL: a zero or negative gap, a rod wider than the target, an element size that does
    //       not fit, a recording outside the simulated time, an end time in seconds instead
    //       of microseconds (a runaway run), an unknown hourglass form, an ogive whose meplat
    //       is too small to mesh at the element size and an erosion strain <= 0 are errors
    //       naming the file, the line and the field.
    // SETUP: variants of penetration-hzb-1700.toml in a scratch folder.
    // REFERENCE: the error message names the file and the field (and the line for TOML
    //   fields; the recording's time is checked against `end_time`).
    let scratch = std::env::temp_dir().join(format!("stoss-penetration-{}", std::process::id()));
    let cases: [(&str, &str, &str); 8] = [
        ("end_time = 60.3e-6", "gap = 0.0\nend_time = 60.3e-6", "gap"),
        (
            "end_time = 60.3e-6",
            "gap = -1e-4\nend_time = 60.3e-6",
            "gap",
        ),
        (
            "target_radius = 36.0e-3",
            "target_radius = 2.0e-3",
            "target_radius",
        ),
        (
            "element_size = 0.4e-3",
            "element_size = 4.0",
            "element_size",
        ),
        ("end_time = 60.3e-6", "end_time = 50.0e-6", "end_time"),
        ("end_time = 60.3e-6", "end_time = 60.3", "end_time"),
        (
            "end_time = 60.3e-6",
            "hourglass = \"stiff\"\nend_time = 60.3e-6",
            "hourglass",
        ),
        (
            "end_time = 60.3e-6",
            "nose = \"ogive\"\nnose_length = 7.5e-3\ntip_radius = 0.02e-3\nend_time = 60.3e-6",
            "element_size",
        ),
    ];
    for (k, (from, to, field)) in cases.iter().enumerate() {
        let path = write_variant(&scratch.join(format!("case-{k}")), &[(from, to)]);
        let error = Experiment::load(&path).unwrap_err().to_string();
        assert!(error.contains(field), "{to}: {error}");
        if *to == "end_time = 50.0e-6" {
            // The recording's point is out of range: the recording file and point are named.
            assert!(error.contains("recording.csv"), "{to}: {error}");
        } else {
            // TOML fields are named with their line: `experiment.toml:<line>: field ...`.
            assert!(error.contains("experiment.toml:"), "{to}: {error}");
        }
    }
    // Erosion strain <= 0 in the rod's material file.
    let folder = scratch.join("erosion");
    std::fs::create_dir_all(&folder).unwrap();
    let rod = std::fs::read_to_string(fixture("materials/wha-jc.toml"))
        .unwrap()
        .replace(
            "erosion_geometric_strain = 1.5",
            "erosion_geometric_strain = 0.0",
        );
    let rod_path = folder.join("rod.toml");
    std::fs::write(&rod_path, rod).unwrap();
    let rod_field = format!("rod_material = \"{}\"", rod_path.display());
    let materials = fixture("materials").display().to_string();
    let path = write_variant(
        &folder,
        &[(
            &format!("rod_material = \"{materials}/wha-jc.toml\"")[..],
            &rod_field[..],
        )],
    );
    let error = Experiment::load(&path).unwrap_err().to_string();
    assert!(
        error.contains("erosion_geometric_strain") && error.contains("rod.toml"),
        "{error}"
    );
    let _ = std::fs::remove_dir_all(&scratch);
}

#[test]
fn the_penetration_campaign_holds_seed_000s_published_final_depths() {
    // GOAL: the bundled campaign loads both penetration experiments, with the rod material
    //       resolved, and their recordings are the published numbers.
    // SETUP: fixtures/campaigns/penetration-hzb.toml.
    // REFERENCE: seed 000 sec. 5 (Anderson et al. 1995): 2.32 cm at 55.0 us (1250 m/s, 29.0 mm)
    //   and 4.56 cm at 60.3 us (1700 m/s, 49.5 mm), +/- 0.06 cm.
    let campaign = stoss::fit::Campaign::load(&fixture("campaigns/penetration-hzb.toml")).unwrap();
    let expected = [(55.0e-6, 2.32e-2, 29.0e-3), (60.3e-6, 4.56e-2, 49.5e-3)];
    assert_eq!(campaign.experiments.len(), 2);
    for (experiment, (time, depth, thickness)) in campaign.experiments.iter().zip(expected) {
        let Setup::Penetration(spec) = &experiment.file.setup else {
            panic!("not a penetration experiment");
        };
        assert!(spec.rod.is_some());
        assert_eq!(spec.target_thickness, thickness);
        let last = experiment.recording.last().unwrap();
        assert_eq!(last.quantity, "nose_depth");
        assert_eq!(
            (last.position, last.value, last.uncertainty),
            (time, depth, 0.06e-2)
        );
    }
}

/// A rigid rod of seed 000's diameter (5 mm, 30 mm long) with `nose`, driven at a constant
/// `speed` into an 40 mm thick, 30 mm radius HzB-W plate made elastic-perfectly plastic at
/// 1.5 GPa (erosion at 150 % geometric strain), 0.4 mm mesh, until its tip is `depth` deep.
/// Returns the target's mean axial resistance over each 1 mm of travel `(tip depth, force)`,
/// the run, and the number of live target nodes inside the rod's shank at the end.
fn driven_rigid_rod(
    nose: Nose,
    speed: f64,
    depth: f64,
    hourglass: HourglassControl,
) -> (Vec<(f64, f64)>, stoss::solver::AxisymmetricRun, usize) {
    let (_, mut spec, _) = seed_experiment();
    let target = perfectly_plastic("hzb-w-jc.toml", 1.5e9);
    spec.velocity = speed;
    spec.rod_length = 30.0e-3;
    spec.nose = nose;
    if nose == Nose::Ogive {
        spec.nose_length = Some(2.5e-3 * 11f64.sqrt()); // CRH 3
    }
    spec.hourglass = hourglass;
    spec.target_thickness = 40.0e-3;
    spec.target_radius = 30.0e-3;
    spec.end_time = depth / speed;
    let driven = spec
        .run_driven(
            &PartMaterial::from(target),
            &SolverSettings::default(),
            1.0e-3,
        )
        .unwrap();
    let (resistance, run, built) = (driven.resistance, driven.run, driven.model);
    let rod_nodes = built.rod_nodes();
    let tip = built.rod_tip();
    let model = built.model;
    // Live target nodes inside the rod's cylinder, behind its nose.
    let shank = tip - speed * run.energy().time + spec.nose_length.unwrap_or(0.0);
    let mut live = vec![false; run.positions.len()];
    for (e, nodes) in model.mesh.elements.iter().enumerate() {
        if !run.eroded[e] && !built.rod_elements.contains(&e) {
            for &n in nodes {
                live[n] = true;
            }
        }
    }
    let inside = (0..rod_nodes[0])
        .filter(|&n| {
            let p = run.positions[n];
            live[n] && p[0] < 0.9 * 2.5e-3 && p[1] > shank + 0.5e-3
        })
        .count();
    (resistance, run, inside)
}

/// Forrestal's static resistance of a penetrator of radius `a` into an elastic-perfectly
/// plastic target, `pi a^2 sigma_s`, with Hill's spherical cavity pressure (the target's
/// moduli, its yield stress 1.5 GPa).
fn cavity_expansion_resistance(target: &Material, radius: f64) -> f64 {
    let Eos::MieGruneisen(eos) = target.eos else {
        panic!("the HzB-W file has a Mie-Grüneisen EoS");
    };
    let bulk = eos.reference_density * eos.sound_speed * eos.sound_speed;
    let hill = spherical_cavity_pressure(1.5e9, bulk, target.shear_modulus);
    std::f64::consts::PI * radius * radius * hill
}

#[test]
fn a_driven_rigid_rod_meets_the_cavity_expansion_resistance_and_stays_outside_the_target() {
    // GOAL: the erosion, the eroding contact and the elements together give a target the
    //       resistance of cavity-expansion theory, and hourglass deformation ahead of a blunt
    //       rod does not let target material pass through it.
    // SETUP: driven_rigid_rod at 300 m/s to 14 mm: (a) an ogive nose (CRH 3), (b) a flat
    //        nose, both with the stiffness hourglass form (set here; the penetration default
    //        is the viscous form); (c) the flat nose with the viscous form.
    // REFERENCE: Forrestal's static resistance pi a^2 sigma_s with Hill's cavity pressure
    //   (Forrestal, Okajima & Luk, J. Appl. Mech. 55 (1988) 755), 100.9 kN here; the dynamic
    //   term N* B rho V^2 adds 2 % for the ogive, about 15 % for a flat nose. (a) the mean
    //   force over 10-14 mm within 0.85-1.2 of it (measured 0.99-1.11); (b) within 0.85-2.0 of
    //   it (1.4-1.7: the flat face pushes a dead zone and the eroded debris) and no live target
    //   node inside the rod; (c) the defect this guards against: with the viscous form the
    //   target tangles ahead of the flat face and passes through it (the force falls to a
    //   fraction; 207 target nodes end inside the rod at 25 mm). Energy error <= 1 % in (a), (b).
    let reference = cavity_expansion_resistance(&perfectly_plastic("hzb-w-jc.toml", 1.5e9), 2.5e-3);
    let late = |resistance: &[(f64, f64)]| -> Vec<f64> {
        resistance
            .iter()
            .filter(|(depth, _)| *depth >= 10.0e-3)
            .map(|(_, force)| force / reference)
            .collect()
    };
    let (ogive, run, inside) =
        driven_rigid_rod(Nose::Ogive, 300.0, 14.0e-3, HourglassControl::Stiffness);
    let ratios = late(&ogive);
    let mean = ratios.iter().sum::<f64>() / ratios.len() as f64;
    assert!(
        (0.85..1.2).contains(&mean),
        "ogive: {ratios:?} of {reference} N"
    );
    assert!(run.energy().error_percent().abs() <= 1.0);
    assert_eq!(inside, 0);
    let (flat, run, inside) =
        driven_rigid_rod(Nose::Flat, 300.0, 14.0e-3, HourglassControl::Stiffness);
    let ratios = late(&flat);
    assert!(
        ratios.iter().all(|r| (0.85..2.0).contains(r)),
        "flat: {ratios:?}"
    );
    assert!(run.energy().error_percent().abs() <= 1.0);
    assert_eq!(inside, 0, "target nodes inside the flat rod");
    let (_, _, inside) = driven_rigid_rod(Nose::Flat, 300.0, 14.0e-3, HourglassControl::Viscous);
    assert!(
        inside > 10,
        "viscous form: {inside} target nodes inside the rod"
    );
}

#[test]
fn a_rigid_blunt_nose_at_the_eroding_rods_rate_meets_forrestals_dynamic_resistance() {
    // GOAL: the target's side of the eroding interface is right. Under a rigid hemispherical
    //       nose pushed at the rate at which the FE's eroding rods penetrate (455 m/s: a
    //       near-fluid rod into this target at 0.2 mm, docs/solver.md), the eroding target
    //       resists with cavity-expansion theory's face pressure. A deficit of the target
    //       under an eroding crater (material deleted instead of pushed aside) would show
    //       here, since this target erodes the same way.
    // SETUP: driven_rigid_rod with a hemispherical nose, 455 m/s to 14 mm, viscous hourglass
    //        form (the penetration default), 0.4 mm mesh.
    // REFERENCE: Forrestal, Okajima & Luk, J. Appl. Mech. 55 (1988) 755: mean face pressure
    //   sigma_s + N* B rho V^2, N* = 1/2 for a hemisphere, B between 1 (compressible steel)
    //   and 3/2 (incompressible): 5.97-6.37 GPa here. The mean over 10-14 mm within 5 % of
    //   that range (measured 6.21 GPa at 0.4 mm, 6.12 at 0.2 mm; a target resistance short
    //   by a fifth, as the Tate balance of the eroding rod reads, would give about 5.0 GPa).
    let speed = 455.0;
    let radius = 2.5e-3;
    let area = std::f64::consts::PI * radius * radius;
    let target = perfectly_plastic("hzb-w-jc.toml", 1.5e9);
    let static_pressure = cavity_expansion_resistance(&target, radius) / area;
    let inertia = 0.5 * target.density * speed * speed;
    let (low, high) = (static_pressure + inertia, static_pressure + 1.5 * inertia);
    let (resistance, run, _) = driven_rigid_rod(
        Nose::Hemispherical,
        speed,
        14.0e-3,
        HourglassControl::Viscous,
    );
    let late: Vec<f64> = resistance
        .iter()
        .filter(|(depth, _)| *depth >= 10.0e-3)
        .map(|(_, force)| force / area)
        .collect();
    let mean = late.iter().sum::<f64>() / late.len() as f64;
    assert!(
        (0.95 * low..1.05 * high).contains(&mean),
        "mean face pressure {mean:e} Pa against {low:e}-{high:e} ({late:?})"
    );
    assert!(run.energy().error_percent().abs() <= 1.0);
}

#[test]
fn a_driven_run_refuses_a_runaway_size_before_it_starts() {
    // GOAL: a spec edited in code gets the same up-front size checks as a file.
    // SETUP: the seed experiment's spec with a 1 um element (about 1e11 elements), and with a
    //        zero averaging window.
    // REFERENCE: an error naming the field, returned without running.
    let (_, mut spec, _) = seed_experiment();
    let target = PartMaterial::from(perfectly_plastic("hzb-w-jc.toml", 1.5e9));
    let settings = SolverSettings::default();
    spec.element_size = 1.0e-6;
    let error = spec.run_driven(&target, &settings, 1.0e-3).err().unwrap();
    assert!(error.to_string().contains("element_size"), "{error}");
    let (_, spec, _) = seed_experiment();
    let error = spec.run_driven(&target, &settings, 0.0).err().unwrap();
    assert!(error.to_string().contains("window"), "{error}");
}

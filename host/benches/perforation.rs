//! Concrete perforation validation and throughput (seed 001 sec. 4): the bundled model of FOI's
//! Lagrange perforation runs, fired with the constants of each of FOI's runs (seed tables
//! 4.5-4.7), against that run's exit velocity (code to code) and the tests' 190 +/- 14 m/s;
//! then table 4.4 as printed under both tensile options, and the old numerical set-up (LS-DYNA's
//! bulk viscosity) for comparison. Each row: the exit velocity, the energy error, the rear-face
//! damage-zone diameter, the element-cycles per second and the wall time.
//!
//! GOAL: the FE model reproduces FOI's Autodyn runs with the same constants and mesh.
//! SETUP: `fixtures/experiments/perforation-concrete-152mm.toml` (elastic projectile, Autodyn's
//! bulk viscosity, gap 1 mm, erosion 150 %), one shot at FOI's 459 m/s, 2 threads (and 1 for the
//! bundled row's throughput).
//! REFERENCE: seed 001 tables 4.6 (10 mm) and 4.7 (5 mm): B99008 247, B99035 194, B99036 189,
//! B99038 212, B99055 269, B99056 237, B99057 207 m/s.
//!
//! Run: `cargo bench -p stoss --bench perforation` (about 20 minutes on 2 cores). The figures are
//! in docs/solver.md.

use std::path::PathBuf;
use std::time::Instant;
use stoss::experiment::perforation::rear_damage_diameter;
use stoss::experiment::{Experiment, Setup};
use stoss::input::material;
use stoss::solver::{BulkViscosity, SolverSettings};
use stoss_kernel::rht::TensileFailure;
use stoss_kernel::PartMaterial;

/// One row: a run of FOI's (or a variant of ours) and what it changes against the bundled model.
struct Case {
    label: &'static str,
    foi_exit: Option<f64>,
    element: f64,
    residual: (f64, f64),
    damage: (f64, f64),
    tensile: TensileFailure,
    friction: f64,
    lsdyna_viscosity: bool,
    threads: usize,
}

const LAGRANGE: Case = Case {
    label: "",
    foi_exit: None,
    element: 10.0e-3,
    residual: (1.60, 0.61),
    damage: (0.08, 0.05),
    tensile: TensileFailure::PressureCutoff,
    friction: 0.0,
    lsdyna_viscosity: false,
    threads: 2,
};

fn main() {
    let fixtures = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures");
    let path = fixtures.join("experiments/perforation-concrete-152mm.toml");
    let experiment = Experiment::load(&path).expect("fixture loads");
    let (_, slab) = material::load_part(&experiment.default_material_path().expect("material"))
        .expect("material loads");
    let Setup::Perforation(spec) = &experiment.file.setup else {
        panic!("not a perforation experiment");
    };
    let velocity = 459.0;
    let cases = [
        Case {
            label: "B99036 (the bundled constants)",
            foi_exit: Some(189.0),
            threads: 1,
            ..LAGRANGE
        },
        Case {
            label: "B99036 (the bundled constants)",
            foi_exit: Some(189.0),
            ..LAGRANGE
        },
        Case {
            label: "B99008",
            foi_exit: Some(247.0),
            damage: (0.04, 0.01),
            ..LAGRANGE
        },
        Case {
            label: "B99035",
            foi_exit: Some(194.0),
            residual: (1.90, 0.60),
            ..LAGRANGE
        },
        Case {
            label: "B99038 (EFMIN cell blank in the seed: table 4.5's 0.05)",
            foi_exit: Some(212.0),
            damage: (0.04, 0.05),
            ..LAGRANGE
        },
        Case {
            label: "B99055",
            foi_exit: Some(269.0),
            element: 5.0e-3,
            damage: (0.04, 0.01),
            ..LAGRANGE
        },
        Case {
            label: "B99056",
            foi_exit: Some(237.0),
            element: 5.0e-3,
            ..LAGRANGE
        },
        Case {
            label: "B99057 (friction 0.05)",
            foi_exit: Some(207.0),
            element: 5.0e-3,
            friction: 0.05,
            ..LAGRANGE
        },
        Case {
            label: "table 4.4 as printed, cut-off",
            residual: (1.3, 0.65),
            damage: (0.04, 0.01),
            ..LAGRANGE
        },
        Case {
            label: "table 4.4 as printed, instant failure",
            residual: (1.3, 0.65),
            damage: (0.04, 0.01),
            tensile: TensileFailure::HydroTensileLimit,
            ..LAGRANGE
        },
        Case {
            label: "B99036, instant failure",
            tensile: TensileFailure::HydroTensileLimit,
            ..LAGRANGE
        },
        Case {
            label: "B99036, LS-DYNA's bulk viscosity (0.06, 1.5)",
            lsdyna_viscosity: true,
            ..LAGRANGE
        },
    ];
    println!(
        "| run | slab element | threads | exit (m/s) | FOI (Autodyn) | FE / FOI | tests 190 +/- 14 | energy error | rear damage diameter (m) | elements | element-cycles/s | wall (s) |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    for case in &cases {
        let mut spec = spec.clone();
        spec.element_size = case.element;
        spec.friction = case.friction;
        if case.lsdyna_viscosity {
            spec.bulk_viscosity = Some(BulkViscosity::default());
        }
        let mut concrete = *slab.rht().expect("an RHT slab");
        let parameters = &mut concrete.parameters;
        (parameters.residual_b, parameters.residual_m) = case.residual;
        (parameters.damage_d1, parameters.minimum_failure_strain) = case.damage;
        parameters.tensile_failure = case.tensile;
        let target = PartMaterial::from(concrete);
        let settings = SolverSettings {
            threads: Some(case.threads),
            ..SolverSettings::default()
        };
        let started = Instant::now();
        let shot = match spec.fire(&target, velocity, &settings) {
            Ok(shot) => shot,
            Err(error) => {
                println!("| {} | failed: {error} |", case.label);
                continue;
            }
        };
        let wall = started.elapsed().as_secs_f64();
        let exit = shot.residual_velocity;
        let (foi, ratio) = match case.foi_exit {
            Some(foi) => (
                format!("{foi:.0}"),
                format!("{:+.1} %", 100.0 * (exit / foi - 1.0)),
            ),
            None => ("-".into(), "-".into()),
        };
        println!(
            "| {} | {:.0} mm | {} | {exit:.1} | {foi} | {ratio} | {:+.1} % | {:+.3} % | {:.2} | {} | {:.3e} | {wall:.1} |",
            case.label,
            case.element * 1e3,
            case.threads,
            100.0 * (exit / 190.0 - 1.0),
            shot.energy.error_percent(),
            rear_damage_diameter(&spec, &shot.field),
            shot.field.mesh.elements.len(),
            shot.element_cycles as f64 / wall,
        );
    }
}

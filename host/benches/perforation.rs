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
//! in docs/solver.md; the runs are `stoss::validate::perforation::RUNS`, and FOI's seven are
//! `stoss validate` rows (`perforation-b99036`...).

use std::path::PathBuf;
use std::time::Instant;
use stoss::experiment::perforation::rear_damage_diameter;
use stoss::validate::perforation::{fire, Run, LAGRANGE, RUNS};

fn main() {
    let fixtures = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures");
    // The bundled row on one thread too, for its throughput.
    let one_thread = (LAGRANGE, 1);
    let cases: Vec<(Run, usize)> = std::iter::once(one_thread)
        .chain(RUNS.iter().map(|run| (*run, 2)))
        .collect();
    println!(
        "| run | slab element | threads | exit (m/s) | FOI (Autodyn) | FE / FOI | tests 190 +/- 14 | energy error | rear damage diameter (m) | elements | element-cycles/s | wall (s) |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    for (case, threads) in &cases {
        let started = Instant::now();
        let (spec, shot) = match fire(&fixtures, case, Some(*threads)) {
            Ok(fired) => fired,
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
            "| {} | {:.0} mm | {threads} | {exit:.1} | {foi} | {ratio} | {:+.1} % | {:+.3} % | {:.2} | {} | {:.3e} | {wall:.1} |",
            case.label,
            case.element * 1e3,
            100.0 * (exit / 190.0 - 1.0),
            shot.energy.error_percent(),
            rear_damage_diameter(&spec, &shot.field),
            shot.field.mesh.elements.len(),
            shot.element_cycles as f64 / wall,
        );
    }
}

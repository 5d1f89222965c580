//! Concrete perforation validation and throughput (seed 001 sec. 4): one shot at the tests'
//! mean impact velocity (458.1 m/s, measured exit 190 +/- 14 m/s) for each slab element size,
//! tensile option and thread count: the exit velocity, the modified-NDRC exit velocity, the
//! energy error, the rear-face damage-zone diameter, the element-cycles per second and the wall
//! time.
//!
//! Run: `cargo bench -p stoss --bench perforation` (10 mm on 1 and 2 threads, both tensile
//! options; 5 mm on 2 threads: about 10 minutes on 2 cores). The figures are in docs/solver.md.

use std::path::PathBuf;
use std::time::Instant;
use stoss::analytic::concrete::{modified_ndrc, ndrc_ogive_nose_factor, ConcreteShot};
use stoss::experiment::perforation::{concrete_shot, rear_damage_diameter};
use stoss::experiment::{Experiment, Setup};
use stoss::input::material;
use stoss::solver::SolverSettings;
use stoss_kernel::rht::TensileFailure;
use stoss_kernel::PartMaterial;

fn main() {
    let fixtures = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures");
    let path = fixtures.join("experiments/perforation-concrete-152mm.toml");
    let experiment = Experiment::load(&path).expect("fixture loads");
    let (_, slab) = material::load_part(&experiment.default_material_path().expect("material"))
        .expect("material loads");
    let Setup::Perforation(spec) = &experiment.file.setup else {
        panic!("not a perforation experiment");
    };
    let velocity = 458.1;
    let cases = [
        (10.0e-3, TensileFailure::HydroTensileLimit, 1),
        (10.0e-3, TensileFailure::HydroTensileLimit, 2),
        (10.0e-3, TensileFailure::PressureCutoff, 2),
        (5.0e-3, TensileFailure::HydroTensileLimit, 2),
    ];
    println!(
        "| slab element | tensile option | threads | exit (m/s) | measured | NDRC | energy error | rear damage diameter (m) | elements | element-cycles/s | wall (s) |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for (size, tension, threads) in cases {
        let mut spec = spec.clone();
        spec.element_size = size;
        let mut concrete = *slab.rht().expect("an RHT slab");
        concrete.parameters.tensile_failure = tension;
        let target = PartMaterial::from(concrete);
        let settings = SolverSettings {
            threads: Some(threads),
            ..SolverSettings::default()
        };
        let started = Instant::now();
        let shot = match spec.fire(&target, velocity, &settings) {
            Ok(shot) => shot,
            Err(error) => {
                println!(
                    "| {:.0} mm | {tension:?} | {threads} | failed: {error} |",
                    size * 1e3
                );
                continue;
            }
        };
        let wall = started.elapsed().as_secs_f64();
        let ndrc = concrete_shot(&spec, &target)
            .ok()
            .map(|s| ConcreteShot { velocity, ..s })
            .and_then(|s| {
                modified_ndrc(
                    &s,
                    spec.plate_thickness,
                    ndrc_ogive_nose_factor(s.caliber_radius_head),
                )
                .ok()
            })
            .map_or(f64::NAN, |n| n.residual_velocity);
        let diameter = rear_damage_diameter(&spec, &shot.field);
        let elements = shot.field.mesh.elements.len();
        println!(
            "| {:.0} mm | {tension:?} | {threads} | {:.1} | 190 +/- 14 | {:.1} | {:+.3} % | {:.2} | {} | {:.3e} | {:.1} |",
            size * 1e3,
            shot.residual_velocity,
            ndrc,
            shot.energy.error_percent(),
            diameter,
            elements,
            shot.element_cycles as f64 / wall,
            wall,
        );
    }
}

//! Long-rod penetration validation and throughput (seed 000 experiments 1 and 2): for each
//! element size and thread count, the final nose depth against the recording and the
//! Walker–Anderson cross-check, the energy error, the surface interpenetration, the
//! element-cycles per second, the wall time and the contact's share of it.
//!
//! Run: `cargo bench -p stoss --bench penetration` (0.4 mm on 1 and 2 threads, 0.2 mm on 2
//! threads, both shots: about 10 minutes on 2 cores). `STOSS_FINE=1` adds the 0.1 mm mesh
//! of the 1700 m/s shot (about 20 minutes more). The figures are in docs/solver.md.

use std::path::PathBuf;
use std::time::Instant;
use stoss::analytic::penetration::depth_at;
use stoss::experiment::{Experiment, Setup};
use stoss::input::material;
use stoss::solver::SolverSettings;

fn main() {
    let fixtures = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures");
    let mut cases = vec![
        ("penetration-hzb-1250", 0.4e-3, 1),
        ("penetration-hzb-1250", 0.4e-3, 2),
        ("penetration-hzb-1250", 0.2e-3, 2),
        ("penetration-hzb-1700", 0.4e-3, 1),
        ("penetration-hzb-1700", 0.4e-3, 2),
        ("penetration-hzb-1700", 0.2e-3, 2),
    ];
    if std::env::var_os("STOSS_FINE").is_some() {
        cases.push(("penetration-hzb-1700", 0.1e-3, 2));
    }
    println!(
        "| shot | element | threads | nose depth (mm) at t | recorded | Walker-Anderson | energy error | interpenetration / element | elements | element-cycles/s | wall (s) | contact share |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    for (name, size, threads) in cases {
        let path = fixtures.join(format!("experiments/{name}.toml"));
        let experiment = Experiment::load(&path).expect("fixture loads");
        let (_, target) = material::load(&experiment.default_material_path().expect("material"))
            .expect("material loads");
        let Setup::Penetration(spec) = &experiment.file.setup else {
            panic!("{name} is not a penetration experiment");
        };
        let mut spec = spec.clone();
        spec.element_size = size;
        let settings = SolverSettings {
            threads: Some(threads),
            ..SolverSettings::default()
        };
        let started = Instant::now();
        let (result, run, built) = match spec.run(&target.into(), &settings) {
            Ok(done) => done,
            Err(error) => {
                println!(
                    "| {name} | {:.1} mm | {threads} | failed: {error} | | | | | | | {:.1} | |",
                    size * 1e3,
                    started.elapsed().as_secs_f64()
                );
                continue;
            }
        };
        let wall = started.elapsed().as_secs_f64();
        let point = &experiment.recording[experiment.recording.len() - 1];
        let check = spec.cross_check(&target).expect("cross-check");
        println!(
            "| {name} | {:.1} mm | {threads} | {:.2} at {:.1} us | {:.2} | {:.2} | {:+.3} % | {:.3} | {} | {:.3e} | {:.1} | {:.1} % |",
            size * 1e3,
            stoss::measure::interpolate(&result.nose_depth, point.position) * 1e3,
            point.position * 1e6,
            point.value * 1e3,
            depth_at(&check.walker_anderson, point.position) * 1e3,
            run.energy().error_percent(),
            run.contact.largest_penetration / built.smallest_element,
            built.model.mesh.elements.len(),
            run.element_cycles as f64 / wall,
            wall,
            100.0 * run.contact.seconds / wall,
        );
    }
}

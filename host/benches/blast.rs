//! Blast-load and blast-plate figures (issue "near-field blast-bulged plate"): the Euler load
//! per charge at two cell sizes (wall time, cell updates per second, impulse on the exposed
//! plate and at its centre), the Euler reflected impulse of 1 kg TNT at 1, 2 and 3 m against
//! Kingery-Bulmash on grids wide enough not to confine the wave, the cache hit from disk,
//! and one plate simulation per fixture at the calibration mesh.
//!
//! Run: `cargo bench -p stoss --bench blast` (about 10 minutes on 2 cores). The figures are in
//! docs/solver.md, "Blast load and the blast-bulged plate".

use std::path::PathBuf;
use std::time::Instant;
use stoss::blast::cache;
use stoss::experiment::blast_plate::Coupling;
use stoss::experiment::{Experiment, Setup};
use stoss::input::material;
use stoss::solver::SolverSettings;
use stoss::validate::blast::{charge_load, tnt_reflected_impulse};

fn main() {
    let fixtures = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures");
    let folder = std::env::temp_dir().join(format!("stoss-bench-blast-{}", std::process::id()));
    let names = ["blast-hha-37g-13mm", "blast-hha-57g-25mm"];

    println!("## Euler load per charge (2 threads)\n");
    println!("| charge | cell | cells | steps | wall (s) | cell updates/s | impulse r<=200 mm (N s) | centre impulse (Pa s) | peak (GPa) |");
    println!("|---|---|---|---|---|---|---|---|---|");
    for name in names {
        for cell in [1.0e-3, 0.5e-3] {
            let clock = Instant::now();
            let load = charge_load(&fixtures, &format!("experiments/{name}.toml"), cell)
                .expect("Euler run");
            let wall = clock.elapsed().as_secs_f64();
            println!(
                "| {name} | {:.1} mm | {} | {} | {wall:.1} | {:.2e} | {:.2} | {:.0} | {:.2} |",
                cell * 1e3,
                load.run.cells,
                load.run.steps,
                load.run.cell_updates as f64 / wall,
                load.impulse,
                load.centre_impulse,
                load.run.wall.peak().0 / 1e9
            );
        }
    }

    println!(
        "\n## 1 kg TNT, reflected impulse at the axis against Kingery-Bulmash (10 mm cells)\n"
    );
    println!("| height (m) | grid radius (m) | Euler (Pa s) | Kingery-Bulmash (Pa s) | difference | wall (s) |");
    println!("|---|---|---|---|---|---|");
    for height in [1.0, 2.0, 3.0] {
        let clock = Instant::now();
        let (positive, expected) = tnt_reflected_impulse(height).expect("Euler run");
        println!(
            "| {height:.1} | {:.1} | {positive:.1} | {expected:.1} | {:+.1} % | {:.1} |",
            1.2 * height,
            100.0 * (positive / expected - 1.0),
            clock.elapsed().as_secs_f64()
        );
    }

    println!("\n## Cache and plate (2 threads, calibration mesh)\n");
    for name in names {
        let path = fixtures.join(format!("experiments/{name}.toml"));
        let mut experiment = Experiment::load(&path).expect("fixture loads");
        let (_, steel) = material::load(&experiment.default_material_path().expect("material"))
            .expect("material loads");
        let Setup::BlastPlate(spec) = &mut experiment.file.setup else {
            panic!("{name} is not a blast plate");
        };
        spec.cache_folder = Some(folder.clone());
        let clock = Instant::now();
        let computed = spec.load().expect("load");
        let computing = clock.elapsed().as_secs_f64();
        cache::forget_memory();
        let clock = Instant::now();
        let from_disk = spec.load().expect("load");
        let reading = clock.elapsed().as_secs_f64();
        assert_eq!(computed.wall, from_disk.wall);
        println!("{name}: load computed {computing:.1} s, read from disk {reading:.3} s");
        for coupling in [Coupling::OneWay, Coupling::TwoWay] {
            spec.coupling = coupling;
            let clock = Instant::now();
            let (result, run, model) = spec
                .run(&steel, &SolverSettings::default())
                .expect("plate run");
            let wall = clock.elapsed().as_secs_f64();
            println!(
            "{name} {coupling:?}: plate {} elements, \
             {:.2e} element-cycles in {wall:.1} s ({:.2e}/s), shape read at {:.2} ms, peak {:.2} mm, \
             impulse {:.2} N s, 95 % of it by {:.1} us with the centre {:.2} mm away, energy error {:+.3} %",
            model.mesh.elements.len(),
            run.element_cycles as f64,
            run.element_cycles as f64 / wall,
            result.settled_at * 1e3,
            result.peak() * 1e3,
            result.load_impulse,
            result.load_time * 1e6,
            result.deflection_at_load_time * 1e3,
            run.energy().error_percent()
        );
        }
    }
    let _ = std::fs::remove_dir_all(&folder);
}

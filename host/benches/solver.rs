//! Solver throughput: element-cycles per second of the axisymmetric solver with the JC 4340
//! material on 1 and 2 threads, and the wall time of one Taylor run at the mesh a calibration
//! uses (8 elements across the radius), and the 3D hexahedral solver on the quarter rod.
//! Run: `cargo bench -p stoss --bench solver`.

use divan::counter::ItemsCount;
use divan::Bencher;
use stoss::experiment::TaylorSpec;
use stoss::solver::SolverSettings;
use stoss_kernel::Material;

fn main() {
    divan::main();
}

/// The 343 m/s 4340 rod (8.1 x 7.62 mm) at `radial` elements across the radius.
fn taylor(radial: usize, threads: usize) -> (TaylorSpec, SolverSettings) {
    (
        TaylorSpec::new(8.1e-3, 7.62e-3, 343.0, radial),
        SolverSettings {
            threads: Some(threads),
            ..SolverSettings::default()
        },
    )
}

#[divan::bench(args = [1, 2], sample_count = 5, sample_size = 1)]
fn axisymmetric_element_cycles(bencher: Bencher, threads: usize) {
    let (spec, settings) = taylor(16, threads);
    let material = Material::STEEL_4340;
    // Count element-cycles of one run to report throughput.
    let cycles = spec.run(&material, &settings).unwrap().1.element_cycles;
    bencher
        .counter(ItemsCount::new(cycles as usize))
        .bench(|| spec.run(&material, &settings).unwrap().0.final_length);
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn taylor_208_run_at_calibration_mesh(bencher: Bencher) {
    let spec = TaylorSpec::new(25.4e-3, 7.62e-3, 208.0, 8);
    let settings = SolverSettings::default();
    bencher.bench(|| {
        spec.run(&Material::STEEL_4340, &settings)
            .unwrap()
            .0
            .final_length
    });
}

#[divan::bench(args = [1, 2], sample_count = 3, sample_size = 1)]
fn hexahedral_element_cycles(bencher: Bencher, threads: usize) {
    let (spec, settings) = taylor(8, threads);
    let material = Material::STEEL_4340;
    let cycles = spec.run_3d(&material, &settings).unwrap().1.element_cycles;
    bencher
        .counter(ItemsCount::new(cycles as usize))
        .bench(|| spec.run_3d(&material, &settings).unwrap().0);
}

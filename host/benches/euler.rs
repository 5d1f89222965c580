//! The Eulerian penetration solver (host/src/euler) against the recordings and the analytic
//! models, and its speed. The figures are in docs/euler.md.
//!
//! GOAL / SETUP / REFERENCE per section:
//! - `shots`: seed 000's two long-rod shots (fixtures/experiments/penetration-hzb-*.toml) on
//!   the Eulerian solver at the calibration cell (0.4 mm; 0.2 mm too with `fine`): final nose
//!   depth against the radiograph (Anderson et al. 1995) and Walker–Anderson, energy error,
//!   wall time, cell-cycles per second.
//! - `strength`: the 1250 m/s rod into a semi-infinite (80 mm) target made elastic-perfectly
//!   plastic at A = 0.5 ... 4 GPa, to 30 us: the penetration rate 10-30 us against
//!   Walker–Anderson's (IJIE 17 (1995) 19), and the crater radius one rod diameter above the
//!   nose against Walker–Anderson's fit (1.59 a at 1250 m/s).
//! - `smooth`: the final depth of the 1250 m/s shot at 1244 / 1250 / 1256 m/s and at the
//!   target's A times 0.99 / 1 / 1.01: monotone, and the largest deviation from the straight
//!   line through the ends.
//! - `threads`: the 1250 m/s shot to 20 us on 1 and 2 threads: speed-up and identical depth.
//! - `crater`: the crater radius of the 1250 m/s shot as the eroding model's is measured, the
//!   target's A varied; `crater-heating` (on demand): the bundled target with and without its
//!   thermal softening; `crater-velocity` (on demand): the bundled target struck at 1250 and
//!   1700 m/s against Walker–Anderson's 1.59 a and 1.92 a.
//! - `converge` (on demand, about 25 minutes): the 1250 m/s shot at 0.4, 0.2 and 0.1 mm cells,
//!   for the 0.2 / 0.1 mm criterion (3 %).
//!
//! Run: `cargo bench -p stoss --bench euler` (about 10 minutes on 2 cores); choose sections
//! with `STOSS_EULER_BENCH=shots,fine`.

mod semi_infinite;

use semi_infinite::{perfectly_plastic, shot};
use std::path::PathBuf;
use std::time::Instant;
use stoss::analytic::penetration::{default_crater_radius, depth_at};
use stoss::experiment::penetration::euler::{EulerPenetration, TARGET};
use stoss::experiment::penetration::PenetrationSolver;
use stoss::experiment::{Experiment, PenetrationSpec, Setup};
use stoss::input::material;
use stoss::measure::interpolate;
use stoss::solver::SolverSettings;
use stoss_kernel::PartMaterial;

fn sections() -> String {
    std::env::var("STOSS_EULER_BENCH")
        .unwrap_or_else(|_| "shots,strength,smooth,crater,threads".into())
}

fn fixture(name: &str) -> (PenetrationSpec, PartMaterial) {
    let fixtures = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures");
    let experiment =
        Experiment::load(&fixtures.join(format!("experiments/{name}"))).expect("fixture loads");
    let Setup::Penetration(spec) = &experiment.file.setup else {
        panic!("not a penetration experiment");
    };
    let (_, target) =
        material::load(&experiment.default_material_path().expect("material")).expect("target");
    let mut spec = spec.clone();
    spec.solver = PenetrationSolver::Euler;
    (spec, target.into())
}

fn settings(threads: usize) -> SolverSettings {
    SolverSettings {
        threads: Some(threads),
        ..SolverSettings::default()
    }
}

/// The crater radius one rod diameter above the nose: the distance from the axis to the
/// first cell at least half full of target in that row.
fn crater_radius(run: &EulerPenetration, nose: f64, diameter: f64) -> f64 {
    let s = &run.solver;
    let row = ((nose + diameter - s.origin_z) / s.grid.spacing_z) as usize;
    (0..s.grid.cells_r)
        .find(|&i| s.fraction(row * s.grid.cells_r + i, TARGET) >= 0.5)
        .map_or(f64::NAN, |i| i as f64 * s.grid.spacing_r)
}

fn shots(names: &[&str], cells: &[f64]) {
    println!("| shot | cell (mm) | nose depth (mm) | recorded (mm) | Walker–Anderson (mm) | FE / recorded | energy error | cells | cycles | wall (s) | material-cell updates / s |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for &name in names {
        let (base, target) = fixture(name);
        let recorded = if name.contains("1250") { 23.2 } else { 45.6 };
        for &h in cells {
            let spec = PenetrationSpec {
                element_size: h,
                ..base.clone()
            };
            let started = Instant::now();
            let run = spec.run_euler(&target, &settings(2));
            let wall = started.elapsed().as_secs_f64();
            match run {
                Ok(run) => {
                    let depth = run.result.nose_depth.last().unwrap().1 * 1e3;
                    let wa = spec
                        .cross_check(target.j2().unwrap())
                        .map(|c| depth_at(&c.walker_anderson, spec.end_time) * 1e3)
                        .unwrap_or(f64::NAN);
                    let s = &run.solver;
                    println!(
                        "| {} m/s | {:.2} | {depth:.2} | {recorded:.1} | {wa:.2} | {:.3} | {:+.2} % | {} | {} | {wall:.1} | {:.2e} |",
                        spec.velocity,
                        h * 1e3,
                        depth / recorded,
                        run.energy().error_percent(),
                        s.grid.cell_count(),
                        s.cycles,
                        s.material_updates as f64 / wall,
                    );
                }
                Err(error) => println!(
                    "| {} m/s | {:.2} | failed: {error} |",
                    spec.velocity,
                    h * 1e3
                ),
            }
        }
    }
}

fn strength() {
    let shot = shot();
    let mut spec = shot.spec;
    spec.solver = PenetrationSolver::Euler;
    spec.rod = Some(Box::new(
        perfectly_plastic(shot.rod.clone(), 1.506e9, None).into(),
    ));
    println!("| target A (GPa) | P(10 us) FE / WA (mm) | P(30 us) FE / WA (mm) | rate 10-30 us FE / WA (mm/us) | FE / WA | crater radius / a (FE, WA) | energy error | wall (s) |");
    println!("|---|---|---|---|---|---|---|---|");
    for a in [0.5, 1.0, 1.5, 2.0, 3.0, 4.0] {
        let target = perfectly_plastic(shot.target.clone(), a * 1e9, None);
        let check = spec.cross_check(&target).expect("cross-check");
        let started = Instant::now();
        match spec.run_euler(&target.into(), &settings(2)) {
            Ok(run) => {
                let fe = |t: f64| interpolate(&run.result.nose_depth, t) * 1e3;
                let wa = |t: f64| depth_at(&check.walker_anderson, t) * 1e3;
                let fe_rate = (fe(30e-6) - fe(10e-6)) / 20.0;
                let wa_rate = (wa(30e-6) - wa(10e-6)) / 20.0;
                let nose = -fe(30e-6) * 1e-3;
                let radius =
                    crater_radius(&run, nose, spec.rod_diameter) / (0.5 * spec.rod_diameter);
                let wa_radius = default_crater_radius(spec.rod_diameter, spec.velocity)
                    .expect("crater radius")
                    / (0.5 * spec.rod_diameter);
                println!(
                    "| {a:.1} | {:.2} / {:.2} | {:.2} / {:.2} | {fe_rate:.3} / {wa_rate:.3} | {:.3} | {radius:.2}, {wa_radius:.2} | {:+.2} % | {:.1} |",
                    fe(10e-6),
                    wa(10e-6),
                    fe(30e-6),
                    wa(30e-6),
                    fe_rate / wa_rate,
                    run.energy().error_percent(),
                    started.elapsed().as_secs_f64()
                );
            }
            Err(error) => println!("| {a:.1} | failed: {error} | | | | | | |"),
        }
    }
}

/// The crater measured as the eroding Lagrangian model's is (`penetration_crater` bench): the
/// same shots (the fixture's 1250 m/s rod into an 80 mm HzB-W target, its JC `A` varied),
/// averaged over 10-30 us, `R_c` the radius at which the target's volume fraction crosses one
/// half (between cell centres) in the rows one to three rod radii above the nose.
fn crater() {
    let shot = shot();
    println!("| target A (GPa) | element | rate FE / WA | R_c / a, 1-3 a above the nose (WA 1.59) | at the head, 0-1 a | wall (s) |");
    println!("|---|---|---|---|---|---|");
    for element in [0.4e-3, 0.2e-3] {
        for yield_stress in [0.5, 1.0, 1.5, 2.0, 3.0, 4.0] {
            let mut file = shot.target.clone();
            file.set_constant("strength.yield_stress", yield_stress * 1e9)
                .expect("a Johnson-Cook target");
            crater_row(
                &format!("{yield_stress:.1}"),
                &file,
                element,
                shot.spec.velocity,
                "",
            );
        }
    }
}

/// The same crater for the bundled HzB-W target as it is and made isothermal (its thermal
/// softening switched off): whether the target's heating widens the crater.
fn crater_heating() {
    let shot = shot();
    println!("| target | element | rate FE / WA | R_c / a, 1-3 a above the nose (WA 1.59) | at the head, 0-1 a | wall (s) |");
    println!("|---|---|---|---|---|---|");
    for element in [0.4e-3, 0.2e-3] {
        crater_row(
            "HzB-W, adiabatic",
            &shot.target,
            element,
            shot.spec.velocity,
            "",
        );
        let mut file = shot.target.clone();
        file.heating = stoss_kernel::Heating::Isothermal;
        crater_row("HzB-W, isothermal", &file, element, shot.spec.velocity, "");
    }
}

/// The crater of the bundled HzB-W target struck at 1250 and 1700 m/s (seed 000's two
/// velocities), against the `awcsc` default radius Walker–Anderson use.
fn crater_velocity() {
    let shot = shot();
    println!("| velocity (m/s) | element | rate FE / WA | R_c / a, 1-3 a above the nose | at the head, 0-1 a | WA R_c / a | wall (s) |");
    println!("|---|---|---|---|---|---|---|");
    for element in [0.4e-3, 0.2e-3] {
        for velocity in [1250.0, 1700.0] {
            let wa = default_crater_radius(shot.spec.rod_diameter, velocity)
                .expect("crater radius")
                / (0.5 * shot.spec.rod_diameter);
            let label = format!("{velocity:.0}");
            crater_row(
                &label,
                &shot.target,
                element,
                velocity,
                &format!(" {wa:.2} |"),
            );
        }
    }
}

/// One row of the crater tables: the rod striking `file` at `velocity` on `element` cells,
/// with `extra` columns (already formatted, each ending in `|`) before the wall time.
fn crater_row(
    label: &str,
    file: &material::MaterialFile,
    element: f64,
    velocity: f64,
    extra: &str,
) {
    let started = Instant::now();
    match stoss::validate::semi_infinite::euler_crater_at(
        &PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures"),
        file.clone(),
        element,
        velocity,
        Some(2),
    ) {
        Ok(crater) => println!(
            "| {label} | {:.1} mm | {:.2} | {:.2} | {:.2} |{extra} {:.0} |",
            element * 1e3,
            crater.rate_ratio,
            crater.behind_head,
            crater.at_head,
            started.elapsed().as_secs_f64()
        ),
        Err(error) => {
            let blanks = " |".repeat(extra.matches('|').count());
            println!(
                "| {label} | {:.1} mm | failed: {error} | | |{blanks} |",
                element * 1e3
            )
        }
    }
}

fn smooth() {
    // `stoss::validate::euler`, also the `euler-smooth-*` rows of `stoss validate`.
    let fixtures = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures");
    for (label, line) in [
        (
            "striking velocity (m/s)",
            stoss::validate::euler::by_velocity(&fixtures, Some(2)),
        ),
        (
            "A factor",
            stoss::validate::euler::by_strength(&fixtures, Some(2)),
        ),
    ] {
        let line = line.expect("runs");
        let depths: Vec<(f64, f64)> = line.points.iter().map(|&(x, d)| (x, d * 1e3)).collect();
        println!("{label} -> final depth (mm): {depths:?}");
        println!(
            "monotone {}, largest deviation from the line {:.3} %",
            line.monotone,
            line.largest_deviation * 100.0
        );
    }
}

fn threads() {
    let (base, target) = fixture("penetration-hzb-1250.toml");
    let spec = PenetrationSpec {
        end_time: 20e-6,
        ..base
    };
    let mut depths = Vec::new();
    let mut walls = Vec::new();
    for threads in [1, 2] {
        let started = Instant::now();
        let run = spec.run_euler(&target, &settings(threads)).expect("run");
        walls.push(started.elapsed().as_secs_f64());
        depths.push(run.result.nose_depth.last().unwrap().1);
    }
    println!(
        "threads 1 / 2: {:.1} s / {:.1} s, speed-up {:.2}; depths identical: {}",
        walls[0],
        walls[1],
        walls[0] / walls[1],
        depths[0].to_bits() == depths[1].to_bits()
    );
}

fn main() {
    let sections = sections();
    if sections.contains("shots") {
        let cells: &[f64] = if sections.contains("fine") {
            &[0.4e-3, 0.2e-3]
        } else {
            &[0.4e-3]
        };
        shots(
            &["penetration-hzb-1250.toml", "penetration-hzb-1700.toml"],
            cells,
        );
    }
    if sections.contains("converge") {
        shots(&["penetration-hzb-1250.toml"], &[0.4e-3, 0.2e-3, 0.1e-3]);
    }
    if sections.contains("strength") {
        strength();
    }
    if sections.contains("smooth") {
        smooth();
    }
    if sections.split(',').any(|s| s == "crater-velocity") {
        crater_velocity();
    }
    if sections.split(',').any(|s| s == "crater-heating") {
        crater_heating();
    }
    if sections.split(',').any(|s| s == "crater") {
        crater();
    }
    if sections.contains("threads") {
        threads();
    }
}

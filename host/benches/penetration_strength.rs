//! How the eroding Lagrangian model's penetration rate follows the target's strength, against
//! Walker–Anderson (the issue-10 accuracy question: the 1250 m/s shot over-penetrates).
//!
//! GOAL: separate a bias of the FE model (element erosion, eroding contact) from a bias of
//! the target's constants. If the FE resistance followed the target's strength as
//! Walker–Anderson's cavity-expansion term does, the FE and Walker–Anderson depths would
//! stay in a fixed ratio as the yield stress changes.
//!
//! SETUP: seed 000's 1250 m/s WHA rod (`fixtures/experiments/penetration-hzb-1250.toml`,
//! 0.4 mm mesh) into a semi-infinite HzB-W target (80 mm, so the rear face plays no part in
//! the first 30 us), the target's Johnson-Cook `A` set to 0.5 ... 4 GPa (B, n, C, m, EoS and
//! the 150 % geometric-strain erosion as in the fixture); at the default time-step safety
//! and at 0.3 (a stiffer eroding-contact penalty, `k ~ 1/dt0^2`).
//!
//! REFERENCE: Walker & Anderson, IJIE 17 (1995) 19-48 (`stoss::analytic::penetration`),
//! with the same strengths (each material's flow stress at zero strain and rate).
//!
//! Run: `cargo bench -p stoss --bench penetration_strength` (about 2 minutes on 2 cores).
//! The figures are in docs/solver.md ("Accuracy").

mod semi_infinite;

use semi_infinite::shot;
use std::time::Instant;
use stoss::analytic::penetration::depth_at;
use stoss::measure::interpolate;
use stoss::solver::SolverSettings;

fn main() {
    let shot = shot();
    let (spec, file) = (shot.spec, shot.target);
    println!(
        "| target A (GPa) | safety | P(10 us) FE / WA (mm) | P(30 us) FE / WA (mm) | rate 10-30 us FE / WA (mm/us) | FE / WA | rod length at 30 us (mm) | largest tolerated exposure / element | energy error | wall (s) |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    let cases = [
        (0.5, None),
        (1.0, None),
        (1.5, None),
        (2.0, None),
        (3.0, None),
        (4.0, None),
        (1.5, Some(0.3)),
        (4.0, Some(0.3)),
    ];
    for (yield_stress, safety) in cases {
        let mut target_file = file.clone();
        target_file
            .set_constant("strength.yield_stress", yield_stress * 1e9)
            .expect("a Johnson-Cook target");
        let target = target_file.material().expect("valid target");
        let mut settings = SolverSettings {
            threads: Some(2),
            ..SolverSettings::default()
        };
        if let Some(safety) = safety {
            settings.time_step_safety = safety;
        }
        let check = spec.cross_check(&target).expect("cross-check");
        let started = Instant::now();
        let label = safety.map_or("default".to_string(), |s| format!("{s}"));
        match spec.run(&target.into(), &settings) {
            Ok((result, run, built)) => {
                let fe = |t: f64| interpolate(&result.nose_depth, t) * 1e3;
                let wa = |t: f64| depth_at(&check.walker_anderson, t) * 1e3;
                let fe_rate = (fe(30e-6) - fe(10e-6)) / 20.0;
                let wa_rate = (wa(30e-6) - wa(10e-6)) / 20.0;
                println!(
                    "| {yield_stress:.1} | {label} | {:.2} / {:.2} | {:.2} / {:.2} | {fe_rate:.3} / {wa_rate:.3} | {:.2} | {:.2} | {:.2} | {:+.2} % | {:.1} |",
                    fe(10e-6),
                    wa(10e-6),
                    fe(30e-6),
                    wa(30e-6),
                    fe_rate / wa_rate,
                    interpolate(&result.rod_length, 30e-6) * 1e3,
                    run.contact.largest_initial_penetration / built.smallest_element,
                    run.energy().error_percent(),
                    started.elapsed().as_secs_f64(),
                );
            }
            Err(error) => {
                println!("| {yield_stress:.1} | {label} | failed: {error} | | | | | | | |")
            }
        }
    }
}

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
//! The figures are in docs/solver.md ("Accuracy"); the FE / WA column is the
//! `lagrange-strength-*` rows of `stoss validate` (`stoss::validate::semi_infinite`).

use std::path::PathBuf;
use std::time::Instant;
use stoss::validate::semi_infinite::lagrange_strength;

fn main() {
    let fixtures = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures");
    println!(
        "| target A (GPa) | safety | P(10 us) FE / WA (mm) | P(30 us) FE / WA (mm) | FE / WA | rod length at 30 us (mm) | largest tolerated exposure / element | energy error | wall (s) |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
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
        let started = Instant::now();
        let label = safety.map_or("default".to_string(), |s| format!("{s}"));
        match lagrange_strength(&fixtures, yield_stress * 1e9, safety, Some(2)) {
            Ok(run) => {
                let ((fe10, wa10), (fe30, wa30)) = run.depths;
                println!(
                    "| {yield_stress:.1} | {label} | {:.2} / {:.2} | {:.2} / {:.2} | {:.2} | {:.2} | {:.2} | {:+.2} % | {:.1} |",
                    fe10 * 1e3,
                    wa10 * 1e3,
                    fe30 * 1e3,
                    wa30 * 1e3,
                    run.rate_ratio,
                    run.rod_length * 1e3,
                    run.exposure,
                    run.energy_error,
                    started.elapsed().as_secs_f64(),
                );
            }
            Err(error) => println!("| {yield_stress:.1} | {label} | failed: {error} | | | | | | |"),
        }
    }
}

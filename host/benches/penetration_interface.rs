//! Which side of the eroding interface carries the long-rod bias (issue 10): Tate's interface
//! balance `1/2 rho_p (v - u)^2 + Y_p = 1/2 rho_t u^2 + R_t` read off the FE run with one or
//! both materials near-fluid.
//!
//! GOAL: separate the hydrodynamic transfer across the eroding interface, the rod's strength
//! and the target's resistance. With both materials near-fluid the FE penetration rate must be
//! Bernoulli's `u = v / (1 + sqrt(rho_t / rho_p))`; with only the rod strong, the rod's
//! strength read off the balance must be its yield stress; with only the target strong, the
//! target's `R_t` read off the balance is compared with the static cavity-expansion pressures.
//!
//! SETUP: `fixtures/experiments/penetration-hzb-1250.toml` with an 80 mm (semi-infinite)
//! target, 1250 m/s; rod and target elastic-perfectly plastic and isothermal (Y 0.02 GPa for
//! "near-fluid", else rod 1.5 GPa, target 1.45 GPa); 0.4 and 0.2 mm (and 0.1 mm with
//! `STOSS_FINE=1`), 2 threads. The rate is the nose depth's gain from 10 to 30 us; `v` the
//! rod's mass-averaged velocity, averaged over the same window.
//!
//! REFERENCE: Bernoulli (both near-fluid); the rod's yield stress; Hill's static spherical
//! cavity pressure `2/3 Y (1 + ln(E / (3 (1 - nu) Y)))` (5.0 GPa, 3.45 Y) and Walker &
//! Anderson's `7/3 Y ln(alpha)` (Walker & Anderson, IJIE 17 (1995) 19-48).
//!
//! Run: `cargo bench -p stoss --bench penetration_interface` (about 3 minutes on 2 cores; 20 with
//! `STOSS_FINE=1`). The figures are in docs/solver.md ("Accuracy").

mod semi_infinite;

use semi_infinite::{perfectly_plastic, shot};
use std::time::Instant;
use stoss::measure::interpolate;
use stoss::solver::SolverSettings;

fn main() {
    let shot = shot();
    let (rod_density, target_density) = (shot.rod.density, shot.target.density);
    let mut elements = vec![0.4e-3, 0.2e-3];
    if std::env::var_os("STOSS_FINE").is_some() {
        elements.push(0.1e-3);
    }
    let fluid = 0.02e9;
    let cases = [
        ("both near-fluid", fluid, fluid),
        ("rod strong, target near-fluid", 1.5e9, fluid),
        ("rod near-fluid, target strong", fluid, 1.45e9),
        ("both strong", 1.5e9, 1.45e9),
    ];
    println!(
        "| case | element | FE rate u (m/s) | rod velocity v (m/s) | Bernoulli u (m/s) | R_t - Y_p from the balance (GPa) | hourglass / internal energy | wall (s) |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for (label, rod_yield, target_yield) in cases {
        for &element in &elements {
            let started = Instant::now();
            let mut spec = shot.spec.clone();
            spec.element_size = element;
            spec.rod = Some(Box::new(
                perfectly_plastic(shot.rod.clone(), rod_yield, None).into(),
            ));
            let target = perfectly_plastic(shot.target.clone(), target_yield, None);
            let settings = SolverSettings {
                threads: Some(2),
                ..SolverSettings::default()
            };
            let (result, run, _) = match spec.run(&target.into(), &settings) {
                Ok(outcome) => outcome,
                Err(error) => {
                    println!("| {label} | {:.1} mm | failed: {error} |", element * 1e3);
                    continue;
                }
            };
            let depth = |t: f64| interpolate(&result.nose_depth, t);
            let velocity = |t: f64| interpolate(&result.rod_velocity, t);
            let u = (depth(30e-6) - depth(10e-6)) / 20e-6;
            let v = 0.5 * (velocity(10e-6) + velocity(30e-6));
            let bernoulli = v / (1.0 + (target_density / rod_density).sqrt());
            let balance = 0.5 * rod_density * (v - u).powi(2) - 0.5 * target_density * u * u;
            let energy = run.energy();
            println!(
                "| {label} | {:.1} mm | {u:.1} | {v:.1} | {bernoulli:.1} | {:.2} | {:.2} | {:.0} |",
                element * 1e3,
                balance / 1e9,
                energy.hourglass / energy.internal,
                started.elapsed().as_secs_f64()
            );
        }
    }
}

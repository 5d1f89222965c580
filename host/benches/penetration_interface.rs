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
//! Two more tables take each side alone, without the eroding interface between them:
//!
//! - **The target under a rigid nose.** The rod made rigid with a hemispherical nose and pushed
//!   at a constant `u` (`PenetrationSpec::run_driven`) into the same target (1.45 GPa, eroding
//!   at its 150 % geometric strain); the mean face pressure over 10-14 mm against Forrestal's
//!   `sigma_s + N* B rho u^2` (`N*` = 1/2 for a hemisphere, `B` 1 to 3/2; Forrestal, Okajima &
//!   Luk, J. Appl. Mech. 55 (1988) 755). With the FE's own `B` and Hill's `sigma_s`, the
//!   pressure at the nose's apex, where the normal velocity is `u`, is `sigma_s + B rho u^2`:
//!   the rate a Bernoulli rod at the striking velocity would reach against that centreline
//!   pressure is the target's side of Tate's balance alone, for comparison with
//!   Walker–Anderson's rate (380 m/s for this near-fluid rod).
//! - **The rod on a rigid wall.** The near-fluid rod against the target made a rigid body: a
//!   jet on a wall, whose force in the steady state is the momentum flux `rho_p A v^2` (the
//!   rod's material leaves along the wall). The force is the rod's momentum loss from 10 to
//!   28 us, its eroded mass included; the eroded material leaving backwards is the excess.
//!
//! A fourth takes the eroding interface whole (near-fluid or strong rod, strong target): the
//! force on the rod over 10-30 us (its momentum loss, eroded mass included), the radius `R` of
//! its head (the widest live rod node within one rod radius of the nose), the force per unit
//! head area `F / (pi R^2)` against Forrestal's face pressure at the FE's rate, and the final
//! axial velocity `w` of the eroded rod material from `F = Y_p A + rho_p A (v - u) (v - w)`.
//!
//! Run: `cargo bench -p stoss --bench penetration_interface` (about 5 minutes on 2 cores; 25
//! with `STOSS_FINE=1`). The figures are in docs/solver.md ("Accuracy").

mod semi_infinite;

use semi_infinite::{perfectly_plastic, shot, Shot};
use std::f64::consts::PI;
use std::ops::ControlFlow;
use std::time::Instant;
use stoss::analytic::penetration::spherical_cavity_pressure;
use stoss::experiment::penetration::{Nose, PenetrationModel};
use stoss::measure::interpolate;
use stoss::solver::{Discretisation, SolverSettings};
use stoss_kernel::{Material, PartMaterial};

const NEAR_FLUID: f64 = 0.02e9;
const TARGET_YIELD: f64 = 1.45e9;

fn settings() -> SolverSettings {
    SolverSettings {
        threads: Some(2),
        ..SolverSettings::default()
    }
}

fn main() {
    let shot = shot();
    let (rod_density, target_density) = (shot.rod.density, shot.target.density);
    let mut elements = vec![0.4e-3, 0.2e-3];
    if std::env::var_os("STOSS_FINE").is_some() {
        elements.push(0.1e-3);
    }
    let fluid = NEAR_FLUID;
    let cases = [
        ("both near-fluid", fluid, fluid),
        ("rod strong, target near-fluid", 1.5e9, fluid),
        ("rod near-fluid, target strong", fluid, TARGET_YIELD),
        ("both strong", 1.5e9, TARGET_YIELD),
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
            let (result, run, _) = match spec.run(&target.into(), &settings()) {
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
    println!();
    target_under_a_rigid_nose(&shot, &elements);
    println!();
    rod_on_a_rigid_wall(&shot, &elements);
    println!();
    eroding_rod_momentum(&shot, &elements);
}

/// The first one-sided table: the target's face pressure under a rigid hemisphere pushed at
/// the rates of the near-fluid rod (Walker–Anderson's, and the FE's at 0.2 and 0.4 mm).
fn target_under_a_rigid_nose(shot: &Shot, elements: &[f64]) {
    let target = perfectly_plastic(shot.target.clone(), TARGET_YIELD, None);
    let radius = 0.5 * shot.spec.rod_diameter;
    let area = PI * radius * radius;
    let hill = static_cavity_pressure(&target);
    let rod_density = shot.rod.density;
    println!(
        "Target under a rigid hemisphere: Hill's sigma_s = {:.2} GPa; a Bernoulli rod at the striking {:.0} m/s (a near-fluid rod does not slow) against the centreline pressure",
        hill / 1e9, shot.spec.velocity
    );
    println!(
        "| u (m/s) | element | FE face pressure (GPa) | Forrestal, B 1 to 3/2 (GPa) | (FE - rho u^2 / 2) / sigma_s | B = (FE - sigma_s) / (rho u^2 / 2) | Bernoulli rod's rate against sigma_s + B rho u^2 (m/s) | wall (s) |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for speed in [380.0, 455.0, 520.0] {
        for &element in elements {
            let started = Instant::now();
            let mut spec = shot.spec.clone();
            spec.element_size = element;
            spec.velocity = speed;
            spec.rod_length = 30.0e-3;
            spec.nose = Nose::Hemispherical;
            spec.end_time = 14.0e-3 / speed;
            spec.rod = Some(Box::new(
                perfectly_plastic(shot.rod.clone(), NEAR_FLUID, None).into(),
            ));
            let outcome = spec.run_driven(&PartMaterial::from(target), &settings(), 1.0e-3);
            let Ok(driven) = outcome else {
                println!("| {speed:.0} | {:.1} mm | failed |", element * 1e3);
                continue;
            };
            let late: Vec<f64> = driven
                .resistance
                .iter()
                .filter(|(depth, _)| *depth >= 10.0e-3)
                .map(|(_, force)| force / area)
                .collect();
            let face = late.iter().sum::<f64>() / late.len() as f64;
            let inertia = 0.5 * target.density * speed * speed;
            // The FE's dynamic coefficient B in the mean face pressure sigma_s + B rho u^2 / 2
            // (N* = 1/2); at the nose's apex, where the normal velocity is u, cavity-expansion
            // theory's pressure is sigma_s + B rho u^2. The rate u' at which a Bernoulli rod's
            // stagnation pressure 1/2 rho_p (v - u')^2 meets that centreline pressure.
            let k = (face - hill) / inertia;
            let v = shot.spec.velocity;
            let (mut low, mut high) = (0.0, v);
            for _ in 0..60 {
                let u = 0.5 * (low + high);
                let rod_side = 0.5 * rod_density * (v - u).powi(2);
                let target_side = hill + k * target.density * u * u;
                if rod_side > target_side {
                    low = u;
                } else {
                    high = u;
                }
            }
            println!(
                "| {speed:.0} | {:.1} mm | {:.2} | {:.2}-{:.2} | {:.3} | {k:.2} | {:.0} | {:.0} |",
                element * 1e3,
                face / 1e9,
                (hill + inertia) / 1e9,
                (hill + 1.5 * inertia) / 1e9,
                (face - inertia) / hill,
                0.5 * (low + high),
                started.elapsed().as_secs_f64()
            );
        }
    }
}

/// Hill's static spherical-cavity pressure of the perfectly plastic target (Pa).
fn static_cavity_pressure(target: &Material) -> f64 {
    let stoss_kernel::eos::Eos::MieGruneisen(eos) = target.eos else {
        panic!("the HzB-W file has a Mie-Grüneisen EoS");
    };
    let bulk = eos.reference_density * eos.sound_speed * eos.sound_speed;
    spherical_cavity_pressure(TARGET_YIELD, bulk, target.shear_modulus)
}

/// The rod's lumped nodal masses (whole ring, kg; zero off the rod) and its nodes.
fn rod_masses(built: &PenetrationModel, density: f64) -> (Vec<f64>, Vec<usize>) {
    let mesh = &built.model.mesh;
    let reference = mesh.reference_positions();
    let mut mass = vec![0.0; reference.len()];
    for &e in &built.rod_elements {
        let volume = mesh.element_volume(e, &reference);
        for &n in mesh.element_nodes(e) {
            mass[n] += 2.0 * PI * density * volume / 4.0;
        }
    }
    (mass, built.rod_nodes())
}

/// The second one-sided table: the near-fluid rod on the target made rigid, a jet on a wall.
fn rod_on_a_rigid_wall(shot: &Shot, elements: &[f64]) {
    println!(
        "Near-fluid rod on a rigid wall: force over the steady jet's rho_p A v^2, from the rod's momentum loss over 10-28 us"
    );
    println!(
        "| contact | element | force / rho_p A v^2 | eroded rod mass (g) | its backward momentum / initial momentum | wall (s) |"
    );
    println!("|---|---|---|---|---|---|");
    for self_contact in [false, true] {
        for &element in elements {
            let started = Instant::now();
            let mut spec = shot.spec.clone();
            spec.element_size = element;
            spec.self_contact = self_contact;
            spec.end_time = 28.0e-6;
            let rod = perfectly_plastic(shot.rod.clone(), NEAR_FLUID, None);
            let target = perfectly_plastic(shot.target.clone(), TARGET_YIELD, None);
            let Ok(mut built) = spec.model(&target.into(), &rod.into(), &settings()) else {
                println!("| - | {:.1} mm | failed to build |", element * 1e3);
                continue;
            };
            built.model.rigid_parts = vec![0];
            let mesh = &built.model.mesh;
            let (mass, rod_nodes) = rod_masses(&built, rod.density);
            let (start, end) = (built.impact_time + 10.0e-6, built.impact_time + 28.0e-6);
            let mut momentum: Vec<(f64, f64)> = Vec::new();
            let outcome = built.model.run_observed(&mut |snapshot| {
                let p: f64 = rod_nodes
                    .iter()
                    .map(|&n| mass[n] * snapshot.velocities[n][1])
                    .sum();
                momentum.push((snapshot.time, p));
                ControlFlow::Continue(())
            });
            let Ok(run) = outcome else {
                println!("| - | {:.1} mm | failed |", element * 1e3);
                continue;
            };
            let at = |t: f64| interpolate(&momentum, t);
            let force = (at(end) - at(start)) / (end - start);
            let area = PI * (0.5 * spec.rod_diameter).powi(2);
            let flux = rod.density * area * spec.velocity * spec.velocity;
            let mut live = vec![false; mass.len()];
            for &e in &built.rod_elements {
                if !run.eroded[e] {
                    for &n in mesh.element_nodes(e) {
                        live[n] = true;
                    }
                }
            }
            let (mut eroded_mass, mut backward) = (0.0, 0.0);
            for &n in rod_nodes.iter().filter(|&&n| !live[n]) {
                eroded_mass += mass[n];
                backward += mass[n] * run.velocities[n][1].max(0.0);
            }
            let initial: f64 = rod_nodes.iter().map(|&n| mass[n]).sum::<f64>() * spec.velocity;
            println!(
                "| {} | {:.1} mm | {:.3} | {:.2} | {:.3} | {:.0} |",
                if self_contact {
                    "single surface"
                } else {
                    "two-way (default)"
                },
                element * 1e3,
                force / flux,
                eroded_mass * 1e3,
                backward / initial,
                started.elapsed().as_secs_f64()
            );
        }
    }
}

/// The eroding interface as a whole: the force the target exerts on the rod (its momentum
/// loss, eroded mass included), the radius of the rod's head, and the force per unit head
/// area against the face pressure a rigid nose meets at the same rate (Forrestal's
/// `sigma_s + N* B rho u^2`). The eroded rod material's final axial velocity `w` follows from
/// the rod's momentum balance `F = Y_p A + m' (v - w)`, with `m' = rho_p A (v - u)` the
/// erosion rate: `w = 0` is material left at rest on the crater wall.
fn eroding_rod_momentum(shot: &Shot, elements: &[f64]) {
    let target = perfectly_plastic(shot.target.clone(), TARGET_YIELD, None);
    let hill = static_cavity_pressure(&target);
    let radius = 0.5 * shot.spec.rod_diameter;
    let area = PI * radius * radius;
    println!(
        "The eroding rod as a whole, 10-30 us: force on the rod F (its momentum loss), head radius R (widest live rod node within one rod radius of the nose)"
    );
    println!(
        "| rod | element | u (m/s) | v (m/s) | F (kN) | R (mm) | F / (pi R^2) (GPa) | Forrestal at u, B 1 to 3/2 (GPa) | eroded rod's final velocity w (m/s) | wall (s) |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for (label, rod_yield) in [("near-fluid", NEAR_FLUID), ("strong", 1.5e9)] {
        for &element in elements {
            let started = Instant::now();
            let mut spec = shot.spec.clone();
            spec.element_size = element;
            let rod = perfectly_plastic(shot.rod.clone(), rod_yield, None);
            let Ok(built) = spec.model(&target.into(), &rod.into(), &settings()) else {
                println!("| {label} | {:.1} mm | failed to build |", element * 1e3);
                continue;
            };
            let (mass, rod_nodes) = rod_masses(&built, rod.density);
            let mesh = &built.model.mesh;
            let (start, end) = (built.impact_time + 10.0e-6, built.impact_time + 30.0e-6);
            // Per snapshot: time, rod momentum, rod mass-averaged live velocity, nose, head.
            let mut history: Vec<[f64; 5]> = Vec::new();
            let outcome = built.model.run_observed(&mut |snapshot| {
                let momentum: f64 = rod_nodes
                    .iter()
                    .map(|&n| mass[n] * snapshot.velocities[n][1])
                    .sum();
                let live = built
                    .rod_elements
                    .iter()
                    .filter(|&&e| !snapshot.eroded[e])
                    .flat_map(|&e| mesh.element_nodes(e).iter().copied());
                let nose = live
                    .clone()
                    .map(|n| snapshot.positions[n][1])
                    .fold(f64::INFINITY, f64::min);
                let (mut head, mut live_mass, mut live_momentum) = (0.0f64, 0.0, 0.0);
                for n in live {
                    let p = snapshot.positions[n];
                    if p[1] < nose + radius {
                        head = head.max(p[0]);
                    }
                    live_mass += mass[n];
                    live_momentum += mass[n] * snapshot.velocities[n][1];
                }
                let velocity = if live_mass > 0.0 {
                    -live_momentum / live_mass
                } else {
                    0.0
                };
                history.push([snapshot.time, momentum, velocity, nose, head]);
                ControlFlow::Continue(())
            });
            if outcome.is_err() {
                println!("| {label} | {:.1} mm | failed |", element * 1e3);
                continue;
            }
            let column =
                |k: usize| -> Vec<(f64, f64)> { history.iter().map(|h| (h[0], h[k])).collect() };
            let (momentum, velocity, nose) = (column(1), column(2), column(3));
            let force =
                (interpolate(&momentum, end) - interpolate(&momentum, start)) / (end - start);
            let u = (interpolate(&nose, start) - interpolate(&nose, end)) / (end - start);
            let v = 0.5 * (interpolate(&velocity, start) + interpolate(&velocity, end));
            let window: Vec<f64> = history
                .iter()
                .filter(|h| h[0] >= start && h[0] <= end)
                .map(|h| h[4])
                .collect();
            let head = window.iter().sum::<f64>() / window.len() as f64;
            let inertia = 0.5 * target.density * u * u;
            let erosion_rate = rod.density * area * (v - u);
            let w = v - (force - rod_yield * area) / erosion_rate;
            println!(
                "| {label} | {:.1} mm | {u:.0} | {v:.0} | {:.0} | {:.2} | {:.2} | {:.2}-{:.2} | {w:.0} | {:.0} |",
                element * 1e3,
                force / 1e3,
                head * 1e3,
                force / (PI * head * head) / 1e9,
                (hill + inertia) / 1e9,
                (hill + 1.5 * inertia) / 1e9,
                started.elapsed().as_secs_f64()
            );
        }
    }
}

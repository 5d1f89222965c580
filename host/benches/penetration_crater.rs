//! The crater of the eroding Lagrangian model against the target's strength (issue 47, item
//! 1): does the eroded material that the model deletes (free mass points carrying no pressure)
//! explain why the model penetrates faster than Walker–Anderson as the target gets stronger?
//!
//! GOAL: confirm or kill the reading that the eroded rod material, which in the real flow
//! turns back as a pressurised layer over the whole crater floor, is missing: if so, the
//! rod's live head `R_h` is narrower than the crater `R_c`, the floor's traction falls off
//! beyond the head, and free mass points deliver little of the rod's momentum loss.
//!
//! SETUP: the penetration-strength bench's shots (seed 000's 1250 m/s WHA rod into an 80 mm
//! HzB-W target, the target's JC `A` 0.5 ... 4 GPa, the rest of the fixture unchanged) at 0.4
//! and 0.2 mm, to 30 us. From snapshots every 0.5 us, averaged over 10-30 us:
//! - `R_h`, the head: the widest node of the rod's body (its live elements connected to the
//!   tail, as the experiment measures the nose) within one rod radius `a` of its nose;
//! - `R_c`, the crater: the innermost live target node between one and three rod radii above
//!   the nose (the crater wall beside the head);
//! - the floor's axial stress by radius: for each band of `a / 2`, the live target element
//!   nearest the interface (highest centroid below the nose plus `a`) and its `sigma_zz`: a
//!   proxy of the floor's normal traction (not the contact force itself);
//! - over the whole run, the axial contact impulse on the rod's live nodes, split by what met
//!   them: live target surface nodes, or free mass points (eroded target debris) held by the
//!   kinematic stop (`ContactStatistics::impulses`).
//!
//! REFERENCE: Walker & Anderson (1995): the rate with the same strengths and their crater
//! radius `R_c = a (1 + 0.287 V + 0.148 V^2)`, V in km/s (1.59 a at 1250 m/s).
//!
//! Run: `cargo bench -p stoss --bench penetration_crater` (about 6 minutes on 2 cores). The
//! figures are in docs/solver.md ("Accuracy": "The crater, item 1 of the Eulerian issue").

mod semi_infinite;

use semi_infinite::shot;
use std::ops::ControlFlow;
use std::time::Instant;
use stoss::analytic::penetration::depth_at;
use stoss::experiment::penetration::ConnectedBody;
use stoss::measure::interpolate;
use stoss::solver::{Discretisation, SolverSettings};
use stoss_kernel::PartMaterial;

/// One snapshot's measurements: time, nose, `R_h`, `R_c`, the floor's stress per band.
type Sample = (f64, f64, f64, f64, [f64; 4]);

/// Radial bands of the floor's stress, in rod radii.
const BANDS: [(f64, f64); 4] = [(0.0, 0.5), (0.5, 1.0), (1.0, 1.5), (1.5, 2.0)];

fn main() {
    let shot = shot();
    let a = 0.5 * shot.spec.rod_diameter;
    println!(
        "| target A (GPa) | element | rate FE / WA | R_h / a | R_c / a (WA 1.59) | floor sigma_zz by r / a: 0-0.5, 0.5-1, 1-1.5, 1.5-2 (GPa) | rod's contact impulse from debris | wall (s) |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for element in [0.4e-3, 0.2e-3] {
        for yield_stress in [0.5, 1.0, 1.5, 2.0, 3.0, 4.0] {
            let started = Instant::now();
            let mut target_file = shot.target.clone();
            target_file
                .set_constant("strength.yield_stress", yield_stress * 1e9)
                .expect("a Johnson-Cook target");
            let target = target_file.material().expect("valid target");
            let rod = shot.rod.material().expect("valid rod");
            let mut spec = shot.spec.clone();
            spec.element_size = element;
            let settings = SolverSettings {
                threads: Some(2),
                output_interval: 0.5e-6,
                ..SolverSettings::default()
            };
            let check = spec.cross_check(&target).expect("cross-check");
            let Ok(built) = spec.model(
                &PartMaterial::from(target),
                &PartMaterial::from(rod),
                &settings,
            ) else {
                println!(
                    "| {yield_stress:.1} | {:.1} mm | failed to build |",
                    element * 1e3
                );
                continue;
            };
            let mesh = &built.model.mesh;
            let rod_part = mesh.element_part[built.rod_elements[0]];
            let is_rod: Vec<bool> = (0..mesh.elements.len())
                .map(|e| mesh.element_part[e] == rod_part)
                .collect();
            let (start, end) = (built.impact_time + 10.0e-6, built.impact_time + 30.0e-6);
            // The rod behind its nose, as the experiment measures it: fragments ahead of the
            // nose are not the nose.
            let mut body = ConnectedBody::new(mesh, &built.rod_elements);
            // Per snapshot: time, nose, R_h, R_c, floor stress per band.
            let mut history: Vec<Sample> = Vec::new();
            let outcome = built.model.run_observed(&mut |snapshot| {
                let x = snapshot.positions;
                let live = |e: usize| !snapshot.eroded[e];
                body.find(mesh, snapshot.eroded);
                let rod_nodes = built
                    .rod_elements
                    .iter()
                    .zip(&body.member)
                    .filter(|(_, &member)| member)
                    .flat_map(|(&e, _)| mesh.element_nodes(e).iter().copied());
                let nose = rod_nodes
                    .clone()
                    .map(|n| x[n][1])
                    .fold(f64::INFINITY, f64::min);
                let head = rod_nodes
                    .filter(|&n| x[n][1] < nose + a)
                    .map(|n| x[n][0])
                    .fold(0.0, f64::max);
                let crater = (0..mesh.elements.len())
                    .filter(|&e| !is_rod[e] && live(e))
                    .flat_map(|e| mesh.element_nodes(e).iter().copied())
                    .filter(|&n| x[n][1] > nose + a && x[n][1] < nose + 3.0 * a)
                    .map(|n| x[n][0])
                    .fold(f64::INFINITY, f64::min);
                let mut floor = [f64::NAN; 4];
                let mut highest = [f64::NEG_INFINITY; 4];
                for e in (0..mesh.elements.len()).filter(|&e| !is_rod[e] && live(e)) {
                    let nodes = mesh.element_nodes(e);
                    let centroid = nodes.iter().fold([0.0; 2], |c, &n| {
                        [c[0] + x[n][0] / 4.0, c[1] + x[n][1] / 4.0]
                    });
                    if centroid[1] > nose + a {
                        continue;
                    }
                    for (band, &(low, high)) in BANDS.iter().enumerate() {
                        let r = centroid[0] / a;
                        if r >= low && r < high && centroid[1] > highest[band] {
                            highest[band] = centroid[1];
                            floor[band] = snapshot.states[e].stress[1];
                        }
                    }
                }
                history.push((snapshot.time, nose, head, crater, floor));
                ControlFlow::Continue(())
            });
            let Ok(run) = outcome else {
                println!("| {yield_stress:.1} | {:.1} mm | failed |", element * 1e3);
                continue;
            };
            let window: Vec<_> = history
                .iter()
                .filter(|h| h.0 >= start && h.0 <= end)
                .collect();
            let mean = |f: &dyn Fn(&Sample) -> f64| {
                let values: Vec<f64> = window
                    .iter()
                    .map(|h| f(h))
                    .filter(|v| v.is_finite())
                    .collect();
                values.iter().sum::<f64>() / values.len().max(1) as f64
            };
            let nose: Vec<(f64, f64)> = history.iter().map(|h| (h.0, -h.1)).collect();
            let fe_rate = (interpolate(&nose, end) - interpolate(&nose, start)) / (end - start);
            let wa = |t: f64| depth_at(&check.walker_anderson, t - built.impact_time);
            let wa_rate = (wa(end) - wa(start)) / (end - start);
            let floor: Vec<String> = (0..4)
                .map(|band| format!("{:.2}", mean(&|h| h.4[band]) / 1e9))
                .collect();
            let impulse = run
                .contact
                .impulses
                .iter()
                .find(|i| i.part == rod_part)
                .copied()
                .unwrap_or_default();
            let total = impulse.surfaces[1] + impulse.debris[1];
            println!(
                "| {yield_stress:.1} | {:.1} mm | {:.2} | {:.2} | {:.2} | {} | {:.1} % | {:.0} |",
                element * 1e3,
                fe_rate / wa_rate,
                mean(&|h| h.2) / a,
                mean(&|h| h.3) / a,
                floor.join(", "),
                100.0 * impulse.debris[1] / total,
                started.elapsed().as_secs_f64()
            );
        }
    }
}

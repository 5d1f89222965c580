//! Runs a path of implicit Johnson-Cook 4340 plastic updates (uniaxial strain, 1e-5 per
//! 1e-8 s, the benchmark's `path` case) for profiling under callgrind:
//! `valgrind --tool=callgrind target/release/examples/update_profile [updates]`.

use stoss_kernel::math::exp;
use stoss_kernel::strength::JohnsonCook;
use stoss_kernel::{update, Material, MaterialState, StepInput};

fn main() {
    let updates: u32 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(20_000);
    let material = Material::STEEL_4340.with_strength(JohnsonCook::STEEL_4340);
    let mut state = MaterialState::initial(298.0);
    let skip: u32 = std::env::args()
        .nth(2)
        .and_then(|a| a.parse().ok())
        .unwrap_or(0);
    let mut iterations = 0u64;
    let mut plastic = 0u32;
    for step in 0..updates + skip {
        let axial = -1.0e-5;
        let input = StepInput {
            strain_increment: [axial, 0.0, 0.0, 0.0, 0.0, 0.0],
            dt: 1.0e-8,
            relative_volume: state.relative_volume * exp(axial),
        };
        let output = update(&material, &mut state, std::hint::black_box(&input)).expect("update");
        if step < skip {
            continue;
        }
        iterations += u64::from(output.iterations);
        plastic += u32::from(output.plastic_increment > 0.0);
    }
    println!(
        "{updates} updates, {plastic} plastic, {:.3} iterations per plastic update, eps_p {:.4}",
        iterations as f64 / f64::from(plastic.max(1)),
        state.plastic_strain
    );
}

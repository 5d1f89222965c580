//! Runs implicit Johnson-Cook 4340 updates in uniaxial strain (1e-5 per 1e-8 s, the
//! benchmark's `path` case; with `points > 1`, the `block` case: point `i` at
//! `1 + 0.5 i / points` times that rate, all points advanced together) for profiling under
//! callgrind or perf:
//! `valgrind --tool=callgrind target/release/examples/update_profile [steps] [skipped] [points]`.
//! The first `skipped` steps are run but not counted. Prints the mean return iterations and a
//! hash of the final states' bits (equal hashes: bit-identical paths).

use stoss_kernel::math::exp;
use stoss_kernel::strength::JohnsonCook;
use stoss_kernel::{update, Material, MaterialState, StepInput};

fn argument(position: usize, default: u32) -> u32 {
    std::env::args()
        .nth(position)
        .and_then(|a| a.parse().ok())
        .unwrap_or(default)
}

fn main() {
    let steps = argument(1, 20_000);
    let skip = argument(2, 0);
    let points = argument(3, 1).max(1) as usize;
    let material = Material::STEEL_4340.with_strength(JohnsonCook::STEEL_4340);
    let mut states = vec![MaterialState::initial(298.0); points];
    let mut iterations = 0u64;
    let mut plastic = 0u64;
    for step in 0..steps + skip {
        for (point, state) in states.iter_mut().enumerate() {
            let axial = -1.0e-5 * (1.0 + 0.5 * point as f64 / points as f64);
            let input = StepInput {
                strain_increment: [axial, 0.0, 0.0, 0.0, 0.0, 0.0],
                dt: 1.0e-8,
                relative_volume: state.relative_volume * exp(axial),
            };
            let output = update(&material, state, std::hint::black_box(&input)).expect("update");
            if step >= skip {
                iterations += u64::from(output.iterations);
                plastic += u64::from(output.plastic_increment > 0.0);
            }
        }
    }
    // FNV-1a over the final states' bits: a change in any update's last bit carries into the
    // state of the steps after it, so equal hashes mean bit-identical paths.
    let hash = states
        .iter()
        .flat_map(|state| state.values())
        .fold(0xcbf2_9ce4_8422_2325_u64, |hash, value| {
            (hash ^ value.to_bits()).wrapping_mul(0x0100_0000_01b3)
        });
    println!(
        "{} updates, {plastic} plastic, {:.3} iterations per plastic update, eps_p {:.4}, \
         state hash {hash:016x}",
        u64::from(steps) * points as u64,
        iterations as f64 / plastic.max(1) as f64,
        states[0].plastic_strain
    );
}

//! The `update_lanes` target: a group of `LANES` points through the kernel's group update
//! (`stoss_kernel::update_lanes`, the C ABI batch's and the VUMAT's path) against each point
//! alone through `update`.
//!
//! Input: the first byte chooses the strength family (JC, MJC, TJC, ZA; the first three go
//! through the group's stages, ZA one point at a time); the rest is cut into `LANES` equal
//! parts, each decoded as a `strength_update_<model>` case ([`crate::strength::decode`]). The
//! first part's material is every lane's; each part gives its lane's state and steps (a lane
//! with fewer steps repeats them), so lanes start, yield, fail and refuse steps at different
//! times.
//!
//! Properties: no panic; every lane's result (output or error) and state are, bit for bit,
//! those of `update` on that lane alone, step after step.

use crate::strength::{decode, Family};
use stoss_kernel::{update, update_lanes, MaterialState, StepInput, UpdateError, LANES};

/// One fuzz case.
pub fn run(data: &[u8]) {
    let Some((&choice, rest)) = data.split_first() else {
        return;
    };
    let family = [
        Family::JohnsonCook,
        Family::ModifiedJohnsonCook,
        Family::TwoRateJohnsonCook,
        Family::ZerilliArmstrong,
    ][usize::from(choice % 4)];
    let part = rest.len() / LANES;
    let cases: Vec<_> = (0..LANES)
        .map(|lane| decode(family, &rest[lane * part..(lane + 1) * part]))
        .collect();
    let material = cases[0].material;
    let mut grouped: [MaterialState; LANES] = core::array::from_fn(|lane| cases[lane].initial);
    let mut alone = grouped;
    let steps = cases.iter().map(|c| c.steps.len()).max().unwrap_or(0);
    for step in 0..steps {
        let inputs: [StepInput; LANES] = core::array::from_fn(|lane| {
            let own = &cases[lane].steps;
            if own.is_empty() {
                StepInput {
                    strain_increment: [0.0; 6],
                    dt: 1e-6,
                    relative_volume: alone[lane].relative_volume,
                }
            } else {
                own[step % own.len()].input
            }
        });
        let mut results = [Err(UpdateError::NonFiniteInput); LANES];
        update_lanes(&material, &mut grouped, &inputs, &mut results);
        for lane in 0..LANES {
            let expected = update(&material, &mut alone[lane], &inputs[lane]);
            let same_result = match (&results[lane], &expected) {
                (Ok(a), Ok(b)) => {
                    a.wave_speed.to_bits() == b.wave_speed.to_bits()
                        && a.plastic_increment.to_bits() == b.plastic_increment.to_bits()
                        && a.yield_stress.to_bits() == b.yield_stress.to_bits()
                        && a.iterations == b.iterations
                }
                (Err(a), Err(b)) => a == b,
                _ => false,
            };
            let same_state = grouped[lane].values().map(f64::to_bits)
                == alone[lane].values().map(f64::to_bits)
                && grouped[lane].flags == alone[lane].flags
                && grouped[lane].yield_check.flow_stress.to_bits()
                    == alone[lane].yield_check.flow_stress.to_bits()
                && grouped[lane].yield_check.plastic_strain.to_bits()
                    == alone[lane].yield_check.plastic_strain.to_bits()
                && grouped[lane].yield_check.temperature.to_bits()
                    == alone[lane].yield_check.temperature.to_bits();
            assert!(
                same_result && same_state,
                "lane {lane}, step {step}: {:?} / {:?} against {:?} / {:?}\nmaterial {material:?}\ninput {:?}",
                results[lane],
                grouped[lane],
                expected,
                alone[lane],
                inputs[lane]
            );
        }
    }
}

//! Mechanical Threshold Stress: fuzzed constants, state and steps through
//! `stoss_kernel::update` (properties: `stoss_fuzz::check::run_steps`).
#![no_main]

use stoss_fuzz::strength::{run, Family};

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    run(Family::MechanicalThresholdStress, data);
});

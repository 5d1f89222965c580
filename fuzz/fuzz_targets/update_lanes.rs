//! The group update against the one-point update: `LANES` fuzzed points of one fuzzed material
//! through `stoss_kernel::update_lanes`, each bit for bit as alone through `update`
//! (properties: `stoss_fuzz::lanes`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    stoss_fuzz::lanes::run(data);
});

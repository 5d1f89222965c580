//! K&C concrete: fuzzed constants, EoS, state and steps through `stoss_kernel::kc::update`
//! (properties: `stoss_fuzz::kc`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    stoss_fuzz::kc::run(data);
});

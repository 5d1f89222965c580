//! RHT concrete: fuzzed constants, EoS, state and steps through `stoss_kernel::rht::update`
//! (properties: `stoss_fuzz::rht`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    stoss_fuzz::rht::run(data);
});

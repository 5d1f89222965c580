//! Every equation of state with fuzzed constants: `validate`, `evaluate` over fuzzed
//! compressions and histories, then hydrostatic steps through `update`
//! (properties: `stoss_fuzz::eos`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    stoss_fuzz::eos::run(data);
});

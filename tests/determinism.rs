//! Host determinism: results depend only on the inputs and the recorded seeds, on every
//! platform. The host's float functions that feed a result are `libm`'s (or the kernel's),
//! never the platform's, so a synthetic recording hashes the same on x86_64 and on aarch64
//! (`.ci/cross.sh` runs this test under qemu). A change of these hashes is a change of
//! results: re-pin them only with the reason in the commit.

use std::path::PathBuf;
use stoss::cli::synthesize::{recordings, SynthesizeArgs};
use stoss::hash::fnv1a;

fn fixtures() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures")
}

/// FNV-1a of the data rows (after the `quantity,...` header line: the comment header holds
/// the absolute paths of this checkout).
fn rows_hash(text: &str) -> u64 {
    let data = text
        .split_once("quantity,position,value,uncertainty\n")
        .unwrap()
        .1;
    fnv1a(data)
}

#[test]
fn synthetic_recordings_hash_the_same_on_every_platform() {
    // GOAL: `stoss synthesize` (mesh grading, explicit solver, kernel, seeded normal noise)
    //       gives the same bits on every target.
    // SETUP: the bundled 4340 Taylor test at 208 m/s (graded axisymmetric mesh, eroding-free
    //        impact, 1 % noise, seed 7) and a quasi-static tension flow curve.
    // REFERENCE: hashes pinned on x86_64; `.ci/cross.sh` checks them on aarch64 under qemu.
    let cases = [
        (
            "taylor-4340-208",
            0x184b25c3b542fbdd_u64,
            0x2eeb9e06c7a4295d_u64,
        ),
        (
            "flow-4340-jc-tension-570s-298K",
            0x26804f015987a710_u64,
            0xeffbb8a2c4b8be9f_u64,
        ),
    ];
    let mut found = Vec::new();
    for (name, _, _) in cases {
        let args = SynthesizeArgs {
            experiment: fixtures().join(format!("experiments/{name}.toml")),
            material: fixtures().join("materials/4340-jc.toml"),
            noise: 0.01,
            seed: 7,
            output: PathBuf::from("unused.csv"),
        };
        let (noisy, clean) = recordings(&args).unwrap();
        found.push((name, rows_hash(&noisy), rows_hash(&clean)));
    }
    for ((name, noisy, clean), (_, want_noisy, want_clean)) in found.iter().zip(&cases) {
        assert_eq!(
            (*noisy, *clean),
            (*want_noisy, *want_clean),
            "{name}: found {noisy:#018x}, {clean:#018x}"
        );
    }
}

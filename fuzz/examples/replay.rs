//! Replay fuzz inputs without libFuzzer and print what they exercised.
//!
//! Usage (from fuzz/): `cargo run --release --example replay -- <target> <file or dir>...`,
//! e.g. `cargo run --release --example replay -- strength_update_jc corpus/strength_update_jc`.
//! A failing property panics with the material, state and step, as under the fuzzer.

use std::path::{Path, PathBuf};
use stoss_fuzz::check::Tally;
use stoss_fuzz::strength::Family;

fn files(path: &Path, out: &mut Vec<PathBuf>) {
    if path.is_dir() {
        let mut entries: Vec<PathBuf> = std::fs::read_dir(path)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
            .map(|entry| entry.unwrap().path())
            .collect();
        entries.sort();
        for entry in entries {
            files(&entry, out);
        }
    } else {
        out.push(path.to_path_buf());
    }
}

fn main() {
    let mut args = std::env::args().skip(1);
    let target = args
        .next()
        .expect("usage: replay <target> <file or dir>...");
    let run: fn(&[u8]) -> Tally = match target.as_str() {
        "strength_update_jc" => |d| stoss_fuzz::strength::run(Family::JohnsonCook, d),
        "strength_update_za" => |d| stoss_fuzz::strength::run(Family::ZerilliArmstrong, d),
        "strength_update_mjc" => |d| stoss_fuzz::strength::run(Family::ModifiedJohnsonCook, d),
        "strength_update_tjc" => |d| stoss_fuzz::strength::run(Family::TwoRateJohnsonCook, d),
        "strength_update_ptw" => |d| stoss_fuzz::strength::run(Family::PrestonTonksWallace, d),
        "strength_update_khl" => |d| stoss_fuzz::strength::run(Family::KhanHuangLiang, d),
        "strength_update_vk" => |d| stoss_fuzz::strength::run(Family::VoceKocks, d),
        "strength_update_mts" => {
            |d| stoss_fuzz::strength::run(Family::MechanicalThresholdStress, d)
        }
        "eos" => stoss_fuzz::eos::run,
        "rht_update" => stoss_fuzz::rht::run,
        "kc_update" => stoss_fuzz::kc::run,
        other => panic!("unknown target {other}"),
    };
    let mut inputs = Vec::new();
    for arg in args {
        files(Path::new(&arg), &mut inputs);
    }
    let mut total = Tally::default();
    for path in &inputs {
        let data = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        eprintln!("{}", path.display());
        total.add(&run(&data));
    }
    println!(
        "{target}: {} inputs, {} steps, {} checked in domain ({} plastic), in-domain errors: \
         {} non-finite result, {} return mapping diverged, {} other",
        inputs.len(),
        total.steps,
        total.checked,
        total.plastic,
        total.errors[0],
        total.errors[1],
        total.errors[2]
    );
}

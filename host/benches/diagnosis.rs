//! Identification rate of `stoss diagnose` on the concealed-effect cases of
//! fixtures/diagnosis/ over noise seeds and levels (`stoss::validate::identification`): for
//! each case, the truth's noise-free predictions are perturbed by Gaussian noise of 1, 3 and
//! 5 % (seed = 1000 case + 100 level + seed), the Johnson-Cook model is calibrated (short
//! Bayesian run plus polish, as in tests/diagnose.rs) and diagnosed; prints identified, same
//! physics and false alarms per case and level, and the simulations each diagnosis costs.
//! Every diagnosis's accepted term is printed to stderr. The 1 % rows are also `stoss
//! validate` rows (`identify-*`).
//!
//! Run: `cargo bench -p stoss --bench diagnosis` (environment: `SEEDS` (default 10), `CASES`
//! (comma-separated, default all), `NOISE` (comma-separated, default 0.01,0.03,0.05; a level's
//! position in this list enters its seeds)).

use std::path::Path;
use stoss::validate::identification::{identification, CASES, NOISE_LEVELS, SEEDS};

fn env_list(name: &str, default: &str) -> Vec<String> {
    std::env::var(name)
        .unwrap_or_else(|_| default.into())
        .split(',')
        .map(str::to_string)
        .collect()
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/diagnosis");
    let seeds: u64 = std::env::var("SEEDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(SEEDS);
    let all: Vec<&str> = CASES.iter().map(|(name, _)| *name).collect();
    let cases = env_list("CASES", &all.join(","));
    let default_noise: Vec<String> = NOISE_LEVELS.iter().map(|n| n.to_string()).collect();
    let noises: Vec<f64> = env_list("NOISE", &default_noise.join(","))
        .iter()
        .map(|n| n.parse().expect("NOISE"))
        .collect();
    println!("case          noise  identified  same physics  false alarms  points/diagnosis  simulations/diagnosis  points/calibration  (seeds 1..={seeds}, noise seed = 1000 case + 100 level + seed)");
    for (case, expected) in CASES {
        if !cases.iter().any(|c| c == case) {
            continue;
        }
        for (level, &noise) in noises.iter().enumerate() {
            let mut print = |v: &stoss::validate::identification::Verdict| {
                eprintln!(
                    "{case} noise {noise} seed {}: accepted {} (top test {}; refits: {})",
                    v.noise_seed,
                    v.accepted.as_deref().unwrap_or("none"),
                    v.top_test,
                    v.refits.join("; ")
                )
            };
            let tally =
                identification(&root, case, noise, level, seeds, &mut print).expect("diagnosis");
            let count = |n: u64| {
                if expected.is_some() {
                    n.to_string()
                } else {
                    "-".into()
                }
            };
            println!(
                "{case:<12} {:>5.0} %  {:>5}/{seeds:<4}  {:>6}/{seeds:<5}  {:>6}/{seeds:<5}  {:>16.0}  {:>21.0}  {:>18}",
                100.0 * noise,
                count(tally.identified),
                count(tally.same_physics),
                tally.false_alarms,
                tally.points as f64 / seeds as f64,
                tally.simulations as f64 / seeds as f64,
                tally.calibration_points / seeds as usize,
            );
        }
    }
}

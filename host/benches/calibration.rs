//! Simulations to reach a target error on the synthetic flow-curve campaign
//! (fixtures/campaigns/synthetic-flow.toml: JC, 5 constants, known truth), for the Bayesian
//! optimiser, random Latin hypercube sampling, CMA-ES and ten Bayesian simulations followed by
//! the least-squares finish (`least_squares`), over 10 seeds; median and quartiles. The target is 1.5 x the error of the truth itself (0.235, the noise floor), or
//! `TARGET_FACTOR` x it (issue 15 asks for 1.1).
//! Run: `cargo bench -p stoss --bench calibration` (`TARGET_FACTOR=1.1 BASELINE_BUDGET=3000
//! cargo bench ...`: the baselines to convergence). The
//! optimisers see ln(error), as in `stoss calibrate`.

use std::path::Path;
use stoss::validate::finish::{baseline_to_target, Baseline, NOISE_FLOOR};

const BUDGET: usize = 100;
const SEEDS: u64 = 10;

fn quartiles(mut runs: Vec<usize>, failures: usize, budget: usize) -> String {
    // Runs that missed the target count as "more than the budget".
    runs.extend(std::iter::repeat_n(usize::MAX, failures));
    runs.sort_unstable();
    let show = |k: usize| {
        if runs[k] == usize::MAX {
            format!(">{budget}")
        } else {
            runs[k].to_string()
        }
    };
    let n = runs.len();
    format!(
        "{:>6} {:>6} {:>6}   reached {}/{}",
        show(n / 4),
        show(n / 2),
        show((3 * n) / 4),
        n - failures,
        n
    )
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let factor: f64 = std::env::var("TARGET_FACTOR")
        .ok()
        .and_then(|v| v.parse().ok())
        .filter(|f: &f64| *f > 1.0)
        .unwrap_or(1.5);
    let target = factor * NOISE_FLOOR;
    println!("synthetic flow campaign, 5 constants, target error {target:.3}, budget {BUDGET}, {SEEDS} seeds");
    println!(
        "{:<22} {:>6} {:>6} {:>6}   (simulations to target: 25 %, median, 75 %)",
        "optimiser", "q25", "median", "q75"
    );
    // The baselines may run longer, to convergence rather than censored at the Bayesian
    // budget (`BASELINE_BUDGET`, default the same 100).
    let baseline_budget: usize = std::env::var("BASELINE_BUDGET")
        .ok()
        .and_then(|v| v.parse().ok())
        .filter(|b: &usize| *b >= BUDGET)
        .unwrap_or(BUDGET);
    let fixtures = root.join("fixtures");
    for baseline in [
        Baseline::Bayesian,
        Baseline::RandomLatinHypercube,
        Baseline::CmaEs,
    ] {
        let budget = if baseline == Baseline::Bayesian {
            BUDGET
        } else {
            baseline_budget
        };
        let runs =
            baseline_to_target(&fixtures, baseline, factor, budget, SEEDS).expect("baseline runs");
        let reached: Vec<usize> = runs.iter().flatten().copied().collect();
        let missed = runs.len() - reached.len();
        println!(
            "{:<22} {}",
            baseline.name(),
            quartiles(reached, missed, budget)
        );
    }

    let runs = stoss::validate::finish::simulations_to_target(&fixtures, factor, SEEDS)
        .expect("least-squares finish");
    let reached: Vec<usize> = runs.iter().flatten().copied().collect();
    let missed = runs.len() - reached.len();
    println!(
        "{:<22} {}",
        format!("bayesian {} + LM", stoss::validate::finish::START),
        quartiles(reached, missed, BUDGET)
    );
}

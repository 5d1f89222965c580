//! Simulations to reach a target error on the synthetic flow-curve campaign
//! (fixtures/campaigns/synthetic-flow.toml: JC, 5 constants, known truth), for the Bayesian
//! optimiser, random Latin hypercube sampling, CMA-ES and ten Bayesian simulations followed by
//! the least-squares finish (`least_squares`), over 10 seeds; median and quartiles. The target is 1.5 x the error of the truth itself (0.235, the noise floor), or
//! `TARGET_FACTOR` x it (issue 15 asks for 1.1).
//! Run: `cargo bench -p stoss --bench calibration` (`TARGET_FACTOR=1.1 BASELINE_BUDGET=3000
//! cargo bench ...`: the baselines to convergence). The
//! optimisers see ln(error), as in `stoss calibrate`.

use std::path::Path;
use stoss::optimise::{AskTell, BayesianOptimiser, Bounds, CmaEs, OptimiserSettings, RandomSearch};
use stoss::validate::finish::{SyntheticFlow, NOISE_FLOOR};

const BUDGET: usize = 100;
const SEEDS: u64 = 10;

fn run(
    optimiser: &mut dyn AskTell,
    objective: &dyn Fn(&[f64]) -> Option<f64>,
    target: f64,
    budget: usize,
) -> Option<usize> {
    let mut used = 0;
    while used < budget {
        let points = optimiser.ask();
        if points.is_empty() {
            return None;
        }
        let values: Vec<Option<f64>> = points.iter().map(|p| objective(p)).collect();
        for v in &values {
            used += 1;
            if v.is_some_and(|v| v <= target) {
                return Some(used);
            }
        }
        let logs: Vec<Option<f64>> = values
            .iter()
            .map(|v| v.map(|e| e.max(1e-300).ln()))
            .collect();
        if optimiser.tell(&points, &logs).is_err() {
            return None;
        }
    }
    None
}

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
    let flow = SyntheticFlow::load(&root.join("fixtures")).expect("campaign");
    let space = &flow.space;
    let objective = |x: &[f64]| flow.error(x);
    let factor: f64 = std::env::var("TARGET_FACTOR")
        .ok()
        .and_then(|v| v.parse().ok())
        .filter(|f: &f64| *f > 1.0)
        .unwrap_or(1.5);
    let target = factor * NOISE_FLOOR;
    let pairs = space.bound_pairs();
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
    for name in ["bayesian (GP + log-EI)", "random Latin hypercube", "CMA-ES"] {
        let budget = if name.starts_with("bayesian") {
            BUDGET
        } else {
            baseline_budget
        };
        let mut reached = Vec::new();
        let mut missed = 0;
        for seed in 0..SEEDS {
            let bounds = Bounds::from_pairs(&pairs).expect("bounds");
            let opt_settings =
                OptimiserSettings::new(space.dimension(), budget, seed).with_batch(2);
            let mut optimiser: Box<dyn AskTell> = match name {
                "bayesian (GP + log-EI)" => {
                    Box::new(BayesianOptimiser::new(bounds, opt_settings).expect("bo"))
                }
                "random Latin hypercube" => {
                    Box::new(RandomSearch::new(bounds, &opt_settings).expect("lhs"))
                }
                _ => Box::new(CmaEs::new(bounds, &opt_settings).expect("cma")),
            };
            match run(optimiser.as_mut(), &objective, target, budget) {
                Some(n) => reached.push(n),
                None => missed += 1,
            }
        }
        println!("{name:<22} {}", quartiles(reached, missed, budget));
    }

    // Ten Bayesian simulations, then the least-squares finish
    // (`stoss::validate::finish`, also the `finish-*` rows of `stoss validate`).
    let fixtures = root.join("fixtures");
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

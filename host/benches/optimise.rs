//! Evaluations-to-target of the Bayesian optimiser against random Latin hypercube sampling and
//! CMA-ES on Branin (2-D) and Hartmann-6 (6-D), over 10 seeds: median and quartiles. Not a
//! timed benchmark: the figure of merit is the number of objective evaluations (simulations)
//! needed, which is what a calibration pays for. Prints a Markdown table (docs/calibration.md).
//!
//! Run: `cargo bench -p stoss --bench optimise` (about 10 minutes on 2 cores), or
//! `cargo bench -p stoss --bench optimise -- --seeds 3 --only branin` for a quick look.

use std::time::Instant;
use stoss::optimise::functions::{
    branin, branin_bounds, hartmann6, hartmann6_bounds, BRANIN_MIN, HARTMANN6_MIN,
};
use stoss::optimise::{
    evaluations_to_target, AskTell, BayesianOptimiser, Bounds, CmaEs, OptimiserSettings,
    RandomSearch,
};

/// Proposals per iteration: the two cores of the reference machine.
const BATCH: usize = 2;

struct Problem {
    name: &'static str,
    f: fn(&[f64]) -> f64,
    bounds: Bounds,
    /// (label, target value).
    targets: Vec<(String, f64)>,
    /// Budget of the GP-BO and CMA-ES runs; random sampling gets `RANDOM_FACTOR` times more.
    budget: usize,
}

/// Random sampling is cheap to run: give it a longer budget so that its median is measured
/// rather than censored.
const RANDOM_FACTOR: usize = 10;

/// Runs `optimiser` until every target is reached or the budget is spent; returns the
/// evaluations-to-target of each target (`None`: not reached).
fn race(optimiser: &mut dyn AskTell, f: fn(&[f64]) -> f64, targets: &[f64]) -> Vec<Option<usize>> {
    let hardest = targets.iter().copied().fold(f64::INFINITY, f64::min);
    loop {
        let points = optimiser.ask();
        if points.is_empty() {
            break;
        }
        let values: Vec<Option<f64>> = points.iter().map(|x| Some(f(x))).collect();
        if optimiser.tell(&points, &values).is_err() {
            break;
        }
        if optimiser.best().is_some_and(|b| b.1 <= hardest) {
            break;
        }
    }
    targets
        .iter()
        .map(|&t| evaluations_to_target(optimiser.evaluations(), t))
        .collect()
}

/// Nearest-rank quantile of evaluations-to-target, unreached runs counting as infinite.
fn quantile(sorted: &[Option<usize>], q: f64) -> Option<f64> {
    let n = sorted.len();
    if n == 0 {
        return None;
    }
    if (q - 0.5).abs() < 1e-12 && n.is_multiple_of(2) {
        let a = sorted[n / 2 - 1]?;
        let b = sorted[n / 2]?;
        return Some((a + b) as f64 / 2.0);
    }
    let rank = ((q * n as f64).ceil() as usize).clamp(1, n);
    sorted[rank - 1].map(|v| v as f64)
}

fn budget_of(method: &str, budget: usize) -> usize {
    if method == "random LHS" {
        budget * RANDOM_FACTOR
    } else {
        budget
    }
}

fn show(q: Option<f64>, budget: usize) -> String {
    match q {
        Some(v) => format!("{v}"),
        None => format!(">{budget}"),
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let seeds = args
        .iter()
        .position(|a| a == "--seeds")
        .and_then(|i| args.get(i + 1))
        .and_then(|s| s.parse::<u64>().ok())
        .unwrap_or(10);
    let only = args
        .iter()
        .position(|a| a == "--only")
        .and_then(|i| args.get(i + 1))
        .cloned();
    let problems = vec![
        Problem {
            name: "Branin (2-D)",
            f: branin,
            bounds: branin_bounds(),
            targets: vec![
                (
                    format!("f* + 0.1 = {:.4}", BRANIN_MIN + 0.1),
                    BRANIN_MIN + 0.1,
                ),
                (
                    format!("f* + 1e-2 = {:.4}", BRANIN_MIN + 1e-2),
                    BRANIN_MIN + 1e-2,
                ),
            ],
            budget: 300,
        },
        Problem {
            name: "Hartmann-6 (6-D)",
            f: hartmann6,
            bounds: hartmann6_bounds(),
            targets: vec![
                ("f <= -2.5 (within 25%)".to_string(), -2.5),
                ("f <= -3.0 (within 10%)".to_string(), -3.0),
                (
                    format!("f* + 1e-2 = {:.4}", HARTMANN6_MIN + 1e-2),
                    HARTMANN6_MIN + 1e-2,
                ),
            ],
            budget: 300,
        },
    ];
    println!("| function | target | method | reached | median | Q1 | Q3 | wall s/run |");
    println!("|---|---|---|---|---|---|---|---|");
    for problem in &problems {
        if only
            .as_ref()
            .is_some_and(|o| !problem.name.to_lowercase().contains(o))
        {
            continue;
        }
        let dim = problem.bounds.dim();
        let targets: Vec<f64> = problem.targets.iter().map(|t| t.1).collect();
        for method in ["GP-BO (log-EI)", "random LHS", "CMA-ES"] {
            let mut hits: Vec<Vec<Option<usize>>> = vec![Vec::new(); targets.len()];
            let started = Instant::now();
            for seed in 0..seeds {
                let budget = budget_of(method, problem.budget);
                let settings = OptimiserSettings::new(dim, budget, seed).with_batch(BATCH);
                let bounds = problem.bounds.clone();
                let mut optimiser: Box<dyn AskTell> = match method {
                    "GP-BO (log-EI)" => Box::new(BayesianOptimiser::new(bounds, settings)?),
                    "random LHS" => Box::new(RandomSearch::new(bounds, &settings)?),
                    _ => Box::new(CmaEs::new(bounds, &settings)?),
                };
                for (k, hit) in race(optimiser.as_mut(), problem.f, &targets)
                    .into_iter()
                    .enumerate()
                {
                    hits[k].push(hit);
                }
            }
            let wall = started.elapsed().as_secs_f64() / seeds.max(1) as f64;
            for (k, (label, _)) in problem.targets.iter().enumerate() {
                let mut sorted = hits[k].clone();
                sorted.sort_by_key(|h| h.unwrap_or(usize::MAX));
                let reached = sorted.iter().filter(|h| h.is_some()).count();
                let per_seed: Vec<String> = hits[k]
                    .iter()
                    .map(|h| h.map_or("-".to_string(), |v| v.to_string()))
                    .collect();
                println!(
                    "| {} | {label} | {method} | {reached}/{seeds} | {} | {} | {} | {wall:.1} |",
                    problem.name,
                    show(quantile(&sorted, 0.5), budget_of(method, problem.budget)),
                    show(quantile(&sorted, 0.25), budget_of(method, problem.budget)),
                    show(quantile(&sorted, 0.75), budget_of(method, problem.budget)),
                );
                eprintln!(
                    "  {} / {label} / {method}: {}",
                    problem.name,
                    per_seed.join(" ")
                );
            }
        }
    }
    Ok(())
}

//! Simulations to a target error on the synthetic flow-curve campaign
//! (`fixtures/campaigns/synthetic-flow.toml`: JC, five constants, known truth) with ten
//! Bayesian simulations followed by the least-squares finish (`least_squares`): the figure
//! docs/calibration.md quotes as "Bayesian 10 + least squares", and the optimisers it is
//! compared with run alone ([`baseline_to_target`]). Used by the `finish-*` and `optimiser-*`
//! rows of `stoss validate` and by `cargo bench -p stoss --bench calibration`.
//!
//! The Bayesian optimiser's first [`START`] simulations, then the bounded Levenberg-Marquardt
//! on the whitened residuals from its best point (forward-difference Jacobians, two trial
//! dampings per iteration): the simulations to the target are the start plus the points the
//! finish evaluates up to the first iteration count whose result reaches it, and the scoring of
//! that result (the final Jacobian a diagnosis needs is not counted).

use crate::fit::{evaluate, levenberg_marquardt, score, Campaign, Engine, Hypothesis, ModelSpace};
use crate::optimise::{AskTell, BayesianOptimiser, Bounds, CmaEs, OptimiserSettings, RandomSearch};
use crate::solver::SolverSettings;
use std::path::Path;

/// The truth's own error on the fitted curves of the synthetic flow campaign: the noise floor.
pub const NOISE_FLOOR: f64 = 0.2352;

/// Bayesian simulations before the finish.
pub const START: usize = 10;

/// Most simulations a run may use.
pub const BUDGET: usize = 100;

/// Seeds (0 to `SEEDS - 1`) the documents quote.
pub const SEEDS: u64 = 10;

/// The synthetic flow campaign, its first model's search space and the fitted experiments:
/// what the optimisers are run on.
pub struct SyntheticFlow {
    /// The campaign (`fixtures/campaigns/synthetic-flow.toml`).
    pub campaign: Campaign,
    /// Its first model's search space.
    pub space: ModelSpace,
    /// The fitted experiments.
    pub fitted: Vec<usize>,
    settings: SolverSettings,
}

impl SyntheticFlow {
    /// The campaign under `fixtures`, its simulations on one thread each.
    pub fn load(fixtures: &Path) -> Result<Self, String> {
        let path = fixtures.join("campaigns/synthetic-flow.toml");
        let campaign = Campaign::load(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        let model = campaign
            .file
            .models
            .first()
            .ok_or("the synthetic flow campaign has no model")?;
        let space = campaign.space(model);
        let fitted = campaign.fitted();
        Ok(Self {
            campaign,
            space,
            fitted,
            settings: SolverSettings {
                threads: Some(1),
                ..SolverSettings::default()
            },
        })
    }

    /// The weighted error of the fitted experiments at the unit-space point `x` (none: the
    /// candidate is infeasible or a simulation failed).
    pub fn error(&self, x: &[f64]) -> Option<f64> {
        evaluate(&self.campaign, &self.space, x, &self.fitted, &self.settings)
            .total(&self.campaign, &self.fitted)
    }
}

/// For each seed, the simulations until the error is at most `factor` times
/// [`NOISE_FLOOR`] (none: not within [`BUDGET`]).
pub fn simulations_to_target(
    fixtures: &Path,
    factor: f64,
    seeds: u64,
) -> Result<Vec<Option<usize>>, String> {
    let flow = SyntheticFlow::load(fixtures)?;
    let SyntheticFlow {
        campaign,
        space,
        fitted,
        settings,
    } = &flow;
    let objective = |x: &[f64]| flow.error(x);
    let target = factor * NOISE_FLOOR;
    let pairs = space.bound_pairs();
    let mut runs = Vec::new();
    for seed in 0..seeds {
        let bounds = Bounds::from_pairs(&pairs).map_err(|e| e.to_string())?;
        let opt_settings = OptimiserSettings::new(space.dimension(), START, seed).with_batch(2);
        let mut optimiser =
            BayesianOptimiser::new(bounds, opt_settings).map_err(|e| e.to_string())?;
        let mut best: Option<(Vec<f64>, f64)> = None;
        let mut used = 0;
        let mut early = None;
        while used < START {
            let points = optimiser.ask();
            if points.is_empty() {
                break;
            }
            let values: Vec<Option<f64>> = points.iter().map(|p| objective(p)).collect();
            for (point, value) in points.iter().zip(&values) {
                used += 1;
                if let Some(v) = value {
                    if early.is_none() && *v <= target {
                        early = Some(used);
                    }
                    if best.as_ref().is_none_or(|(_, b)| v < b) {
                        best = Some((point.clone(), *v));
                    }
                }
            }
            let logs: Vec<Option<f64>> = values
                .iter()
                .map(|v| v.map(|e| e.max(1e-300).ln()))
                .collect();
            optimiser.tell(&points, &logs).map_err(|e| e.to_string())?;
        }
        if early.is_some() {
            runs.push(early);
            continue;
        }
        let Some((start, _)) = best else {
            runs.push(None);
            continue;
        };
        let hypothesis =
            Hypothesis::base(&campaign.base, space, &start).map_err(|e| e.to_string())?;
        let start_values = hypothesis.values().map_err(|e| e.to_string())?;
        let mut found = None;
        for iterations in 1..=6 {
            let mut quiet = |_: crate::fit::Progress<'_>| {};
            let mut pool = crate::fit::executor::Local::new(2).map_err(|e| e.to_string())?;
            let mut engine =
                Engine::new(campaign, &mut pool, None, &mut quiet).map_err(|e| e.to_string())?;
            let Ok(fit) =
                levenberg_marquardt(&mut engine, &hypothesis, &start_values, fitted, iterations)
            else {
                break;
            };
            let counted = START + engine.points - fit.values.len() + 1;
            let realised = hypothesis.realise(&fit.values).map_err(|e| e.to_string())?;
            let total: Option<f64> = fitted
                .iter()
                .map(|&i| {
                    let experiment = &campaign.experiments[i];
                    let predicted = realised.predict(experiment, settings).ok()?;
                    score(&experiment.recording, &predicted)
                        .map(|s| s.error * campaign.file.experiments[i].weight)
                })
                .sum();
            if total.is_some_and(|v| v <= target) {
                found = Some(counted);
                break;
            }
        }
        runs.push(found.filter(|&n| n <= BUDGET));
    }
    Ok(runs)
}

/// The median of `runs`, a run that missed counting as more than any that reached (none: the
/// median run missed).
pub fn median(runs: &[Option<usize>]) -> Option<usize> {
    let mut sorted: Vec<usize> = runs.iter().map(|r| r.unwrap_or(usize::MAX)).collect();
    sorted.sort_unstable();
    sorted
        .get(sorted.len() / 2)
        .copied()
        .filter(|&n| n != usize::MAX)
}

/// An optimiser run alone on the synthetic flow campaign, for comparison with the finish.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Baseline {
    /// The Bayesian optimiser (GP, log-EI) for the whole budget.
    Bayesian,
    /// Random Latin hypercube sampling.
    RandomLatinHypercube,
    /// CMA-ES from the box centre.
    CmaEs,
}

impl Baseline {
    /// The name docs/calibration.md gives it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Bayesian => "Bayesian (GP, log-EI)",
            Self::RandomLatinHypercube => "random Latin hypercube",
            Self::CmaEs => "CMA-ES",
        }
    }
}

/// For each seed, the simulations `baseline` alone (batches of two) needs until the error is
/// at most `factor` times [`NOISE_FLOOR`] (none: not within `budget`).
pub fn baseline_to_target(
    fixtures: &Path,
    baseline: Baseline,
    factor: f64,
    budget: usize,
    seeds: u64,
) -> Result<Vec<Option<usize>>, String> {
    let flow = SyntheticFlow::load(fixtures)?;
    let target = factor * NOISE_FLOOR;
    let pairs = flow.space.bound_pairs();
    let mut runs = Vec::new();
    for seed in 0..seeds {
        let bounds = Bounds::from_pairs(&pairs).map_err(|e| e.to_string())?;
        let settings = OptimiserSettings::new(flow.space.dimension(), budget, seed).with_batch(2);
        let mut optimiser: Box<dyn AskTell> = match baseline {
            Baseline::Bayesian => {
                Box::new(BayesianOptimiser::new(bounds, settings).map_err(|e| e.to_string())?)
            }
            Baseline::RandomLatinHypercube => {
                Box::new(RandomSearch::new(bounds, &settings).map_err(|e| e.to_string())?)
            }
            Baseline::CmaEs => Box::new(CmaEs::new(bounds, &settings).map_err(|e| e.to_string())?),
        };
        runs.push(race(
            optimiser.as_mut(),
            &|x| flow.error(x),
            target,
            budget,
        )?);
    }
    Ok(runs)
}

/// Ask and tell `optimiser` (on the log of the error) until a simulation reaches `target`
/// (the simulations used) or `budget` is spent (none).
fn race(
    optimiser: &mut dyn AskTell,
    objective: &dyn Fn(&[f64]) -> Option<f64>,
    target: f64,
    budget: usize,
) -> Result<Option<usize>, String> {
    let mut used = 0;
    while used < budget {
        let points = optimiser.ask();
        if points.is_empty() {
            return Ok(None);
        }
        let values: Vec<Option<f64>> = points.iter().map(|p| objective(p)).collect();
        for value in &values {
            used += 1;
            if value.is_some_and(|v| v <= target) {
                return Ok(Some(used));
            }
        }
        let logs: Vec<Option<f64>> = values
            .iter()
            .map(|v| v.map(|e| e.max(1e-300).ln()))
            .collect();
        optimiser.tell(&points, &logs).map_err(|e| e.to_string())?;
    }
    Ok(None)
}

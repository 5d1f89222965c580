//! The calibration's optimiser: the batch Bayesian optimiser of [`crate::optimise`] over a
//! model's box of constants.

use super::run::Proposer;
use crate::fit::ModelSpace;
use crate::optimise::{AskTell, BayesianOptimiser, Bounds, OptimiserSettings};

struct Bayesian(BayesianOptimiser);

impl Proposer for Bayesian {
    fn ask(&mut self) -> Vec<Vec<f64>> {
        self.0.ask()
    }

    fn tell(&mut self, points: &[Vec<f64>], values: &[Option<f64>]) -> Result<(), String> {
        self.0.tell(points, values).map_err(|e| e.to_string())
    }
}

/// A proposer that cannot be built (invalid bounds or settings): proposes nothing, so the
/// run stops with "no feasible candidate" naming the model, and says why.
struct Unusable(String);

impl Proposer for Unusable {
    fn ask(&mut self) -> Vec<Vec<f64>> {
        eprintln!("optimiser: {}", self.0);
        Vec::new()
    }

    fn tell(&mut self, _: &[Vec<f64>], _: &[Option<f64>]) -> Result<(), String> {
        Err(self.0.clone())
    }
}

/// Builds a Bayesian optimiser per instance: Latin hypercube of `design` points (default
/// `3 x dimension`, at most the budget), GP + log-EI, batches of `batch` (kriging believer),
/// seeded.
pub fn bayesian_factory(
    design: Option<usize>,
) -> impl Fn(&ModelSpace, usize, usize, u64) -> Box<dyn Proposer> + Sync {
    move |space: &ModelSpace, budget: usize, batch: usize, seed: u64| -> Box<dyn Proposer> {
        let pairs = space.bound_pairs();
        let built = Bounds::from_pairs(&pairs).and_then(|bounds| {
            let mut settings =
                OptimiserSettings::new(space.dimension(), budget, seed).with_batch(batch);
            if let Some(design) = design {
                settings.initial = design.min(budget);
            }
            BayesianOptimiser::new(bounds, settings)
        });
        match built {
            Ok(optimiser) => Box::new(Bayesian(optimiser)),
            Err(error) => Box::new(Unusable(format!("model {}: {error}", space.name))),
        }
    }
}

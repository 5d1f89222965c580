//! Batch Bayesian optimisation (seed 000 sec. 4; Jones, Schonlau & Welch 1998, "Efficient
//! global optimization of expensive black-box functions"): a Latin hypercube start, then a
//! Gaussian-process surrogate with log expected improvement and kriging-believer batches,
//! from `egobox-ego`'s ask/tell service.

use super::design::{latin_hypercube, space_filling, squared_distance};
use super::{checked_values, AskTell, Bounds, Evaluation, OptimiseError, OptimiserSettings};
use crate::random::SplitMix64;
use egobox_ego::{
    CorrelationSpec, EgorServiceBuilder, InfillStrategy, QEiStrategy, RegressionSpec, RuntimeFlags,
};
use ndarray::Array2;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// Points closer than this (unit-cube distance) to an evaluated or proposed point are not
/// proposed again.
const DUPLICATE_DISTANCE: f64 = 1e-9;

/// Covariance kernel of the Gaussian process.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Kernel {
    /// Squared exponential, `exp(-sum_i theta_i d_i^2)` (seed 000).
    #[default]
    SquaredExponential,
    /// Matern 5/2: rougher than the squared exponential, often more robust on simulator
    /// responses.
    Matern52,
}

/// Batch Bayesian optimiser with an ask/tell interface (see the [module](super) notes).
///
/// The first [`ask`](AskTell::ask) returns the Latin hypercube start of `settings.initial`
/// points; each later one returns `settings.batch` proposals (fewer at the end of the budget)
/// that maximise log-EI under the kriging-believer heuristic. Points asked but not yet told
/// enter the surrogate at the best value seen so far (constant liar), so `ask` may be called
/// again before the previous batch is told.
///
/// ```
/// use stoss::optimise::{AskTell, BayesianOptimiser, Bounds, OptimiserSettings};
/// let bounds = Bounds::new(vec![0.0, 0.0], vec![1.0, 2.0]).unwrap();
/// let settings = OptimiserSettings::new(2, 20, 42).with_batch(2);
/// let mut optimiser = BayesianOptimiser::new(bounds, settings).unwrap();
/// loop {
///     let points = optimiser.ask();
///     if points.is_empty() {
///         break;
///     }
///     let values: Vec<Option<f64>> = points
///         .iter()
///         .map(|x| Some((x[0] - 0.3).powi(2) + (x[1] - 1.2).powi(2)))
///         .collect();
///     optimiser.tell(&points, &values).unwrap();
/// }
/// let (x, value) = optimiser.best().unwrap();
/// assert!(value < 1e-3, "{x:?} {value}");
/// ```
#[derive(Clone, Debug)]
pub struct BayesianOptimiser {
    bounds: Bounds,
    settings: OptimiserSettings,
    kernel: Kernel,
    /// Told evaluations (physical units) and their unit-cube coordinates.
    evaluations: Vec<Evaluation>,
    unit: Vec<Vec<f64>>,
    /// Asked, not yet told: (physical, unit-cube) coordinates.
    pending: Vec<(Vec<f64>, Vec<f64>)>,
    started: bool,
    fallbacks: usize,
}

impl BayesianOptimiser {
    /// An optimiser over `bounds` with the squared-exponential kernel.
    pub fn new(bounds: Bounds, settings: OptimiserSettings) -> Result<Self, OptimiseError> {
        settings.validate()?;
        Ok(Self {
            bounds,
            settings,
            kernel: Kernel::default(),
            evaluations: Vec::new(),
            unit: Vec::new(),
            pending: Vec::new(),
            started: false,
            fallbacks: 0,
        })
    }

    /// The same optimiser with another kernel.
    pub fn with_kernel(mut self, kernel: Kernel) -> Self {
        self.kernel = kernel;
        self
    }

    /// The bounds.
    pub fn bounds(&self) -> &Bounds {
        &self.bounds
    }

    /// The settings.
    pub fn settings(&self) -> &OptimiserSettings {
        &self.settings
    }

    /// Points asked and not yet told.
    pub fn pending(&self) -> usize {
        self.pending.len()
    }

    /// Failed evaluations told so far.
    pub fn failures(&self) -> usize {
        self.evaluations
            .iter()
            .filter(|e| e.value.is_none())
            .count()
    }

    /// Proposals that came from the space-filling fall-back instead of the surrogate (too few
    /// successes, a constant objective, or a surrogate that could not be fitted).
    pub fn fallbacks(&self) -> usize {
        self.fallbacks
    }

    /// A seed for the proposals made after `count` points were asked: the same history gives
    /// the same proposals, different iterations get different multistart points.
    fn call_seed(&self, count: usize) -> u64 {
        let mut rng = SplitMix64::new(
            self.settings.seed ^ (count as u64).wrapping_mul(0xD1B5_4A32_D192_ED03),
        );
        rng.next_u64()
    }

    /// `n` proposals in the unit cube.
    fn propose(&mut self, n: usize) -> Vec<Vec<f64>> {
        let dim = self.bounds.dim();
        let asked = self.evaluations.len() + self.pending.len();
        let seed = self.call_seed(asked);
        let (x, y) = self.training_data();
        let distinct_values = y
            .iter()
            .any(|&v| y.first().is_some_and(|&first| v != first));
        let mut proposals = Vec::with_capacity(n);
        if x.len() >= 2 && distinct_values {
            proposals = self.suggest(&x, &y, n, seed);
        }
        let taken: Vec<Vec<f64>> = self
            .unit
            .iter()
            .chain(self.pending.iter().map(|p| &p.1))
            .cloned()
            .collect();
        let mut accepted: Vec<Vec<f64>> = Vec::with_capacity(n);
        for p in proposals {
            let p: Vec<f64> = p.iter().map(|v| v.clamp(0.0, 1.0)).collect();
            let close =
                |q: &Vec<f64>| squared_distance(q, &p) < DUPLICATE_DISTANCE * DUPLICATE_DISTANCE;
            if p.len() == dim && !taken.iter().any(close) && !accepted.iter().any(close) {
                accepted.push(p);
            }
            if accepted.len() == n {
                break;
            }
        }
        if accepted.len() < n {
            let missing = n - accepted.len();
            let existing: Vec<Vec<f64>> = taken.iter().chain(&accepted).cloned().collect();
            accepted.extend(space_filling(&existing, missing, dim, seed ^ 0x5F11));
            self.fallbacks += missing;
        }
        accepted
    }

    /// The surrogate's data in the unit cube: successes at their values, failures at the worst
    /// value seen (imputation), pending points at the best (constant liar); exact duplicates
    /// keep their lowest value.
    fn training_data(&self) -> (Vec<Vec<f64>>, Vec<f64>) {
        let finite = self.evaluations.iter().filter_map(|e| e.value);
        let worst = finite.clone().fold(f64::NEG_INFINITY, f64::max);
        let best = finite.fold(f64::INFINITY, f64::min);
        if !best.is_finite() {
            return (Vec::new(), Vec::new());
        }
        let told = self
            .unit
            .iter()
            .zip(&self.evaluations)
            .map(|(u, e)| (u, e.value.unwrap_or(worst)));
        let lies = self.pending.iter().map(|p| (&p.1, best));
        let mut x: Vec<Vec<f64>> = Vec::new();
        let mut y: Vec<f64> = Vec::new();
        for (u, v) in told.chain(lies) {
            match x.iter().position(|q| q == u) {
                Some(i) => y[i] = y[i].min(v),
                None => {
                    x.push(u.clone());
                    y.push(v);
                }
            }
        }
        (x, y)
    }

    /// Up to `n` proposals from the library (unit cube); empty if it fails.
    fn suggest(&self, x: &[Vec<f64>], y: &[f64], n: usize, seed: u64) -> Vec<Vec<f64>> {
        let dim = self.bounds.dim();
        let Ok(x_data) = Array2::from_shape_vec((x.len(), dim), x.concat()) else {
            return Vec::new();
        };
        let Ok(y_data) = Array2::from_shape_vec((y.len(), 1), y.to_vec()) else {
            return Vec::new();
        };
        let limits = Array2::from_shape_fn((dim, 2), |(_, j)| j as f64);
        let correlation = match self.kernel {
            Kernel::SquaredExponential => CorrelationSpec::SQUAREDEXPONENTIAL,
            Kernel::Matern52 => CorrelationSpec::MATERN52,
        };
        let service = EgorServiceBuilder::optimize()
            .configure(|config| {
                config
                    .configure_gp(|gp| {
                        gp.regression_spec(RegressionSpec::CONSTANT)
                            .correlation_spec(correlation)
                    })
                    .infill_strategy(InfillStrategy::LogEI)
                    .configure_qei(|qei| qei.batch(n).strategy(QEiStrategy::KrigingBeliever))
                    .runtime_flags(RuntimeFlags::none())
                    .seed(seed)
            })
            .min_within(&limits);
        let Ok(service) = service else {
            return Vec::new();
        };
        // The library panics on a surrogate it cannot train; a failed iteration falls back to
        // space filling instead of ending the run.
        match catch_unwind(AssertUnwindSafe(|| service.suggest(&x_data, &y_data))) {
            Ok(points) => points
                .rows()
                .into_iter()
                .filter(|row| row.iter().all(|v| v.is_finite()))
                .map(|row| row.to_vec())
                .collect(),
            Err(_) => Vec::new(),
        }
    }
}

impl AskTell for BayesianOptimiser {
    fn ask(&mut self) -> Vec<Vec<f64>> {
        let used = self.evaluations.len() + self.pending.len();
        let remaining = self.settings.budget.saturating_sub(used);
        if remaining == 0 {
            return Vec::new();
        }
        // Points told before the first ask (a warm start) count towards the initial design:
        // the Latin hypercube fills only what they leave of it.
        let design = self.settings.initial.saturating_sub(self.evaluations.len());
        let unit = if self.started || design == 0 {
            self.started = true;
            self.propose(self.settings.batch.min(remaining))
        } else {
            self.started = true;
            let n = design.min(remaining);
            // The bounds have at least one parameter, so the design cannot fail.
            latin_hypercube(n, self.bounds.dim(), self.settings.seed).unwrap_or_default()
        };
        let points: Vec<Vec<f64>> = unit.iter().map(|u| self.bounds.from_unit(u)).collect();
        self.pending
            .extend(points.iter().cloned().zip(unit.iter().cloned()));
        points
    }

    fn tell(&mut self, points: &[Vec<f64>], values: &[Option<f64>]) -> Result<(), OptimiseError> {
        let values = checked_values(&self.bounds, points, values)?;
        for (x, value) in points.iter().zip(values) {
            // A point handed out by `ask` keeps its exact unit-cube coordinates.
            let unit = match self.pending.iter().position(|p| &p.0 == x) {
                Some(i) => self.pending.remove(i).1,
                None => self.bounds.to_unit(x),
            };
            self.unit.push(unit);
            self.evaluations.push(Evaluation {
                x: x.clone(),
                value,
            });
        }
        Ok(())
    }

    fn evaluations(&self) -> &[Evaluation] {
        &self.evaluations
    }
}

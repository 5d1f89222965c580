//! The optimiser core of `stoss calibrate`: a batch Bayesian optimiser with an ask/tell
//! interface, independent of the simulations (the objective is a black box supplied by the
//! caller).
//!
//! # Method (seed 000, section 4)
//!
//! 1. A Latin hypercube start of `3 x dimension` points ([`latin_hypercube`]).
//! 2. A Gaussian-process surrogate of the objective with a squared-exponential kernel (or
//!    Matern 5/2, [`Kernel`]), a constant mean and one length scale per parameter, fitted by
//!    maximum likelihood (multistart COBYLA on the log-likelihood).
//! 3. Expected improvement, maximised in its logarithmic form (log-EI, Ament et al. 2023),
//!    which stays informative where EI underflows.
//! 4. Batches of `batch` proposals per iteration so that every core runs a simulation: the
//!    kriging-believer heuristic (Ginsbourger, Le Riche & Carraro 2010) - each proposal is added
//!    to the data at its surrogate mean before the next one is chosen.
//!
//! The surrogate and the acquisition come from the `egobox` crates (Lafage 2022, "egobox, a
//! Rust toolbox for efficient global optimization", JOSS 7(78) 4737): `egobox-doe` for the
//! design and `egobox-ego`'s ask/tell service (`EgorServiceBuilder` ... `suggest`) for the GP
//! and log-EI. `docs/calibration.md` records why this library was chosen and what it costs.
//!
//! Everything runs in the unit cube: [`Bounds`] scales proposals out to physical units and
//! told points back in.
//!
//! # Failures
//!
//! A `None` (or non-finite) value is a failed simulation. It is recorded as a failure and the
//! surrogate sees it at the worst value observed so far (imputation), which pushes EI away
//! from the region without modelling the failure boundary separately. Failures never stop a
//! run; a surrogate that cannot be fitted (too few successes, a constant objective, or an
//! internal error of the library) falls back to space-filling proposals.
//!
//! # Determinism
//!
//! Every random number derives from [`OptimiserSettings::seed`] (the design, the multistart
//! points of the hyper-parameter and acquisition optimisers, the fall-back proposals). The
//! library's parallel loops reduce in index order, so the proposals do not depend on the
//! number of threads: the same seed, bounds, settings and told values give the same
//! proposals bit for bit. The proposals do depend on `batch`, which therefore belongs in the
//! record of a run.
//!
//! # Baselines
//!
//! [`RandomSearch`] (a random Latin hypercube of the whole budget) and [`CmaEs`] (Hansen's CMA-ES)
//! share the [`AskTell`] shape so that the benchmark (`cargo bench -p stoss --bench optimise`)
//! compares like with like.

mod bayes;
mod cmaes;
mod design;
pub mod functions;

pub use bayes::{BayesianOptimiser, Kernel};
pub use cmaes::CmaEs;
pub use design::{latin_hypercube, random_latin_hypercube, RandomSearch};

/// Errors of the optimiser core.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum OptimiseError {
    /// The bounds have no parameters.
    #[error("the bounds have no parameters")]
    NoParameters,
    /// Lower and upper bounds have different lengths.
    #[error("{lower} lower bounds but {upper} upper bounds; give one of each per parameter")]
    BoundsLength {
        /// Number of lower bounds.
        lower: usize,
        /// Number of upper bounds.
        upper: usize,
    },
    /// A bound is not finite, or the lower bound is not below the upper bound.
    #[error("parameter {index}: bounds [{lower}, {upper}] must be finite with lower < upper")]
    InvalidBound {
        /// Parameter index.
        index: usize,
        /// Its lower bound.
        lower: f64,
        /// Its upper bound.
        upper: f64,
    },
    /// A setting is out of range.
    #[error("optimiser settings: {0}")]
    InvalidSettings(String),
    /// `tell` was given a different number of points and values.
    #[error("tell: {points} points but {values} values")]
    LengthMismatch {
        /// Number of points.
        points: usize,
        /// Number of values.
        values: usize,
    },
    /// A point has the wrong number of coordinates.
    #[error("point {point} has {found} coordinates; the bounds have {expected}")]
    DimensionMismatch {
        /// Index of the point in the call.
        point: usize,
        /// Dimension of the bounds.
        expected: usize,
        /// Coordinates given.
        found: usize,
    },
    /// A point has a non-finite coordinate or lies outside the bounds.
    #[error(
        "point {point}: coordinate {coordinate} = {value} is not finite or outside the bounds"
    )]
    PointOutOfBounds {
        /// Index of the point in the call.
        point: usize,
        /// Index of the offending coordinate.
        coordinate: usize,
        /// Its value.
        value: f64,
    },
    /// The objective returned a different number of values than points it was given.
    #[error("the objective returned {found} values for {expected} points")]
    ObjectiveLength {
        /// Points given.
        expected: usize,
        /// Values returned.
        found: usize,
    },
    /// Every evaluation of the run failed.
    #[error("all {evaluations} evaluations failed; check the objective and the bounds")]
    NoSuccessfulEvaluation {
        /// Evaluations made.
        evaluations: usize,
    },
}

/// A box of parameters: the optimisers work in the unit cube and scale in and out of it.
#[derive(Clone, Debug, PartialEq)]
pub struct Bounds {
    lower: Vec<f64>,
    upper: Vec<f64>,
}

impl Bounds {
    /// The box `lower[i] <= x[i] <= upper[i]`; every bound finite and `lower[i] < upper[i]`.
    pub fn new(lower: Vec<f64>, upper: Vec<f64>) -> Result<Self, OptimiseError> {
        if lower.len() != upper.len() {
            return Err(OptimiseError::BoundsLength {
                lower: lower.len(),
                upper: upper.len(),
            });
        }
        if lower.is_empty() {
            return Err(OptimiseError::NoParameters);
        }
        for (index, (&l, &u)) in lower.iter().zip(&upper).enumerate() {
            if !(l.is_finite() && u.is_finite() && l < u) {
                return Err(OptimiseError::InvalidBound {
                    index,
                    lower: l,
                    upper: u,
                });
            }
        }
        Ok(Self { lower, upper })
    }

    /// The box from `(lower, upper)` pairs.
    pub fn from_pairs(pairs: &[(f64, f64)]) -> Result<Self, OptimiseError> {
        Self::new(
            pairs.iter().map(|p| p.0).collect(),
            pairs.iter().map(|p| p.1).collect(),
        )
    }

    /// The unit cube `[0, 1]^dim`.
    pub fn unit(dim: usize) -> Result<Self, OptimiseError> {
        Self::new(vec![0.0; dim], vec![1.0; dim])
    }

    /// Number of parameters.
    pub fn dim(&self) -> usize {
        self.lower.len()
    }

    /// Lower bounds.
    pub fn lower(&self) -> &[f64] {
        &self.lower
    }

    /// Upper bounds.
    pub fn upper(&self) -> &[f64] {
        &self.upper
    }

    /// Physical coordinates of a unit-cube point (clamped into the box against rounding).
    pub fn from_unit(&self, unit: &[f64]) -> Vec<f64> {
        unit.iter()
            .zip(self.lower.iter().zip(&self.upper))
            .map(|(&u, (&l, &h))| crate::fit::unit_cube::from_unit(u, l, h).clamp(l, h))
            .collect()
    }

    /// Unit-cube coordinates of a physical point (clamped into `[0, 1]` against rounding).
    pub fn to_unit(&self, x: &[f64]) -> Vec<f64> {
        x.iter()
            .zip(self.lower.iter().zip(&self.upper))
            .map(|(&v, (&l, &h))| crate::fit::unit_cube::to_unit(v, l, h).clamp(0.0, 1.0))
            .collect()
    }

    /// Checks that `x` has the right dimension and lies in the box; `point` names it in the
    /// error.
    pub fn check(&self, point: usize, x: &[f64]) -> Result<(), OptimiseError> {
        if x.len() != self.dim() {
            return Err(OptimiseError::DimensionMismatch {
                point,
                expected: self.dim(),
                found: x.len(),
            });
        }
        for (coordinate, (&v, (&l, &h))) in
            x.iter().zip(self.lower.iter().zip(&self.upper)).enumerate()
        {
            if !(v >= l && v <= h) {
                return Err(OptimiseError::PointOutOfBounds {
                    point,
                    coordinate,
                    value: v,
                });
            }
        }
        Ok(())
    }
}

/// Budget, design size, batch size and seed of an optimiser.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OptimiserSettings {
    /// Total number of evaluations, the initial design included.
    pub budget: usize,
    /// Size of the initial Latin hypercube (seed 000: 3 x dimension).
    pub initial: usize,
    /// Proposals per iteration (default: the number of cores, so that every core runs a
    /// simulation). The proposals depend on it: record it with the seed.
    pub batch: usize,
    /// Seed of every random number the optimiser draws.
    pub seed: u64,
}

impl OptimiserSettings {
    /// Seed 000's settings for `dim` parameters: an initial design of `3 dim` points (at most
    /// the budget) and one proposal per core.
    pub fn new(dim: usize, budget: usize, seed: u64) -> Self {
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        Self {
            budget,
            initial: (3 * dim).min(budget),
            batch: cores,
            seed,
        }
    }

    /// The same settings with `batch` proposals per iteration.
    pub fn with_batch(mut self, batch: usize) -> Self {
        self.batch = batch;
        self
    }

    /// Checks the settings: a budget, a batch and a design of at least one point, the design
    /// within the budget.
    pub fn validate(&self) -> Result<(), OptimiseError> {
        if self.budget == 0 {
            return Err(OptimiseError::InvalidSettings(
                "the budget must be at least one evaluation".into(),
            ));
        }
        if self.batch == 0 {
            return Err(OptimiseError::InvalidSettings(
                "the batch must hold at least one proposal".into(),
            ));
        }
        if self.initial == 0 || self.initial > self.budget {
            return Err(OptimiseError::InvalidSettings(format!(
                "the initial design ({}) must hold between 1 and budget ({}) points",
                self.initial, self.budget
            )));
        }
        Ok(())
    }
}

/// One evaluation: the point (physical units) and its value, `None` if it failed.
#[derive(Clone, Debug, PartialEq)]
pub struct Evaluation {
    /// The point.
    pub x: Vec<f64>,
    /// The objective, `None` for a failed or non-finite evaluation.
    pub value: Option<f64>,
}

/// The ask/tell shape shared by the optimisers.
pub trait AskTell {
    /// The next points to evaluate (physical units); empty once the budget is spent.
    fn ask(&mut self) -> Vec<Vec<f64>>;

    /// The values of evaluated points, `None` (or a non-finite value) for a failure. Points
    /// need not come from [`AskTell::ask`] (a resumed run may replay a log), but they must lie
    /// in the bounds. On error nothing is recorded.
    fn tell(&mut self, points: &[Vec<f64>], values: &[Option<f64>]) -> Result<(), OptimiseError>;

    /// Every evaluation told so far, in order.
    fn evaluations(&self) -> &[Evaluation];

    /// The best evaluation so far (the first of equals), if any succeeded.
    fn best(&self) -> Option<(Vec<f64>, f64)> {
        best_of(self.evaluations())
    }
}

/// The best successful evaluation (the first of equals).
pub(crate) fn best_of(evaluations: &[Evaluation]) -> Option<(Vec<f64>, f64)> {
    let mut best: Option<&Evaluation> = None;
    for e in evaluations {
        if let Some(v) = e.value {
            if best.and_then(|b| b.value).is_none_or(|b| v < b) {
                best = Some(e);
            }
        }
    }
    best.and_then(|e| e.value.map(|v| (e.x.clone(), v)))
}

/// Validates a `tell` call and converts its values: non-finite values become failures.
pub(crate) fn checked_values(
    bounds: &Bounds,
    points: &[Vec<f64>],
    values: &[Option<f64>],
) -> Result<Vec<Option<f64>>, OptimiseError> {
    if points.len() != values.len() {
        return Err(OptimiseError::LengthMismatch {
            points: points.len(),
            values: values.len(),
        });
    }
    for (i, x) in points.iter().enumerate() {
        bounds.check(i, x)?;
    }
    Ok(values.iter().map(|v| v.filter(|v| v.is_finite())).collect())
}

/// The result of [`minimise`].
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    /// The best point (physical units).
    pub x: Vec<f64>,
    /// Its objective.
    pub value: f64,
    /// Every evaluation, in order.
    pub evaluations: Vec<Evaluation>,
}

impl Outcome {
    /// Number of failed evaluations.
    pub fn failures(&self) -> usize {
        self.evaluations
            .iter()
            .filter(|e| e.value.is_none())
            .count()
    }
}

/// Drives an optimiser until its budget is spent: `objective` receives each batch and returns
/// one value per point (`None` for a failure).
pub fn run<O: AskTell + ?Sized>(
    optimiser: &mut O,
    objective: impl Fn(&[Vec<f64>]) -> Vec<Option<f64>>,
) -> Result<(), OptimiseError> {
    loop {
        let points = optimiser.ask();
        if points.is_empty() {
            return Ok(());
        }
        let values = objective(&points);
        if values.len() != points.len() {
            return Err(OptimiseError::ObjectiveLength {
                expected: points.len(),
                found: values.len(),
            });
        }
        optimiser.tell(&points, &values)?;
    }
}

/// Minimises a black-box `objective` over `bounds` by Bayesian optimisation
/// ([`BayesianOptimiser`], squared-exponential kernel). The objective receives batches of
/// `settings.batch` points (the first batch is the initial design) and may evaluate them in
/// parallel; it returns `None` for a failed evaluation.
///
/// ```
/// use stoss::optimise::{minimise, Bounds, OptimiserSettings};
/// let bounds = Bounds::new(vec![-2.0], vec![2.0]).unwrap();
/// let settings = OptimiserSettings::new(1, 12, 7).with_batch(1);
/// let outcome = minimise(
///     |xs: &[Vec<f64>]| xs.iter().map(|x| Some((x[0] - 0.5).powi(2))).collect(),
///     &bounds,
///     &settings,
/// )
/// .unwrap();
/// assert!((outcome.x[0] - 0.5).abs() < 1e-2);
/// ```
pub fn minimise(
    objective: impl Fn(&[Vec<f64>]) -> Vec<Option<f64>>,
    bounds: &Bounds,
    settings: &OptimiserSettings,
) -> Result<Outcome, OptimiseError> {
    let mut optimiser = BayesianOptimiser::new(bounds.clone(), settings.clone())?;
    run(&mut optimiser, objective)?;
    let evaluations = optimiser.evaluations().to_vec();
    let (x, value) = optimiser
        .best()
        .ok_or(OptimiseError::NoSuccessfulEvaluation {
            evaluations: evaluations.len(),
        })?;
    Ok(Outcome {
        x,
        value,
        evaluations,
    })
}

/// The 1-based number of evaluations after which the best value first reached `target`
/// (`value <= target`), or `None` if it never did: the benchmark's evaluations-to-target.
pub fn evaluations_to_target(evaluations: &[Evaluation], target: f64) -> Option<usize> {
    evaluations
        .iter()
        .position(|e| e.value.is_some_and(|v| v <= target))
        .map(|i| i + 1)
}

#[cfg(test)]
mod tests;

//! Designs of experiments: the Latin hypercube start (McKay, Beckman & Conover 1979), here
//! optimised for space filling by `egobox-doe`'s enhanced stochastic evolutionary algorithm
//! (Jin, Chen & Sudjianto 2005), and the random-search baseline built on it.

use super::{checked_values, AskTell, Bounds, Evaluation, OptimiseError, OptimiserSettings};
use crate::random::SplitMix64;
use egobox_doe::{Lhs, LhsKind, SamplingMethod};
use ndarray::Array2;
use rand_xoshiro::rand_core::SeedableRng;
use rand_xoshiro::Xoshiro256Plus;

/// A Latin hypercube of `n` points in the unit cube `[0, 1]^dim`: each coordinate takes one
/// value in each of `n` equal strata, and the design maximises the distance between points
/// (ESE algorithm): the initial design of the Bayesian optimiser. The same `seed` gives the
/// same design. Its cost grows as `n^2`: prefer [`random_latin_hypercube`] beyond a few hundred
/// points.
pub fn latin_hypercube(n: usize, dim: usize, seed: u64) -> Result<Vec<Vec<f64>>, OptimiseError> {
    design(n, dim, seed, LhsKind::Optimized)
}

/// A plain random Latin hypercube (one uniform point per stratum, strata randomly paired):
/// the random-sampling baseline.
pub fn random_latin_hypercube(
    n: usize,
    dim: usize,
    seed: u64,
) -> Result<Vec<Vec<f64>>, OptimiseError> {
    design(n, dim, seed, LhsKind::Classic)
}

fn design(n: usize, dim: usize, seed: u64, kind: LhsKind) -> Result<Vec<Vec<f64>>, OptimiseError> {
    if dim == 0 {
        return Err(OptimiseError::NoParameters);
    }
    if n == 0 {
        return Ok(Vec::new());
    }
    if n == 1 {
        // One stratum per coordinate: a uniform point (the library needs two points).
        let mut rng = SplitMix64::new(seed);
        return Ok(vec![(0..dim).map(|_| rng.uniform()).collect()]);
    }
    let limits = Array2::from_shape_fn((dim, 2), |(_, j)| j as f64);
    let design = Lhs::new_with_rng(&limits, Xoshiro256Plus::seed_from_u64(seed))
        .kind(kind)
        .sample(n);
    Ok(design
        .rows()
        .into_iter()
        .map(|row| row.iter().map(|v| v.clamp(0.0, 1.0)).collect())
        .collect())
}

/// `count` points of the unit cube chosen one by one, each the farthest (largest distance to
/// the nearest point) of `64 dim` uniform candidates from `existing` and the points already
/// chosen: the fall-back proposals when no surrogate can be fitted.
pub(crate) fn space_filling(
    existing: &[Vec<f64>],
    count: usize,
    dim: usize,
    seed: u64,
) -> Vec<Vec<f64>> {
    let mut rng = SplitMix64::new(seed);
    let mut chosen: Vec<Vec<f64>> = Vec::with_capacity(count);
    for _ in 0..count {
        let mut best: Option<(f64, Vec<f64>)> = None;
        for _ in 0..64 * dim {
            let candidate: Vec<f64> = (0..dim).map(|_| rng.uniform()).collect();
            let nearest = existing
                .iter()
                .chain(&chosen)
                .map(|p| squared_distance(p, &candidate))
                .fold(f64::INFINITY, f64::min);
            if best.as_ref().is_none_or(|(d, _)| nearest > *d) {
                best = Some((nearest, candidate));
            }
        }
        if let Some((_, point)) = best {
            chosen.push(point);
        }
    }
    chosen
}

pub(crate) fn squared_distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum()
}

/// The random-search baseline: one random Latin hypercube of the whole budget
/// ([`random_latin_hypercube`]), handed out `batch` points at a time.
#[derive(Clone, Debug)]
pub struct RandomSearch {
    bounds: Bounds,
    batch: usize,
    design: Vec<Vec<f64>>,
    next: usize,
    evaluations: Vec<Evaluation>,
}

impl RandomSearch {
    /// A random search of `settings.budget` points; `settings.initial` is not used.
    pub fn new(bounds: Bounds, settings: &OptimiserSettings) -> Result<Self, OptimiseError> {
        settings.validate()?;
        let design = random_latin_hypercube(settings.budget, bounds.dim(), settings.seed)?
            .iter()
            .map(|u| bounds.from_unit(u))
            .collect();
        Ok(Self {
            bounds,
            batch: settings.batch,
            design,
            next: 0,
            evaluations: Vec::new(),
        })
    }
}

impl AskTell for RandomSearch {
    fn ask(&mut self) -> Vec<Vec<f64>> {
        let end = (self.next + self.batch).min(self.design.len());
        let points = self.design[self.next..end].to_vec();
        self.next = end;
        points
    }

    fn tell(&mut self, points: &[Vec<f64>], values: &[Option<f64>]) -> Result<(), OptimiseError> {
        let values = checked_values(&self.bounds, points, values)?;
        self.evaluations
            .extend(points.iter().zip(values).map(|(x, value)| Evaluation {
                x: x.clone(),
                value,
            }));
        Ok(())
    }

    fn evaluations(&self) -> &[Evaluation] {
        &self.evaluations
    }
}

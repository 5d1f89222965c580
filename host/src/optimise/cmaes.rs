//! The CMA-ES baseline: (mu/mu_w, lambda) evolution strategy with covariance matrix
//! adaptation, cumulative step-size control and the default parameters of Hansen (2016), "The
//! CMA evolution strategy: a tutorial", arXiv:1604.00772, run in the unit cube.

// Small dense linear algebra reads best with explicit indices.
#![allow(clippy::needless_range_loop)]

use super::{checked_values, AskTell, Bounds, Evaluation, OptimiseError, OptimiserSettings};
use crate::random::SplitMix64;

/// Initial step size in the unit cube.
const SIGMA0: f64 = 0.3;
/// Resampling attempts for a candidate outside the unit cube before it is clamped.
const RESAMPLES: usize = 50;

/// CMA-ES with an ask/tell interface: each `ask` returns one generation of `lambda` points
/// (`4 + floor(3 ln n)`, or the batch if larger), sampled around a mean that starts at the
/// centre of the box. Candidates outside the box are resampled, then clamped. Failures rank
/// last. A generation is used once all its points are told; points of an unfinished
/// generation count as failures when `ask` is called again. The search restarts from a
/// random mean when the step size collapses.
#[derive(Clone, Debug)]
pub struct CmaEs {
    bounds: Bounds,
    budget: usize,
    rng: SplitMix64,
    lambda: usize,
    weights: Vec<f64>,
    mu_eff: f64,
    c_sigma: f64,
    d_sigma: f64,
    c_c: f64,
    c_1: f64,
    c_mu: f64,
    chi_n: f64,
    mean: Vec<f64>,
    sigma: f64,
    /// Covariance, its eigenvectors (columns of `b`) and the square roots of its eigenvalues.
    c: Vec<Vec<f64>>,
    b: Vec<Vec<f64>>,
    d: Vec<f64>,
    p_sigma: Vec<f64>,
    p_c: Vec<f64>,
    generation: usize,
    /// The current generation.
    population: Vec<Member>,
    asked: usize,
    evaluations: Vec<Evaluation>,
}

/// A candidate of the current generation.
#[derive(Clone, Debug)]
struct Member {
    /// Physical point.
    x: Vec<f64>,
    /// Unit-cube step `y = (x - m) / sigma`.
    step: Vec<f64>,
    /// Value once told (`Some(None)` for a failure).
    value: Option<Option<f64>>,
}

impl CmaEs {
    /// CMA-ES with the budget, batch and seed of `settings` (`settings.initial` is not used).
    pub fn new(bounds: Bounds, settings: &OptimiserSettings) -> Result<Self, OptimiseError> {
        settings.validate()?;
        let n = bounds.dim();
        let nf = n as f64;
        let lambda = (4 + libm::floor(3.0 * libm::log(nf)) as usize).max(settings.batch);
        let mu = lambda / 2;
        let raw: Vec<f64> = (0..mu)
            .map(|i| libm::log((lambda as f64 + 1.0) / 2.0) - libm::log((i + 1) as f64))
            .collect();
        let sum: f64 = raw.iter().sum();
        let weights: Vec<f64> = raw.iter().map(|w| w / sum).collect();
        let mu_eff = 1.0 / weights.iter().map(|w| w * w).sum::<f64>();
        let c_sigma = (mu_eff + 2.0) / (nf + mu_eff + 5.0);
        let d_sigma = 1.0 + 2.0 * (((mu_eff - 1.0) / (nf + 1.0)).sqrt() - 1.0).max(0.0) + c_sigma;
        let c_c = (4.0 + mu_eff / nf) / (nf + 4.0 + 2.0 * mu_eff / nf);
        let c_1 = 2.0 / ((nf + 1.3).powi(2) + mu_eff);
        let c_mu =
            (1.0 - c_1).min(2.0 * (mu_eff - 2.0 + 1.0 / mu_eff) / ((nf + 2.0).powi(2) + mu_eff));
        let chi_n = nf.sqrt() * (1.0 - 1.0 / (4.0 * nf) + 1.0 / (21.0 * nf * nf));
        Ok(Self {
            bounds,
            budget: settings.budget,
            rng: SplitMix64::new(settings.seed),
            lambda,
            weights,
            mu_eff,
            c_sigma,
            d_sigma,
            c_c,
            c_1,
            c_mu,
            chi_n,
            mean: vec![0.5; n],
            sigma: SIGMA0,
            c: identity(n),
            b: identity(n),
            d: vec![1.0; n],
            p_sigma: vec![0.0; n],
            p_c: vec![0.0; n],
            generation: 0,
            population: Vec::new(),
            asked: 0,
            evaluations: Vec::new(),
        })
    }

    /// Population size.
    pub fn lambda(&self) -> usize {
        self.lambda
    }

    /// One candidate: its unit-cube point and step.
    fn sample(&mut self) -> (Vec<f64>, Vec<f64>) {
        let n = self.mean.len();
        let mut x = vec![0.0; n];
        let mut y = vec![0.0; n];
        for attempt in 0..RESAMPLES {
            let z: Vec<f64> = (0..n).map(|_| self.rng.normal()).collect();
            for i in 0..n {
                y[i] = (0..n).map(|j| self.b[i][j] * self.d[j] * z[j]).sum();
                x[i] = self.mean[i] + self.sigma * y[i];
            }
            if x.iter().all(|v| (0.0..=1.0).contains(v)) || attempt + 1 == RESAMPLES {
                break;
            }
        }
        for i in 0..n {
            x[i] = x[i].clamp(0.0, 1.0);
            y[i] = (x[i] - self.mean[i]) / self.sigma;
        }
        (x, y)
    }

    /// Updates mean, paths, covariance and step size from the told generation.
    fn update(&mut self) {
        let n = self.mean.len();
        let mut ranked: Vec<(f64, usize)> = self
            .population
            .iter()
            .enumerate()
            .filter_map(|(i, p)| p.value.flatten().map(|v| (v, i)))
            .collect();
        if ranked.is_empty() {
            // Nothing succeeded: sample again around the same mean.
            self.population.clear();
            return;
        }
        ranked.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        // Failures rank after every success, in their order.
        let failed = (0..self.population.len()).filter(|i| !ranked.iter().any(|r| r.1 == *i));
        let order: Vec<usize> = ranked.iter().map(|r| r.1).chain(failed).collect();
        let steps: Vec<&Vec<f64>> = order
            .iter()
            .take(self.weights.len())
            .map(|&i| &self.population[i].step)
            .collect();
        let mut y_w = vec![0.0; n];
        for (w, y) in self.weights.iter().zip(&steps) {
            for i in 0..n {
                y_w[i] += w * y[i];
            }
        }
        for i in 0..n {
            self.mean[i] = (self.mean[i] + self.sigma * y_w[i]).clamp(0.0, 1.0);
        }
        // C^(-1/2) y_w = B D^-1 B^T y_w.
        let bt_y: Vec<f64> = (0..n)
            .map(|j| (0..n).map(|i| self.b[i][j] * y_w[i]).sum::<f64>() / self.d[j])
            .collect();
        let c_inv_sqrt_y: Vec<f64> = (0..n)
            .map(|i| (0..n).map(|j| self.b[i][j] * bt_y[j]).sum())
            .collect();
        let cs = (self.c_sigma * (2.0 - self.c_sigma) * self.mu_eff).sqrt();
        for i in 0..n {
            self.p_sigma[i] = (1.0 - self.c_sigma) * self.p_sigma[i] + cs * c_inv_sqrt_y[i];
        }
        self.generation += 1;
        let norm_ps = self.p_sigma.iter().map(|v| v * v).sum::<f64>().sqrt();
        let h_sigma = norm_ps
            / (1.0 - (1.0 - self.c_sigma).powi(2 * self.generation as i32)).sqrt()
            < (1.4 + 2.0 / (n as f64 + 1.0)) * self.chi_n;
        let h = if h_sigma { 1.0 } else { 0.0 };
        let cc = (self.c_c * (2.0 - self.c_c) * self.mu_eff).sqrt();
        for i in 0..n {
            self.p_c[i] = (1.0 - self.c_c) * self.p_c[i] + h * cc * y_w[i];
        }
        let decay = 1.0 - self.c_1 - self.c_mu + (1.0 - h) * self.c_1 * self.c_c * (2.0 - self.c_c);
        for i in 0..n {
            for j in 0..n {
                let rank_mu: f64 = self
                    .weights
                    .iter()
                    .zip(&steps)
                    .map(|(w, y)| w * y[i] * y[j])
                    .sum();
                self.c[i][j] = decay * self.c[i][j]
                    + self.c_1 * self.p_c[i] * self.p_c[j]
                    + self.c_mu * rank_mu;
            }
        }
        self.sigma *= libm::exp((self.c_sigma / self.d_sigma) * (norm_ps / self.chi_n - 1.0));
        self.sigma = self.sigma.min(1.0);
        let (b, eigenvalues) = symmetric_eigen(&self.c);
        let degenerate = eigenvalues.iter().any(|&e| !e.is_finite() || e <= 0.0);
        let largest = eigenvalues.iter().fold(0.0_f64, |a, &e| a.max(e));
        if degenerate || self.sigma * largest.sqrt() < 1e-10 || !self.sigma.is_finite() {
            self.restart();
        } else {
            self.b = b;
            self.d = eigenvalues.iter().map(|e| e.sqrt()).collect();
        }
        self.population.clear();
    }

    /// A fresh search from a random mean.
    fn restart(&mut self) {
        let n = self.mean.len();
        self.mean = (0..n).map(|_| self.rng.uniform()).collect();
        self.sigma = SIGMA0;
        self.c = identity(n);
        self.b = identity(n);
        self.d = vec![1.0; n];
        self.p_sigma = vec![0.0; n];
        self.p_c = vec![0.0; n];
        self.generation = 0;
    }
}

impl AskTell for CmaEs {
    fn ask(&mut self) -> Vec<Vec<f64>> {
        if !self.population.is_empty() {
            // Untold points of the last generation count as failures.
            for p in &mut self.population {
                p.value.get_or_insert(None);
            }
            self.update();
        }
        let remaining = self.budget.saturating_sub(self.asked);
        let count = self.lambda.min(remaining);
        let mut points = Vec::with_capacity(count);
        for _ in 0..count {
            let (unit, step) = self.sample();
            let x = self.bounds.from_unit(&unit);
            points.push(x.clone());
            self.population.push(Member {
                x,
                step,
                value: None,
            });
        }
        self.asked += count;
        points
    }

    fn tell(&mut self, points: &[Vec<f64>], values: &[Option<f64>]) -> Result<(), OptimiseError> {
        let values = checked_values(&self.bounds, points, values)?;
        for (x, value) in points.iter().zip(values) {
            if let Some(member) = self
                .population
                .iter_mut()
                .find(|p| p.value.is_none() && &p.x == x)
            {
                member.value = Some(value);
            }
            self.evaluations.push(Evaluation {
                x: x.clone(),
                value,
            });
        }
        if !self.population.is_empty() && self.population.iter().all(|p| p.value.is_some()) {
            self.update();
        }
        Ok(())
    }

    fn evaluations(&self) -> &[Evaluation] {
        &self.evaluations
    }
}

fn identity(n: usize) -> Vec<Vec<f64>> {
    (0..n)
        .map(|i| (0..n).map(|j| if i == j { 1.0 } else { 0.0 }).collect())
        .collect()
}

/// Eigen-decomposition of a symmetric matrix by cyclic Jacobi rotations: the eigenvectors (as
/// columns) and the eigenvalues.
fn symmetric_eigen(a: &[Vec<f64>]) -> (Vec<Vec<f64>>, Vec<f64>) {
    let n = a.len();
    let mut a: Vec<Vec<f64>> = a.to_vec();
    // Symmetrise against rounding.
    for i in 0..n {
        for j in 0..i {
            let m = 0.5 * (a[i][j] + a[j][i]);
            a[i][j] = m;
            a[j][i] = m;
        }
    }
    let mut v = identity(n);
    for _sweep in 0..100 {
        let off: f64 = (0..n)
            .flat_map(|i| (0..n).filter(move |&j| j != i).map(move |j| (i, j)))
            .map(|(i, j)| a[i][j] * a[i][j])
            .sum();
        let diag: f64 = (0..n).map(|i| a[i][i] * a[i][i]).sum();
        if off <= 1e-30 * diag.max(f64::MIN_POSITIVE) {
            break;
        }
        for p in 0..n {
            for q in p + 1..n {
                if a[p][q] == 0.0 {
                    continue;
                }
                let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for k in 0..n {
                    let akp = a[k][p];
                    let akq = a[k][q];
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for k in 0..n {
                    let apk = a[p][k];
                    let aqk = a[q][k];
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for row in v.iter_mut() {
                    let vkp = row[p];
                    let vkq = row[q];
                    row[p] = c * vkp - s * vkq;
                    row[q] = s * vkp + c * vkq;
                }
            }
        }
    }
    let eigenvalues = (0..n).map(|i| a[i][i]).collect();
    (v, eigenvalues)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jacobi_eigen_decomposition_reconstructs_the_matrix() {
        // GOAL: the eigen-decomposition CMA-ES relies on is correct.
        // SETUP: a symmetric positive-definite 3 x 3 matrix.
        // REFERENCE: A = V diag(l) V^T to 1e-12, V orthonormal to 1e-12.
        let a = vec![
            vec![4.0, 1.0, 0.5],
            vec![1.0, 3.0, 0.2],
            vec![0.5, 0.2, 2.0],
        ];
        let (v, l) = symmetric_eigen(&a);
        for i in 0..3 {
            for j in 0..3 {
                let r: f64 = (0..3).map(|k| v[i][k] * l[k] * v[j][k]).sum();
                assert!((r - a[i][j]).abs() < 1e-12, "{i} {j}: {r} vs {}", a[i][j]);
                let o: f64 = (0..3).map(|k| v[k][i] * v[k][j]).sum();
                let e = if i == j { 1.0 } else { 0.0 };
                assert!((o - e).abs() < 1e-12);
            }
        }
    }
}

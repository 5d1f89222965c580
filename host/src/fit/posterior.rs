//! The posterior of a model's calibrated constants and the band it puts around the prediction
//! of every recorded point, fitted or held out.
//!
//! - **Surrogate of the misfit.** The Gauss-Newton (Laplace) surrogate about the selected
//!   constants `theta0`: `chi^2(theta) = chi^2(theta0) + (theta - theta0)^T J^T J (theta -
//!   theta0)` with the weighted residuals' Jacobian `J` ([`Linearisation`], the one the
//!   linearised intervals use). The selected constants are taken as the likelihood's mode,
//!   as the linearised intervals take them: the calibration minimised its own objective (seed
//!   000's range-scaled RMSE), not this chi-square. Where the chi-square's own least-squares
//!   point on the linear residuals `r0 + J (theta - theta0)` lies outside the 95 % posterior,
//!   the report says so (the two objectives weigh the recordings differently). Where the
//!   predictions bend strongly over the posterior's width, the samples are approximate.
//! - **Posterior.** Likelihood `exp(-chi^2 / (2 s^2))` with `s^2 = max(1, chi^2(theta0) /
//!   (n - p))` (the recorded uncertainties widened by the reduced chi-square, as the
//!   linearised intervals widen them); prior uniform over the search box. Unlike the
//!   linearised intervals, the samples respect the box: a constant near a bound gets a
//!   one-sided interval.
//! - **Sampler.** Random-walk Metropolis (Metropolis et al., J. Chem. Phys. 21 (1953) 1087) in
//!   coordinates scaled by each constant's search range; Gaussian proposals with covariance
//!   `2.38^2 / p` times the Gauss-Newton covariance (Gelman, Roberts & Gilks, Bayesian
//!   Statistics 5 (1996) 599), regularised so that no direction is wider than the box; four
//!   chains started one proposal width apart around the selected point, [`BURN_IN`] steps
//!   dropped and every [`THIN`]th of [`STEPS`] kept; Gelman & Rubin's potential scale
//!   reduction `R-hat` (Stat. Sci. 7 (1992) 457) per constant. Seeded from the campaign's
//!   seed: the same samples on every machine and thread count.
//! - **Prediction band.** `m(theta) = m0 + S (theta - theta0)` at every recorded point (`S`
//!   the prediction slopes), its 2.5 and 97.5 percentiles over the samples: the band of the
//!   model's prediction given the recordings, without the recording noise itself.

use super::campaign::Campaign;
use super::uncertainty::Linearisation;
use super::ModelSpace;
use crate::random::SplitMix64;
use serde::{Deserialize, Serialize};

/// Chains run.
pub const CHAINS: usize = 4;
/// Steps dropped at the start of each chain.
pub const BURN_IN: usize = 2_000;
/// Steps of each chain after the burn-in.
pub const STEPS: usize = 20_000;
/// Every `THIN`th step is kept.
pub const THIN: usize = 20;

/// The sampled posterior of a model's constants and the prediction bands it gives.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Posterior {
    /// Samples kept (all chains).
    pub samples: usize,
    /// Chains run.
    pub chains: usize,
    /// Share of proposals accepted.
    pub acceptance: f64,
    /// `s^2`: the factor the recorded uncertainties' variances were widened by.
    pub scale: f64,
    /// Median of each constant (SI), in the model space's order.
    pub median: Vec<f64>,
    /// 2.5 percentile of each constant.
    pub lower_95: Vec<f64>,
    /// 97.5 percentile of each constant.
    pub upper_95: Vec<f64>,
    /// Correlation matrix of the samples.
    pub correlation: Vec<Vec<f64>>,
    /// The least-squares point of the linear residuals `r0 + J (theta - theta0)` (SI; the
    /// chi-square's own optimum by the surrogate, unbounded).
    pub least_squares: Vec<f64>,
    /// Gelman-Rubin potential scale reduction of each constant (near 1: the chains agree).
    pub r_hat: Vec<f64>,
    /// The prediction band of each campaign experiment (`None`: not linearised).
    pub bands: Vec<Option<PredictionBand>>,
}

/// The prediction band at an experiment's recorded points (SI).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PredictionBand {
    /// The prediction at the selected constants.
    pub predicted: Vec<f64>,
    /// Its 2.5 percentile over the posterior.
    pub lower: Vec<f64>,
    /// Its 97.5 percentile over the posterior.
    pub upper: Vec<f64>,
}

impl PredictionBand {
    /// The band's mean half-width relative to the recorded values (`|recorded|`; points
    /// recorded at 0 left out); `None` without such points.
    pub fn relative_half_width(&self, recorded: &[f64]) -> Option<f64> {
        let widths: Vec<f64> = recorded
            .iter()
            .zip(self.lower.iter().zip(&self.upper))
            .filter(|(y, _)| **y != 0.0)
            .map(|(y, (lo, hi))| 0.5 * (hi - lo) / y.abs())
            .collect();
        (!widths.is_empty()).then(|| widths.iter().sum::<f64>() / widths.len() as f64)
    }
}

impl Posterior {
    /// The mean relative half-width of the prediction bands ([`PredictionBand::
    /// relative_half_width`]) over `campaign`'s fitted and over its held-out experiments
    /// (each `None` without a band there).
    pub fn band_widths(&self, campaign: &Campaign) -> (Option<f64>, Option<f64>) {
        let mean = |held_out: bool| {
            let widths: Vec<f64> = self
                .bands
                .iter()
                .enumerate()
                .filter(|(i, _)| {
                    campaign
                        .file
                        .experiments
                        .get(*i)
                        .is_some_and(|e| e.holdout == held_out)
                })
                .filter_map(|(i, band)| {
                    let recorded: Vec<f64> = campaign.experiments[i]
                        .recording
                        .iter()
                        .map(|p| p.value)
                        .collect();
                    band.as_ref()?.relative_half_width(&recorded)
                })
                .collect();
            (!widths.is_empty()).then(|| widths.iter().sum::<f64>() / widths.len() as f64)
        };
        (mean(false), mean(true))
    }
}

/// Sample the posterior of `linearisation`'s constants (those of `space`) given the
/// recordings of `fitted`, and the prediction band of every linearised experiment.
pub fn sample(
    campaign: &Campaign,
    space: &ModelSpace,
    linearisation: &Linearisation,
    fitted: &[usize],
    seed: u64,
) -> Result<Posterior, String> {
    let theta0 = &linearisation.values;
    let p = theta0.len();
    let (r0, jacobian) = linearisation.residuals(campaign, fitted)?;
    let draws = draw(
        &r0,
        &jacobian,
        theta0,
        (&space.lower[..p], &space.upper[..p]),
        seed,
    )?;
    let Draws {
        samples,
        acceptance,
        r_hat,
        scale,
        least_squares,
    } = draws;
    let percentile = |values: &mut Vec<f64>, q: f64| {
        values.sort_by(f64::total_cmp);
        let at = q * (values.len() - 1) as f64;
        let (k, t) = (libm::floor(at) as usize, at - libm::floor(at));
        values[k] + t * (values[(k + 1).min(values.len() - 1)] - values[k])
    };
    let column = |i: usize| samples.iter().map(|s| s[i]).collect::<Vec<f64>>();
    let median = (0..p).map(|i| percentile(&mut column(i), 0.5)).collect();
    let lower_95 = (0..p).map(|i| percentile(&mut column(i), 0.025)).collect();
    let upper_95 = (0..p).map(|i| percentile(&mut column(i), 0.975)).collect();
    let correlation = correlation_matrix(&samples, p);
    let bands = linearisation
        .predictions
        .iter()
        .zip(&linearisation.slopes)
        .map(|(predicted, slopes)| {
            let (predicted, slopes) = (predicted.as_ref()?, slopes.as_ref()?);
            let mut lower = Vec::with_capacity(predicted.len());
            let mut upper = Vec::with_capacity(predicted.len());
            for (m0, slope) in predicted.iter().zip(slopes) {
                let mut values: Vec<f64> = samples
                    .iter()
                    .map(|s| m0 + (0..p).map(|i| slope[i] * (s[i] - theta0[i])).sum::<f64>())
                    .collect();
                lower.push(percentile(&mut values, 0.025));
                upper.push(percentile(&mut values, 0.975));
            }
            Some(PredictionBand {
                predicted: predicted.clone(),
                lower,
                upper,
            })
        })
        .collect();
    Ok(Posterior {
        samples: samples.len(),
        chains: CHAINS,
        acceptance,
        scale,
        median,
        lower_95,
        upper_95,
        correlation,
        least_squares,
        r_hat,
        bands,
    })
}

/// What the sampler returns: the kept samples (SI constants), the acceptance, each
/// constant's `R-hat` and the likelihood's `s^2`.
struct Draws {
    samples: Vec<Vec<f64>>,
    acceptance: f64,
    r_hat: Vec<f64>,
    scale: f64,
    least_squares: Vec<f64>,
}

/// Sample `exp(-(chi^2(theta0) + dz.A.dz) / (2 s^2))` over the box `lower..=upper`, `A =
/// J^T J` (module documentation: the surrogate and the sampler).
fn draw(
    r0: &[f64],
    jacobian: &[Vec<f64>],
    theta0: &[f64],
    (lower_bound, upper_bound): (&[f64], &[f64]),
    seed: u64,
) -> Result<Draws, String> {
    let p = theta0.len();
    if p == 0 {
        return Err("no constant to sample".into());
    }
    let ranges: Vec<f64> = (0..p).map(|i| upper_bound[i] - lower_bound[i]).collect();
    let n = r0.len();
    if n <= p {
        return Err(format!("{n} recorded points for {p} constants"));
    }
    // In scaled coordinates z_i = (theta_i - theta0_i) / range_i: the curvature A = J^T J and
    // the gradient b = J^T r0 (the latter only for the least-squares point).
    let mut a = vec![vec![0.0; p]; p];
    let mut b = vec![0.0; p];
    for (row, r) in jacobian.iter().zip(r0) {
        for i in 0..p {
            let ji = row[i] * ranges[i];
            b[i] += ji * r;
            for k in 0..p {
                a[i][k] += ji * row[k] * ranges[k];
            }
        }
    }
    let c: f64 = r0.iter().map(|r| r * r).sum();
    let scale = (c / (n - p) as f64).max(1.0);
    // The linear residuals' least-squares point, z = -A^-1 b (A regularised by 1e-12 of its
    // largest diagonal entry where singular).
    let largest = (0..p).map(|i| a[i][i]).fold(0.0, f64::max);
    let mut nudged = a.clone();
    for (i, row) in nudged.iter_mut().enumerate() {
        row[i] += 1e-12 * largest.max(f64::MIN_POSITIVE);
    }
    let least_squares = super::uncertainty::invert(&nudged).map_or_else(
        || theta0.to_vec(),
        |inverse| {
            (0..p)
                .map(|i| theta0[i] - ranges[i] * (0..p).map(|k| inverse[i][k] * b[k]).sum::<f64>())
                .collect()
        },
    );
    let chi_square = |z: &[f64]| {
        let mut total = c;
        for i in 0..p {
            for k in 0..p {
                total += z[i] * a[i][k] * z[k];
            }
        }
        total
    };
    let lower: Vec<f64> = (0..p)
        .map(|i| (lower_bound[i] - theta0[i]) / ranges[i])
        .collect();
    let upper: Vec<f64> = (0..p)
        .map(|i| (upper_bound[i] - theta0[i]) / ranges[i])
        .collect();
    let inside = |z: &[f64]| (0..p).all(|i| z[i] >= lower[i] && z[i] <= upper[i]);
    let log_target = |z: &[f64]| {
        if inside(z) {
            -0.5 * chi_square(z) / scale
        } else {
            f64::NEG_INFINITY
        }
    };
    // Proposal: (2.38^2 / p) s^2 (A + s^2 I)^-1: the Gauss-Newton covariance, no direction
    // wider than the box (the s^2 I term is a unit-width prior on the proposal only).
    let mut regularised = a.clone();
    for (i, row) in regularised.iter_mut().enumerate() {
        row[i] += scale;
    }
    let covariance = super::uncertainty::invert(&regularised)
        .ok_or("the normal matrix could not be inverted")?;
    let factor = 2.38 * 2.38 / p as f64 * scale;
    let proposal = cholesky(
        &covariance
            .iter()
            .map(|row| row.iter().map(|v| v * factor).collect())
            .collect::<Vec<Vec<f64>>>(),
    )
    .ok_or("the proposal covariance is not positive definite")?;
    let step = |rng: &mut SplitMix64, z: &[f64]| -> Vec<f64> {
        let xi: Vec<f64> = (0..p).map(|_| rng.normal()).collect();
        (0..p)
            .map(|i| z[i] + (0..=i).map(|k| proposal[i][k] * xi[k]).sum::<f64>())
            .collect()
    };
    let mut chains: Vec<Vec<Vec<f64>>> = Vec::with_capacity(CHAINS);
    let mut accepted = 0usize;
    for chain in 0..CHAINS {
        let mut rng = SplitMix64::new(seed ^ (0x5EED_0000_0000_0000 + chain as u64));
        // Start one proposal width from the selected point (inside the box), so that the
        // chains' agreement means something.
        let mut z = vec![0.0; p];
        for _ in 0..100 {
            let start = step(&mut rng, &vec![0.0; p]);
            if inside(&start) {
                z = start;
                break;
            }
        }
        let mut log_z = log_target(&z);
        let mut kept = Vec::with_capacity(STEPS / THIN);
        for n in 0..BURN_IN + STEPS {
            let candidate = step(&mut rng, &z);
            let log_candidate = log_target(&candidate);
            if log_candidate.is_finite() && libm::log(rng.uniform()) < log_candidate - log_z {
                z = candidate;
                log_z = log_candidate;
                if n >= BURN_IN {
                    accepted += 1;
                }
            }
            if n >= BURN_IN && (n - BURN_IN) % THIN == THIN - 1 {
                kept.push(z.clone());
            }
        }
        chains.push(kept);
    }
    let r_hat = (0..p).map(|i| gelman_rubin(&chains, i)).collect();
    let samples = chains
        .into_iter()
        .flatten()
        .map(|z| (0..p).map(|i| theta0[i] + z[i] * ranges[i]).collect())
        .collect();
    Ok(Draws {
        samples,
        acceptance: accepted as f64 / (CHAINS * STEPS) as f64,
        r_hat,
        scale,
        least_squares,
    })
}

/// Lower-triangular `L` with `L L^T = matrix` (`None` if not positive definite).
fn cholesky(matrix: &[Vec<f64>]) -> Option<Vec<Vec<f64>>> {
    let n = matrix.len();
    let mut l = vec![vec![0.0; n]; n];
    for i in 0..n {
        for k in 0..=i {
            let sum: f64 = (0..k).map(|j| l[i][j] * l[k][j]).sum();
            if i == k {
                let d = matrix[i][i] - sum;
                if d <= 0.0 {
                    return None;
                }
                l[i][i] = libm::sqrt(d);
            } else {
                l[i][k] = (matrix[i][k] - sum) / l[k][k];
            }
        }
    }
    Some(l)
}

/// Gelman & Rubin's potential scale reduction of coordinate `i` over `chains`.
fn gelman_rubin(chains: &[Vec<Vec<f64>>], i: usize) -> f64 {
    let m = chains.len() as f64;
    let n = chains.iter().map(Vec::len).min().unwrap_or(0) as f64;
    if n < 2.0 || m < 2.0 {
        return f64::NAN;
    }
    let means: Vec<f64> = chains
        .iter()
        .map(|c| c.iter().map(|z| z[i]).sum::<f64>() / c.len() as f64)
        .collect();
    let grand = means.iter().sum::<f64>() / m;
    let between = n / (m - 1.0) * means.iter().map(|x| (x - grand) * (x - grand)).sum::<f64>();
    let within = chains
        .iter()
        .zip(&means)
        .map(|(c, mean)| {
            c.iter().map(|z| (z[i] - mean) * (z[i] - mean)).sum::<f64>() / (c.len() as f64 - 1.0)
        })
        .sum::<f64>()
        / m;
    if within <= 0.0 {
        return f64::NAN;
    }
    let pooled = (n - 1.0) / n * within + between / n;
    libm::sqrt(pooled / within)
}

/// The correlation matrix of `samples` (`p` coordinates each).
fn correlation_matrix(samples: &[Vec<f64>], p: usize) -> Vec<Vec<f64>> {
    let count = samples.len().max(1) as f64;
    let means: Vec<f64> = (0..p)
        .map(|i| samples.iter().map(|s| s[i]).sum::<f64>() / count)
        .collect();
    let covariance = |i: usize, k: usize| {
        samples
            .iter()
            .map(|s| (s[i] - means[i]) * (s[k] - means[k]))
            .sum::<f64>()
            / count
    };
    (0..p)
        .map(|i| {
            (0..p)
                .map(|k| {
                    let scale = libm::sqrt(covariance(i, i) * covariance(k, k));
                    if scale > 0.0 {
                        covariance(i, k) / scale
                    } else {
                        0.0
                    }
                })
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Mean and standard deviation of coordinate `i` of `samples`.
    fn moments(samples: &[Vec<f64>], i: usize) -> (f64, f64) {
        let n = samples.len() as f64;
        let mean = samples.iter().map(|s| s[i]).sum::<f64>() / n;
        let variance = samples.iter().map(|s| (s[i] - mean).powi(2)).sum::<f64>() / n;
        (mean, variance.sqrt())
    }

    #[test]
    fn a_linear_gaussian_posterior_is_recovered_and_a_bound_truncates_it() {
        // GOAL: the sampler draws the posterior it claims: on a linear model linearised at
        //       its least-squares point the posterior is Gaussian in closed form; a search
        //       bound at the selected point truncates it to one side; the least-squares point
        //       is found from elsewhere.
        // SETUP: y = a + b x at x = -1, 0, 1 with unit uncertainty, recorded 1, 2, 4;
        //        linearised at the least-squares point (a, b) = (7/3, 3/2), box [-10, 10]^2;
        //        then at (2.5, 3/2) with a >= 2.5.
        // REFERENCE: chi^2 = 1/6 over 1 degree of freedom, so s^2 = 1; var a = 1/3, var b =
        //        1/2, independent: sample means within 0.05 of (7/3, 3/2), standard
        //        deviations within 5 %, R-hat below 1.05, acceptance 15-60 %. At the bound
        //        the mode is the bound (the surrogate's mode is the selected point): a
        //        half-Gaussian, mean 2.5 + sqrt(1/3) sqrt(2/pi) = 2.961, no sample below 2.5;
        //        the least-squares point reported is still (7/3, 3/2).
        let x = [-1.0, 0.0, 1.0];
        let y = [1.0, 2.0, 4.0];
        let residuals =
            |a: f64, b: f64| -> Vec<f64> { x.iter().zip(&y).map(|(x, y)| y - a - b * x).collect() };
        // dr/da = -1, dr/db = -x.
        let jacobian: Vec<Vec<f64>> = x.iter().map(|x| vec![-1.0, -x]).collect();
        let box_ = (&[-10.0, -10.0][..], &[10.0, 10.0][..]);
        let draws = draw(
            &residuals(7.0 / 3.0, 1.5),
            &jacobian,
            &[7.0 / 3.0, 1.5],
            box_,
            7,
        )
        .unwrap();
        assert_eq!(draws.scale, 1.0);
        let (mean_a, sd_a) = moments(&draws.samples, 0);
        let (mean_b, sd_b) = moments(&draws.samples, 1);
        assert!((mean_a - 7.0 / 3.0).abs() < 0.05, "a {mean_a}");
        assert!((mean_b - 1.5).abs() < 0.05, "b {mean_b}");
        assert!(
            (sd_a / (1.0f64 / 3.0).sqrt() - 1.0).abs() < 0.05,
            "sd a {sd_a}"
        );
        assert!((sd_b / 0.5f64.sqrt() - 1.0).abs() < 0.05, "sd b {sd_b}");
        assert!(draws.r_hat.iter().all(|r| *r < 1.05), "{:?}", draws.r_hat);
        assert!(
            (0.15..0.6).contains(&draws.acceptance),
            "{}",
            draws.acceptance
        );
        let bounded = draw(
            &residuals(2.5, 1.5),
            &jacobian,
            &[2.5, 1.5],
            (&[2.5, -10.0], &[10.0, 10.0]),
            7,
        )
        .unwrap();
        let lowest = bounded
            .samples
            .iter()
            .map(|s| s[0])
            .fold(f64::INFINITY, f64::min);
        assert!(lowest >= 2.5, "{lowest}");
        let (mean_bounded, _) = moments(&bounded.samples, 0);
        let half_gaussian = 2.5 + (1.0f64 / 3.0).sqrt() * (2.0 / std::f64::consts::PI).sqrt();
        assert!(
            (mean_bounded - half_gaussian).abs() < 0.03,
            "{mean_bounded}"
        );
        assert!((bounded.least_squares[0] - 7.0 / 3.0).abs() < 1e-9);
        assert!((bounded.least_squares[1] - 1.5).abs() < 1e-9);
    }
}

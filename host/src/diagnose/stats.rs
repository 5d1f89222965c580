//! The statistics of the diagnosis: normal and chi-square tail probabilities, the
//! Wald-Wolfowitz runs test and lag-1 autocorrelation (the small dense least squares are
//! [`crate::fit::linear`]).
//! Transcendental functions come from `libm`, so results are the same on every platform.

/// Upper tail of the standard normal distribution, `P(Z > z) = erfc(z / sqrt 2) / 2`.
pub fn normal_upper_tail(z: f64) -> f64 {
    0.5 * libm::erfc(z / core::f64::consts::SQRT_2)
}

/// Upper tail of the chi-square distribution with `dof` degrees of freedom, `P(X > x)`: the
/// regularised upper incomplete gamma function `Q(dof/2, x/2)` (series for `x < a + 1`,
/// Lentz continued fraction otherwise; Abramowitz & Stegun 6.5.29 and 6.5.31).
pub fn chi_square_upper_tail(x: f64, dof: f64) -> f64 {
    if x.is_nan() || dof <= 0.0 {
        return f64::NAN;
    }
    if x <= 0.0 {
        return 1.0;
    }
    let a = 0.5 * dof;
    let x = 0.5 * x;
    let log_prefactor = a * libm::log(x) - x - libm::lgamma(a);
    if x < a + 1.0 {
        // P(a, x) = x^a e^-x / Gamma(a) * sum_k x^k / (a (a+1) ... (a+k)).
        let mut term = 1.0 / a;
        let mut sum = term;
        let mut denominator = a;
        for _ in 0..1000 {
            denominator += 1.0;
            term *= x / denominator;
            sum += term;
            if term.abs() < sum.abs() * 1e-16 {
                break;
            }
        }
        (1.0 - sum * libm::exp(log_prefactor)).clamp(0.0, 1.0)
    } else {
        // Q(a, x) = x^a e^-x / Gamma(a) * 1 / (x + 1 - a - 1 (1 - a) / (x + 3 - a - ...)).
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut fraction = d;
        for i in 1..1000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let delta = d * c;
            fraction *= delta;
            if (delta - 1.0).abs() < 1e-16 {
                break;
            }
        }
        (libm::exp(log_prefactor) * fraction).clamp(0.0, 1.0)
    }
}

/// The Wald-Wolfowitz runs test on the signs of a residual series: too few runs means the
/// residuals come in blocks of one sign (structure), not noise.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RunsTest {
    /// Runs of equal sign observed.
    pub runs: usize,
    /// Runs expected under independence, `2 n+ n- / n + 1`.
    pub expected: f64,
    /// One-sided p-value of as few runs or fewer (normal approximation); 1 when undefined.
    pub p_value: f64,
}

/// Runs test of `residuals` (zeros count as positive).
pub fn runs_test(residuals: &[f64]) -> RunsTest {
    let positive = residuals.iter().filter(|r| **r >= 0.0).count() as f64;
    let negative = residuals.len() as f64 - positive;
    let n = positive + negative;
    let runs = if residuals.is_empty() {
        0
    } else {
        1 + residuals
            .windows(2)
            .filter(|w| (w[0] >= 0.0) != (w[1] >= 0.0))
            .count()
    };
    if positive == 0.0 || negative == 0.0 {
        // One sign throughout: as structured as a series can be; p = 2^-(n-1) (every sign
        // equal to the first).
        let p_value = if n >= 2.0 {
            libm::pow(0.5, n - 1.0)
        } else {
            1.0
        };
        return RunsTest {
            runs,
            expected: 1.0,
            p_value,
        };
    }
    let expected = 2.0 * positive * negative / n + 1.0;
    let variance = (expected - 1.0) * (expected - 2.0) / (n - 1.0);
    let p_value = if variance > 0.0 {
        1.0 - normal_upper_tail((runs as f64 - expected) / libm::sqrt(variance))
    } else {
        1.0
    };
    RunsTest {
        runs,
        expected,
        p_value,
    }
}

/// Lag-1 autocorrelation `sum r_i r_(i+1) / sum r_i^2` of whitened residuals (zero mean
/// under the null).
pub fn lag1_autocorrelation(residuals: &[f64]) -> f64 {
    let energy: f64 = residuals.iter().map(|r| r * r).sum();
    if energy == 0.0 || residuals.len() < 2 {
        return 0.0;
    }
    residuals.windows(2).map(|w| w[0] * w[1]).sum::<f64>() / energy
}

/// The noise model of one recording's whitened residuals, estimated from what a fit leaves:
/// a first-order autoregression `e_i = rho e_(i-1) + u_i` with stationary variance `variance`
/// (in units of the recorded uncertainty squared).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ar1 {
    /// Stationary variance, at least 1 (the recorded uncertainty is a floor).
    pub variance: f64,
    /// Lag-1 correlation, in `[0, MAX_CORRELATION]`.
    pub correlation: f64,
}

/// Largest lag-1 correlation an [`Ar1`] estimate takes (at 0.98 the variance of a smooth
/// sum is inflated by `(1 + rho)/(1 - rho)` ~ 99; beyond, one recording would stand for one
/// number whatever its length).
pub const MAX_CORRELATION: f64 = 0.98;

impl Ar1 {
    /// Moment estimate from the residuals `e` of one recording, in recording order:
    /// `variance = max(1, inflation sum e^2 / n)` (`inflation = n_total / (n_total - k)` for
    /// the `k` constants fitted over all recordings), `rho` = lag-1 autocorrelation clamped
    /// to `[0, MAX_CORRELATION]`. A negative estimate is taken as 0: alternating residuals
    /// would otherwise shrink the variance of a smooth sum and make a test more liberal.
    /// Fewer than three residuals give `rho = 0`.
    pub fn estimate(residuals: &[f64], inflation: f64) -> Self {
        let n = residuals.len();
        if n == 0 {
            return Self {
                variance: 1.0,
                correlation: 0.0,
            };
        }
        let energy: f64 = residuals.iter().map(|e| e * e).sum();
        let variance = (inflation * energy / n as f64).max(1.0);
        let correlation = if n < 3 {
            0.0
        } else {
            lag1_autocorrelation(residuals).clamp(0.0, MAX_CORRELATION)
        };
        Self {
            variance,
            correlation,
        }
    }

    /// `Var(z' e) = variance sum_ij z_i z_j rho^|i-j|` for weights `z` on this recording's
    /// residuals, in O(n) (`a_i = z_i + rho a_(i-1)`, the sum is `2 z'a - z'z`).
    pub fn variance_of_sum(&self, weights: &[f64]) -> f64 {
        let rho = self.correlation;
        let mut carried = 0.0;
        let mut cross = 0.0;
        let mut square = 0.0;
        for z in weights {
            carried = z + rho * carried;
            cross += z * carried;
            square += z * z;
        }
        self.variance * (2.0 * cross - square).max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::linear::dot;

    #[test]
    fn tail_probabilities_match_tables() {
        // GOAL: the p-values the diagnosis reports. SETUP: textbook quantiles.
        // REFERENCE: P(Z > 1.959964) = 0.025; chi2(1) 3.841459 -> 0.05; chi2(10) 18.307038
        // -> 0.05; chi2(2) x -> exp(-x/2) exactly; chi2(30) 50.892181 -> 0.01.
        assert!((normal_upper_tail(1.959_964) - 0.025).abs() < 1e-7);
        assert!((chi_square_upper_tail(3.841_459, 1.0) - 0.05).abs() < 1e-7);
        assert!((chi_square_upper_tail(18.307_038, 10.0) - 0.05).abs() < 1e-7);
        assert!((chi_square_upper_tail(50.892_181, 30.0) - 0.01).abs() < 1e-7);
        for x in [0.1, 1.0, 3.0, 10.0, 40.0] {
            let exact = libm::exp(-0.5 * x);
            assert!((chi_square_upper_tail(x, 2.0) - exact).abs() < 1e-14 * exact.max(1e-3));
        }
    }

    #[test]
    fn runs_test_separates_blocks_from_alternation() {
        // GOAL: structure (blocks of one sign) is flagged, alternation is not.
        // SETUP: 10 positives then 10 negatives; strict alternation.
        // REFERENCE: 2 runs (expected 11, z = -4.13, p ~ 2e-5); 20 runs (p ~ 1).
        let blocks: Vec<f64> = (0..20).map(|i| if i < 10 { 1.0 } else { -1.0 }).collect();
        let test = runs_test(&blocks);
        assert_eq!(test.runs, 2);
        assert!((test.expected - 11.0).abs() < 1e-12);
        assert!(test.p_value < 1e-4, "{test:?}");
        let alternating: Vec<f64> = (0..20)
            .map(|i| if i % 2 == 0 { 1.0 } else { -1.0 })
            .collect();
        assert!(runs_test(&alternating).p_value > 0.99);
        assert!((lag1_autocorrelation(&alternating) + 0.95).abs() < 1e-12);
    }

    #[test]
    fn an_ar1_variance_keeps_a_test_on_correlated_noise_at_its_level() {
        // GOAL: the score test's variance for residuals correlated within a recording (issue
        //       15: lag-1 autocorrelation ~0.9 made unrelated terms look significant).
        // SETUP: 2000 recordings of 200 points of AR(1) noise, rho 0.9, stationary standard
        //        deviation 3 (three times the recorded uncertainty, so that the variance
        //        floor of 1 does not make the test conservative); a smooth unrelated column z
        //        (a ramp); the statistic
        //        (z'e)^2 / Var(z'e) with the variance of Ar1::estimate from e itself, against
        //        the independent-residual statistic (z'e)^2 / (s^2 z'z).
        // REFERENCE: under the null, P(chi2(1) > 3.841) = 5 %: the AR(1) test rejects 2-8 % (3.1 % measured);
        //            the independent one far more (its variance is ~19 times too small).
        let mut rng = crate::random::SplitMix64::new(15);
        let (n, trials, rho) = (200, 2000, 0.9_f64);
        let ramp: Vec<f64> = (0..n).map(|i| i as f64 / n as f64 - 0.5).collect();
        let (mut ar1_rejections, mut independent_rejections) = (0, 0);
        for _ in 0..trials {
            let mut e = Vec::with_capacity(n);
            let mut previous = rng.normal();
            for _ in 0..n {
                e.push(3.0 * previous);
                previous = rho * previous + libm::sqrt(1.0 - rho * rho) * rng.normal();
            }
            let projection = dot(&ramp, &e);
            let model = Ar1::estimate(&e, 1.0);
            if projection * projection / model.variance_of_sum(&ramp) > 3.841_459 {
                ar1_rejections += 1;
            }
            if projection * projection / (model.variance * dot(&ramp, &ramp)) > 3.841_459 {
                independent_rejections += 1;
            }
        }
        let ar1 = f64::from(ar1_rejections) / trials as f64;
        let independent = f64::from(independent_rejections) / trials as f64;
        assert!((0.02..=0.08).contains(&ar1), "AR(1) test rejects {ar1}");
        assert!(independent > 0.4, "independent test rejects {independent}");
    }

    #[test]
    fn an_ar1_variance_of_white_residuals_is_the_independent_one() {
        // GOAL: with uncorrelated residuals the AR(1) variance reduces to s^2 z'z.
        // SETUP: alternating residuals (negative lag-1 correlation, clamped to 0), z arbitrary.
        // REFERENCE: variance_of_sum = s^2 z'z with s^2 = max(1, mean e^2).
        let e: Vec<f64> = (0..10)
            .map(|i| if i % 2 == 0 { 2.0 } else { -2.0 })
            .collect();
        let model = Ar1::estimate(&e, 1.0);
        assert_eq!(model.correlation, 0.0);
        assert!((model.variance - 4.0).abs() < 1e-12);
        let z = [0.3, -1.0, 2.0, 0.5, 0.0, 1.5, -0.7, 0.2, 0.9, -2.0];
        let expected = 4.0 * dot(&z, &z);
        assert!((model.variance_of_sum(&z) - expected).abs() < 1e-12 * expected);
    }
}

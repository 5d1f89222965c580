//! Multi-fidelity calibration (docs/calibration.md, "Multi-fidelity"): most of the search's
//! candidates simulate the costly experiments on a coarse mesh, one in `fine_every` also on
//! the fine one, and the difference learned from those pairs corrects the coarse predictions,
//! so that the optimiser sees a model of the fine simulation.
//!
//! The correction is the autoregressive model of Kennedy & O'Hagan (Biometrika 87, 2000),
//! `y_fine(x) = rho y_coarse(x) + delta(x)`, per recorded point: the pairs' mean difference
//! at first; from [`SCALE_PAIRS`] pairs on, also the scale `rho` (the difference regressed on
//! the coarse prediction: a coarse mesh that penetrates 10 % short is 10 % short of a deep and
//! of a shallow shot alike); from `d + 3` pairs on (`d` the searched constants), also a linear
//! trend of `delta` in the unit cube of the constants. The slopes are fitted by ridge-damped
//! least squares. What is left out against full co-kriging: the Gaussian-process residual of
//! `delta` (the correction is a regression, not an interpolant of the pairs).

use super::linear::{gram, solve_damped, transpose_times};
use super::objective::point_scales;
use crate::input::recording::RecordedPoint;
use serde::{Deserialize, Serialize};

/// Which mesh a simulation ran on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Fidelity {
    /// Every experiment as its file gives it.
    #[default]
    Fine,
    /// The experiments with a campaign `coarse` factor on their coarse mesh, the others as
    /// their files give them.
    Coarse,
}

impl Fidelity {
    /// Whether this is the fine fidelity (the files as written).
    pub fn is_fine(&self) -> bool {
        *self == Fidelity::Fine
    }
}

/// Pairs from which the correction has a scale `rho` (the difference's dependence on the
/// coarse prediction itself): with two, a slope through two noisy pairs would be fitted exactly.
pub const SCALE_PAIRS: usize = 3;

/// Ridge damping of the trend's normal equations (relative to their diagonal): a pair more or
/// less moves a slope the pairs barely determine only a little.
const RIDGE: f64 = 0.02;

/// The coarse and fine predictions of one experiment at one candidate.
#[derive(Clone, Debug, PartialEq)]
struct Pair {
    unit: Vec<f64>,
    coarse: Vec<f64>,
    difference: Vec<f64>,
}

/// How well the correction predicted one fine check before it learned from it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CheckRecord {
    /// The experiment (its campaign file entry).
    pub experiment: String,
    /// Pairs the correction had learned from.
    pub pairs_before: usize,
    /// RMS over the recorded points of `(coarse - fine) / scale`, each point scaled as its
    /// error is (`objective::error_scales`).
    pub coarse_error: f64,
    /// The same of the corrected coarse prediction.
    pub corrected_error: f64,
}

/// The learned correction of every experiment that has a coarse fidelity.
#[derive(Clone, Debug, Default)]
pub struct Correction {
    /// Per campaign experiment: its pairs (empty for an experiment without a coarse mesh).
    pairs: Vec<Vec<Pair>>,
}

impl Correction {
    /// An empty correction for a campaign of `experiments` experiments.
    pub fn new(experiments: usize) -> Self {
        Self {
            pairs: vec![Vec::new(); experiments],
        }
    }

    /// Pairs learned for `experiment`.
    pub fn pairs(&self, experiment: usize) -> usize {
        self.pairs.get(experiment).map_or(0, Vec::len)
    }

    /// Learn from the coarse and fine predictions of `experiment` at the candidate `unit`
    /// (unit-cube coordinates). Predictions of a different length than the pairs learned
    /// before are not learned from.
    pub fn learn(&mut self, experiment: usize, unit: &[f64], coarse: &[f64], fine: &[f64]) {
        let Some(pairs) = self.pairs.get_mut(experiment) else {
            return;
        };
        if coarse.len() != fine.len()
            || pairs
                .first()
                .is_some_and(|p| p.difference.len() != coarse.len() || p.unit.len() != unit.len())
        {
            return;
        }
        pairs.push(Pair {
            unit: unit.to_vec(),
            coarse: coarse.to_vec(),
            difference: fine.iter().zip(coarse).map(|(f, c)| f - c).collect(),
        });
    }

    /// The coarse predictions of `experiment` at `unit`, corrected: `coarse + delta`;
    /// unchanged while no pair is learned. Per recorded point, `delta` is the pairs' mean
    /// difference, plus (from [`SCALE_PAIRS`] pairs) a term in the coarse prediction itself,
    /// `(rho - 1) (y_coarse - mean)`, plus (from `d + 3` pairs, `d` the constants) a linear
    /// trend in the unit cube, the slopes fitted to the pairs by ridge-damped least squares.
    pub fn correct(&self, experiment: usize, unit: &[f64], coarse: &[f64]) -> Vec<f64> {
        let pairs = match self.pairs.get(experiment) {
            Some(pairs) if !pairs.is_empty() && pairs[0].difference.len() == coarse.len() => pairs,
            _ => return coarse.to_vec(),
        };
        let n = pairs.len();
        let dimension = unit.len();
        let mean_of = |f: &dyn Fn(&Pair) -> f64| pairs.iter().map(f).sum::<f64>() / n as f64;
        let unit_mean: Vec<f64> = (0..dimension).map(|k| mean_of(&|p| p.unit[k])).collect();
        let with_scale = n >= SCALE_PAIRS;
        let with_trend = n > dimension + 2;
        coarse
            .iter()
            .enumerate()
            .map(|(j, c)| {
                let mean = mean_of(&|p| p.difference[j]);
                if !with_scale {
                    return c + mean;
                }
                let coarse_mean = mean_of(&|p| p.coarse[j]);
                // Columns: the pairs' centred coarse predictions, then (with the trend) their
                // centred unit coordinates; the point to correct in the same coordinates.
                let mut columns = vec![pairs.iter().map(|p| p.coarse[j] - coarse_mean).collect()];
                let mut at = vec![c - coarse_mean];
                if with_trend {
                    for k in 0..dimension {
                        columns.push(pairs.iter().map(|p| p.unit[k] - unit_mean[k]).collect());
                        at.push(unit[k] - unit_mean[k]);
                    }
                }
                let centred: Vec<f64> = pairs.iter().map(|p| p.difference[j] - mean).collect();
                let slopes =
                    solve_damped(&gram(&columns), &transpose_times(&columns, &centred), RIDGE);
                let along: f64 =
                    slopes.map_or(0.0, |b| b.iter().zip(&at).map(|(b, x)| b * x).sum());
                c + mean + along
            })
            .collect()
    }

    /// How far the coarse and the corrected predictions of `experiment` at `unit` lie from the
    /// fine ones, as [`CheckRecord`] (before learning from them).
    pub fn check(
        &self,
        experiment: usize,
        name: &str,
        recording: &[RecordedPoint],
        unit: &[f64],
        coarse: &[f64],
        fine: &[f64],
    ) -> CheckRecord {
        let corrected = self.correct(experiment, unit, coarse);
        let scales = point_scales(recording);
        let rms = |predicted: &[f64]| {
            let n = recording.len().max(1) as f64;
            let sum: f64 = predicted
                .iter()
                .zip(fine)
                .zip(&scales)
                .map(|((p, f), scale)| ((p - f) / scale).powi(2))
                .sum();
            libm::sqrt(sum / n)
        };
        CheckRecord {
            experiment: name.to_string(),
            pairs_before: self.pairs(experiment),
            coarse_error: rms(coarse),
            corrected_error: rms(&corrected),
        }
    }
}

/// The fine checks and simulations of one optimisation instance's search.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FidelitySummary {
    /// Candidates simulated on the coarse meshes.
    pub coarse: usize,
    /// Of them, also simulated on the fine meshes (the fine checks, the search's best
    /// re-simulated included).
    pub fine_checks: usize,
    /// Each fine check's errors before the correction learned from it, in the order they ran.
    pub checks: Vec<CheckRecord>,
}

impl FidelitySummary {
    /// RMS over the checks that had at least one pair to learn from of the coarse and the
    /// corrected errors, and their count.
    pub fn accuracy(&self) -> Option<(f64, f64, usize)> {
        let learned: Vec<&CheckRecord> =
            self.checks.iter().filter(|c| c.pairs_before > 0).collect();
        if learned.is_empty() {
            return None;
        }
        let n = learned.len() as f64;
        let rms = |f: fn(&CheckRecord) -> f64| {
            libm::sqrt(learned.iter().map(|c| f(c) * f(c)).sum::<f64>() / n)
        };
        Some((
            rms(|c| c.coarse_error),
            rms(|c| c.corrected_error),
            learned.len(),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(value: f64) -> RecordedPoint {
        RecordedPoint {
            quantity: "depth".into(),
            position: 0.0,
            value,
            uncertainty: 0.001,
        }
    }

    #[test]
    fn a_constant_offset_is_learned_from_one_pair_and_a_linear_one_from_enough() {
        // GOAL: the correction reproduces a fine model that is the coarse one plus an
        //       offset (one pair suffices) or plus a linear function of the constants (the
        //       trend, once the pairs determine it).
        // SETUP: two constants; coarse(u) = (u0^2, u0 u1); fine = coarse + 0.3 (one pair),
        //        1.1 coarse + 0.05 (three pairs: the scale) or coarse + 0.3 + 0.2 u0 - 0.1 u1
        //        (five pairs: the trend), pairs at scattered points.
        // REFERENCE: the exact fine values; the ridge damping shrinks the slope a little, so
        //            the trend case is held within 10 % of the span of the differences over
        //            the pairs (0.13).
        let coarse = |u: &[f64]| vec![u[0] * u[0], u[0] * u[1]];
        let mut constant = Correction::new(1);
        constant.learn(0, &[0.2, 0.7], &coarse(&[0.2, 0.7]), &[0.34, 0.44]);
        let at = [0.9, 0.1];
        let corrected = constant.correct(0, &at, &coarse(&at));
        assert!((corrected[0] - (0.81 + 0.3)).abs() < 1e-12, "{corrected:?}");
        assert!((corrected[1] - (0.09 + 0.3)).abs() < 1e-12, "{corrected:?}");

        // A scale: fine = 1.1 coarse + 0.05, learned from three pairs (no trend yet).
        let mut scaled = Correction::new(1);
        for u in [[0.1, 0.2], [0.8, 0.3], [0.5, 0.9]] {
            let c = coarse(&u);
            let f: Vec<f64> = c.iter().map(|c| 1.1 * c + 0.05).collect();
            scaled.learn(0, &u, &c, &f);
        }
        for u in [[0.4, 0.4], [0.95, 0.9]] {
            let corrected = scaled.correct(0, &u, &coarse(&u));
            for (k, c) in coarse(&u).iter().enumerate() {
                let error = corrected[k] - (1.1 * c + 0.05);
                // The ridge keeps about 2 % of the scale's term out: within 1 % of the value.
                assert!(error.abs() < 0.01 * (1.1 * c + 0.05), "{u:?}: {error}");
            }
        }

        let shift = |u: &[f64]| 0.3 + 0.2 * u[0] - 0.1 * u[1];
        let mut linear = Correction::new(1);
        let points = [[0.1, 0.2], [0.8, 0.3], [0.5, 0.9], [0.3, 0.6], [0.7, 0.75]];
        for u in &points {
            let c = coarse(u);
            let f: Vec<f64> = c.iter().map(|c| c + shift(u)).collect();
            linear.learn(0, u, &c, &f);
        }
        let shifts: Vec<f64> = points.iter().map(|u| shift(u)).collect();
        let span = shifts.iter().fold(f64::MIN, |a, &b| a.max(b))
            - shifts.iter().fold(f64::MAX, |a, &b| a.min(b));
        for u in [[0.4, 0.4], [0.15, 0.85], [0.9, 0.1]] {
            let corrected = linear.correct(0, &u, &coarse(&u));
            for (k, c) in coarse(&u).iter().enumerate() {
                let error = corrected[k] - (c + shift(&u));
                assert!(error.abs() <= 0.1 * span, "{u:?}: {error} against {span}");
            }
        }
    }

    #[test]
    fn a_check_measures_the_correction_before_it_learns() {
        // GOAL: the accuracy a report states is that of a prediction, not of a fit to the
        //       same pair.
        // SETUP: a fine model 0.5 above the coarse one on a recording of scale 1 (values 0,
        //        1, 2: range 2); a first check (nothing learned), then a second.
        // REFERENCE: first check: coarse and corrected error both 0.5 / 2 = 0.25; after
        //            learning, the second check's corrected error is 0 and the summary counts
        //            only it.
        let recording = [point(0.0), point(1.0), point(2.0)];
        let coarse = [0.0, 1.0, 2.0];
        let fine = [0.5, 1.5, 2.5];
        let mut correction = Correction::new(1);
        let first = correction.check(0, "a", &recording, &[0.5], &coarse, &fine);
        assert_eq!(first.pairs_before, 0);
        assert!((first.coarse_error - 0.25).abs() < 1e-12);
        assert!((first.corrected_error - 0.25).abs() < 1e-12);
        correction.learn(0, &[0.5], &coarse, &fine);
        let second = correction.check(0, "a", &recording, &[0.6], &coarse, &fine);
        assert!(second.corrected_error < 1e-12, "{second:?}");
        let summary = FidelitySummary {
            coarse: 2,
            fine_checks: 2,
            checks: vec![first, second],
        };
        let (coarse_rms, corrected_rms, count) = summary.accuracy().unwrap();
        assert_eq!(count, 1);
        assert!((coarse_rms - 0.25).abs() < 1e-12 && corrected_rms < 1e-12);
    }
}

//! Location-consistent acceptance: a term is accepted only if its refit removes misfit where
//! the misfit was located.
//!
//! A term can lower the total misfit (and pass the information criterion and the held-out
//! error) by re-shaping the fit where the model was already fine, while the located misfit,
//! the significant bands of [`super::locate`], stays where it was. Its name would then be the
//! wrong physics said with confidence. The rule compares two shares over the fitted
//! recordings, with `z` the whitened residuals before and after the refit:
//!
//! - the located region's share of the misfit, `c_L = sum_L z_before^2 / sum z_before^2`
//!   (`L`: the points of the significant bands);
//! - its share of the refit's improvement, `s_L = sum_L (z_before^2 - z_after^2) / sum
//!   (z_before^2 - z_after^2)`.
//!
//! A term that improves every point in proportion to its misfit has `s_L = c_L`; one that
//! re-fits the rest and leaves the located misfit alone has `s_L` well below `c_L`. "Mostly
//! elsewhere" is decided from the data, against the noise, not by a fixed share: with
//! `delta_i = z_before,i - z_after,i` the refit's change of point `i`, the drop `z_before^2 -
//! z_after^2 = 2 z_before delta - delta^2` carries the recorded noise through `z_before`, so
//! the statistic `T = drop_L - c_L drop` has the noise variance `4 sum w_i^2 delta_i^2`
//! (`w = 1 - c_L` inside the located region, `-c_L` outside; independent noise). The term is
//! refused when `T` is significantly negative at the diagnosis's level (one-sided normal
//! test), or when it removes no misfit inside the located region at all. A term that brings
//! both regions to the noise floor has `T > 0` whenever the bands carried more misfit per point
//! than the rest (which is how they were found). With no band in a fitted recording there is
//! nothing to compare with and the rule does not apply.

use super::locate::ExperimentMisfit;
use super::stats::normal_upper_tail;
use crate::experiment::Experiment;
use serde::{Deserialize, Serialize};

/// Where a refit removed misfit, against where the misfit was located.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LocationCheck {
    /// Fitted measurement points inside the located bands.
    pub located_points: usize,
    /// Fitted measurement points in all.
    pub points: usize,
    /// The located region's share of the starting model's chi-square, `c_L` (0-1).
    pub misfit_share: f64,
    /// The located region's share of the refit's chi-square drop, `s_L` (may fall outside
    /// 0-1 when one region gets worse).
    pub drop_share: f64,
    /// The refit's chi-square drop over the fitted points.
    pub drop: f64,
    /// One-sided p-value of `T = drop_L - c_L drop` under the recorded noise: how likely a
    /// located share this far below `c_L` is by noise alone (1 when `s_L >= c_L`-ish).
    pub p_value: f64,
    /// Not significantly elsewhere (`p_value` at or above the level) and a positive drop
    /// inside the located region.
    pub consistent: bool,
}

impl LocationCheck {
    /// The check in words, for a refit's reason.
    pub fn describe(&self) -> String {
        if self.consistent {
            format!(
                "{:.0} % of its improvement lies in the located bands, which hold {:.0} % of the misfit",
                100.0 * self.drop_share,
                100.0 * self.misfit_share
            )
        } else {
            format!(
                "its improvement lies mostly elsewhere: {:.0} % of it falls in the located bands, which hold {:.0} % of the misfit ({} of {} points; p = {:.1e} against the noise)",
                100.0 * self.drop_share,
                100.0 * self.misfit_share,
                self.located_points,
                self.points,
                self.p_value
            )
        }
    }
}

/// The located misfit of a round's starting model: which fitted points lie in its significant
/// bands, and their whitened residuals.
#[derive(Clone, Debug)]
pub struct LocatedMisfit {
    /// Per experiment of the campaign: `(inside a band, whitened residual)` per recorded
    /// point; empty for held-out experiments.
    points: Vec<Vec<(bool, f64)>>,
}

impl LocatedMisfit {
    /// The located misfit from the starting model's per-experiment `misfits` (every experiment
    /// of the campaign, in order).
    pub fn new(misfits: &[ExperimentMisfit]) -> Self {
        let points = misfits
            .iter()
            .map(|m| {
                if m.holdout {
                    return Vec::new();
                }
                m.residuals
                    .iter()
                    .enumerate()
                    .map(|(i, r)| (m.bands.iter().any(|b| b.members.contains(&i)), r.whitened))
                    .collect()
            })
            .collect();
        Self { points }
    }

    /// Whether any fitted point lies in a band (otherwise the rule does not apply).
    pub fn is_located(&self) -> bool {
        self.points.iter().flatten().any(|(inside, _)| *inside)
    }

    /// Compare where the refit's predictions `after` (every experiment) remove misfit with
    /// the located region at significance level `alpha`; `None` when nothing is located or
    /// the predictions do not cover the recordings.
    pub fn check(
        &self,
        experiments: &[Experiment],
        after: &[Vec<f64>],
        alpha: f64,
    ) -> Option<LocationCheck> {
        if !self.is_located() || after.len() != experiments.len() {
            return None;
        }
        let mut compared: Vec<(bool, f64, f64)> = Vec::new();
        for ((points_before, experiment), predicted) in
            self.points.iter().zip(experiments).zip(after)
        {
            if points_before.is_empty() {
                continue;
            }
            if predicted.len() != experiment.recording.len()
                || points_before.len() != predicted.len()
            {
                return None;
            }
            for ((inside, z_before), (point, p)) in points_before
                .iter()
                .zip(experiment.recording.iter().zip(predicted))
            {
                compared.push((*inside, *z_before, (p - point.value) / point.uncertainty));
            }
        }
        compare(&compared, alpha)
    }
}

/// The rule on `(inside the located region, z before, z after)` per fitted point, at level
/// `alpha`.
fn compare(points: &[(bool, f64, f64)], alpha: f64) -> Option<LocationCheck> {
    let (mut located_points, mut misfit_inside, mut misfit_all) = (0, 0.0, 0.0);
    let (mut drop_inside, mut drop_all) = (0.0, 0.0);
    for &(inside, z_before, z_after) in points {
        let before = z_before * z_before;
        let drop = before - z_after * z_after;
        misfit_all += before;
        drop_all += drop;
        if inside {
            located_points += 1;
            misfit_inside += before;
            drop_inside += drop;
        }
    }
    if located_points == 0 || !(misfit_all > 0.0 && drop_all.is_finite()) {
        return None;
    }
    let misfit_share = misfit_inside / misfit_all;
    let drop_share = if drop_all > 0.0 {
        drop_inside / drop_all
    } else {
        0.0
    };
    // T = drop_L - c_L drop and its noise variance 4 sum w^2 delta^2.
    let statistic = drop_inside - misfit_share * drop_all;
    let variance: f64 = points
        .iter()
        .map(|&(inside, z_before, z_after)| {
            let w = if inside {
                1.0 - misfit_share
            } else {
                -misfit_share
            };
            let delta = z_before - z_after;
            4.0 * w * w * delta * delta
        })
        .sum();
    let p_value = if variance > 0.0 {
        normal_upper_tail(-statistic / libm::sqrt(variance))
    } else {
        1.0
    };
    Some(LocationCheck {
        located_points,
        points: points.len(),
        misfit_share,
        drop_share,
        drop: drop_all,
        p_value,
        consistent: drop_inside > 0.0 && p_value >= alpha,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Located points with z = 3, the others with z = 1 before the refit, `n` of each.
    fn with_after(n: usize, inside_after: f64, outside_after: f64) -> Option<LocationCheck> {
        let points: Vec<(bool, f64, f64)> = (0..n)
            .map(|_| (true, 3.0, inside_after))
            .chain((0..n).map(|_| (false, 1.0, outside_after)))
            .collect();
        compare(&points, 0.01)
    }

    #[test]
    fn the_shares_and_the_noise_statistic_are_those_worked_by_hand() {
        // GOAL: c_L, s_L, the drop and the p-value as defined.
        // SETUP: 2 located points z 3 -> 1, 2 others z 1 -> 0.
        // REFERENCE: c_L = 18/20 = 0.9; drops 8, 8, 1, 1: s_L = 16/18; T = 16 - 0.9 * 18 =
        // -0.2; variance 4 (2 * 0.01 * 4 + 2 * 0.81 * 1) = 6.8; p = Phi(-0.2 / 2.6077) =
        // Phi(-0.0767) = 0.4694 (normal table). Not significant: consistent.
        let check = with_after(2, 1.0, 0.0).expect("located");
        assert!((check.misfit_share - 0.9).abs() < 1e-12);
        assert!((check.drop_share - 16.0 / 18.0).abs() < 1e-12);
        assert!((check.drop - 18.0).abs() < 1e-12);
        assert!((check.p_value - 0.4694).abs() < 1e-3, "{}", check.p_value);
        assert!(check.consistent);
        assert_eq!((check.located_points, check.points), (2, 4));
    }

    #[test]
    fn a_refit_that_helps_only_elsewhere_is_refused() {
        // GOAL: the case the rule exists for: the total misfit drops, the located one barely.
        // SETUP: 20 located points z 3 -> 2.95, 20 others z 1 -> 0.
        // REFERENCE: drop_L = 20 * 0.2975 = 5.95, drop = 25.95, c_L = 0.9: T = 5.95 - 23.355
        // = -17.4, variance 4 (20 * 0.01 * 0.0025 + 20 * 0.81) = 64.8: z = -2.16, p =
        // 0.0153 > 0.01, not yet; with 40 of each z = -3.06, p = 0.0011: refused.
        let twenty = with_after(20, 2.95, 0.0).expect("located");
        assert!(twenty.drop > 0.0 && twenty.drop_share < twenty.misfit_share);
        assert!(twenty.consistent, "p {}", twenty.p_value);
        let forty = with_after(40, 2.95, 0.0).expect("located");
        assert!(forty.p_value < 0.01, "p {}", forty.p_value);
        assert!(!forty.consistent);
        assert!(forty.describe().contains("mostly elsewhere"));
    }

    #[test]
    fn a_term_that_removes_nothing_where_the_misfit_is_is_refused() {
        // GOAL: no improvement inside the located region at all is never consistent.
        // SETUP: the located points get worse (3 -> 3.01), the others improve slightly.
        // REFERENCE: drop_L < 0.
        let check = with_after(2, 3.01, 0.9).expect("located");
        assert!(!check.consistent);
    }

    #[test]
    fn nothing_located_means_the_rule_does_not_apply() {
        // GOAL: without a band there is nothing to compare with.
        // SETUP: no point inside. REFERENCE: None.
        assert!(compare(&[(false, 3.0, 1.0), (false, 1.0, 1.0)], 0.01).is_none());
    }
}

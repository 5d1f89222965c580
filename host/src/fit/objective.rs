//! The error measure and the evaluation of one candidate set of constants.
//!
//! Per experiment (seed 000 sec. 4.1): the RMSE of the scaled residuals,
//! `e = sqrt(mean(((predicted - recorded) / scale_q)^2))`, each point scaled by the scale of
//! its quantity `q` ([`error_scales`]). Seed 000 scales a curve by its measured range
//! (`max - min`) and a one-point recording by its value. stoss keeps the range where it
//! describes a curve and falls back to the quantity's magnitude where it does not: for a
//! quantity with fewer than [`MIN_CURVE_POINTS`] points (a two-point curve has a slope, not a
//! shape) and for one whose range the noise alone could produce (range below
//! [`RESOLVED_RANGE_Z`] standard deviations of the difference of its two extreme points).
//! There a range-scaled error measures noise, not misfit, and blows up (a flat two-point
//! curve scored 22). Quantities are scaled separately, so a recording that holds a time and a
//! displacement does not scale one by the other's range. The campaign error is the weighted
//! sum over the fitted experiments. Reported beside it: the uncertainty-weighted RMS
//! `sqrt(mean(((predicted - recorded) / uncertainty)^2))` (1 = at the noise floor).

use super::campaign::{Campaign, Constraints};
use super::fidelity::Fidelity;
use crate::fit::ModelSpace;
use crate::input::recording::RecordedPoint;
use crate::solver::SolverSettings;
use serde::{Deserialize, Serialize};
use stoss_kernel::Material;

/// The scores of one experiment.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Score {
    /// Min-max-scaled RMSE (seed 000).
    pub error: f64,
    /// Uncertainty-weighted RMS.
    pub chi: f64,
}

/// Fewest points of one quantity for its range to scale its error: a curve with a shape.
pub const MIN_CURVE_POINTS: usize = 3;

/// A quantity's range scales its error only when it exceeds this many standard deviations
/// of the difference of its largest and smallest recorded points (two-sided 95 %): a range
/// the noise cannot produce.
pub const RESOLVED_RANGE_Z: f64 = 1.96;

/// What a quantity's residuals are divided by in the error measure.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ScaleKind {
    /// Its measured range `max - min` (seed 000).
    Range,
    /// Its magnitude, the RMS of its recorded values: a relative error.
    Magnitude,
}

impl ScaleKind {
    /// Why this kind was chosen, in words.
    pub fn reason(self) -> &'static str {
        match self {
            ScaleKind::Range => "range (a resolved curve)",
            ScaleKind::Magnitude => "magnitude (too few points or a range within the noise)",
        }
    }
}

/// The scale of one quantity of a recording.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct QuantityScale {
    /// The quantity's name.
    pub quantity: String,
    /// Its recorded points.
    pub points: usize,
    /// Range or magnitude.
    pub kind: ScaleKind,
    /// The scale (SI, > 0).
    pub value: f64,
}

/// The error scale of each quantity of `recording`, in order of first appearance: its range
/// when it has at least [`MIN_CURVE_POINTS`] points and `max - min > z sqrt(u_max^2 +
/// u_min^2)` with `z` = [`RESOLVED_RANGE_Z`] and `u` the extreme points' uncertainties;
/// otherwise its magnitude `sqrt(mean(value^2))` (a one-point quantity: its value, as in seed
/// 000); the RMS uncertainty if every value is zero.
pub fn error_scales(recording: &[RecordedPoint]) -> Vec<QuantityScale> {
    let mut order: Vec<&str> = Vec::new();
    for p in recording {
        if !order.contains(&p.quantity.as_str()) {
            order.push(&p.quantity);
        }
    }
    order
        .into_iter()
        .map(|quantity| {
            let points: Vec<&RecordedPoint> = recording
                .iter()
                .filter(|p| p.quantity == quantity)
                .collect();
            let n = points.len() as f64;
            let lowest = points
                .iter()
                .min_by(|a, b| a.value.total_cmp(&b.value))
                .expect("a quantity has a point");
            let highest = points
                .iter()
                .max_by(|a, b| a.value.total_cmp(&b.value))
                .expect("a quantity has a point");
            let range = highest.value - lowest.value;
            let noise = libm::sqrt(
                highest.uncertainty * highest.uncertainty + lowest.uncertainty * lowest.uncertainty,
            );
            if points.len() >= MIN_CURVE_POINTS && range > RESOLVED_RANGE_Z * noise {
                return QuantityScale {
                    quantity: quantity.to_string(),
                    points: points.len(),
                    kind: ScaleKind::Range,
                    value: range,
                };
            }
            let rms = |f: fn(&RecordedPoint) -> f64| {
                libm::sqrt(points.iter().map(|p| f(p) * f(p)).sum::<f64>() / n)
            };
            let magnitude = rms(|p| p.value);
            QuantityScale {
                quantity: quantity.to_string(),
                points: points.len(),
                kind: ScaleKind::Magnitude,
                value: if magnitude > 0.0 {
                    magnitude
                } else {
                    rms(|p| p.uncertainty).max(f64::MIN_POSITIVE)
                },
            }
        })
        .collect()
}

/// The scales of a recording in words for a report cell: `range` or `magnitude` for a
/// one-quantity recording, else each quantity's (`final_length: magnitude; diameter: range`).
pub fn describe_scales(scales: &[QuantityScale]) -> String {
    let word = |kind: ScaleKind| match kind {
        ScaleKind::Range => "range",
        ScaleKind::Magnitude => "magnitude",
    };
    match scales {
        [one] => word(one.kind).to_string(),
        many => many
            .iter()
            .map(|s| format!("{}: {}", s.quantity, word(s.kind)))
            .collect::<Vec<_>>()
            .join("; "),
    }
}

/// The error scale of each recorded point: its quantity's ([`error_scales`]).
pub fn point_scales(recording: &[RecordedPoint]) -> Vec<f64> {
    let scales = error_scales(recording);
    recording
        .iter()
        .map(|point| {
            scales
                .iter()
                .find(|s| s.quantity == point.quantity)
                .map_or(f64::MIN_POSITIVE, |s| s.value)
        })
        .collect()
}

/// The scaled RMSE (seed 000's measure with [`error_scales`]) and the uncertainty-weighted
/// RMS.
pub fn score(recording: &[RecordedPoint], predicted: &[f64]) -> Option<Score> {
    if recording.len() != predicted.len() || predicted.iter().any(|p| !p.is_finite()) {
        return None;
    }
    let scales = point_scales(recording);
    let n = recording.len() as f64;
    let error = (recording
        .iter()
        .zip(predicted)
        .zip(&scales)
        .map(|((r, p), scale)| ((p - r.value) / scale).powi(2))
        .sum::<f64>()
        / n)
        .sqrt();
    let chi = (recording
        .iter()
        .zip(predicted)
        .map(|(r, p)| ((p - r.value) / r.uncertainty).powi(2))
        .sum::<f64>()
        / n)
        .sqrt();
    Some(Score { error, chi })
}

/// The strain rates (1/s) at which the realism constraints are checked.
const CHECK_RATES: [f64; 6] = [1e-4, 1e-2, 1.0, 1e2, 1e3, 1e4];
/// The highest temperature of the thermal-softening check (K): about what the bundled impact
/// experiments reach (the long-rod shots' target columns, to about 1650 K).
pub const THERMAL_CHECK_CEILING: f64 = 1700.0;
/// The highest strain rate of the thermal-softening check (1/s): the penetration's (about
/// 2.6e6 /s in the target columns), where a Zerilli-Armstrong candidate with
/// `C3 < C4 ln(rate)` has a flow stress that grows exponentially with temperature.
pub const THERMAL_CHECK_MAX_RATE: f64 = 1e6;

/// Check the realism constraints on the flow stress; `Err` names the violated one.
pub fn check_constraints(
    material: &Material,
    constraints: &Constraints,
    floor: f64,
    temperature: f64,
) -> Result<(), String> {
    let strains: Vec<f64> = (0..=20).map(|k| 0.05 * k as f64).collect();
    let mut previous_rate_row: Option<Vec<f64>> = None;
    for &rate in &CHECK_RATES {
        let row: Vec<f64> = strains
            .iter()
            .map(|&e| material.strength.flow_stress(e, rate, temperature).value)
            .collect();
        for (&strain, &stress) in strains.iter().zip(&row) {
            if !(stress >= floor && stress <= constraints.max_flow_stress) {
                return Err(format!(
                    "flow stress {:.3e} Pa at strain {strain}, rate {rate} /s outside [{:.3e}, {:.3e}]",
                    stress, floor, constraints.max_flow_stress
                ));
            }
        }
        if constraints.monotone_hardening && row.windows(2).any(|w| w[1] < w[0] * (1.0 - 1e-12)) {
            return Err(format!("flow stress decreases with strain at {rate} /s"));
        }
        if let Some(previous) = &previous_rate_row {
            if constraints.monotone_rate
                && row
                    .iter()
                    .zip(previous)
                    .any(|(now, before)| *now < *before * (1.0 - 1e-12))
            {
                return Err(format!("flow stress decreases with rate at {rate} /s"));
            }
        }
        previous_rate_row = Some(row);
    }
    if constraints.monotone_temperature {
        check_thermal_softening(material, &strains, temperature)?;
    }
    Ok(())
}

/// The flow stress must not rise with temperature: at every strain of the constraint grid and
/// rates from 1e-4 /s to [`THERMAL_CHECK_MAX_RATE`], from `temperature` to
/// [`THERMAL_CHECK_CEILING`] in steps of at most 50 K. A Zerilli-Armstrong candidate with
/// `C3 < C4 ln(rate / e0)` fails it: its thermal factor `exp(-(C3 - C4 ln(rate/e0)) T)` then
/// grows with temperature, to tens of GPa in a penetration's heated target (the realism check at
/// room temperature does not see it).
fn check_thermal_softening(
    material: &Material,
    strains: &[f64],
    temperature: f64,
) -> Result<(), String> {
    let steps = ((THERMAL_CHECK_CEILING - temperature) / 50.0)
        .ceil()
        .max(1.0) as usize;
    let temperatures: Vec<f64> = (0..=steps)
        .map(|k| temperature + (THERMAL_CHECK_CEILING - temperature) * k as f64 / steps as f64)
        .collect();
    let rates = CHECK_RATES.iter().chain(&[1e5, THERMAL_CHECK_MAX_RATE]);
    for &rate in rates {
        for &strain in strains {
            let mut previous: Option<(f64, f64)> = None;
            for &t in &temperatures {
                let stress = material.strength.flow_stress(strain, rate, t).value;
                if let Some((t0, before)) = previous {
                    if stress > before * (1.0 + 1e-12) && stress > before + 1e-6 {
                        return Err(format!(
                            "flow stress rises with temperature at strain {strain}, rate {rate:.0e} /s: \
                             {before:.3e} Pa at {t0:.0} K, {stress:.3e} Pa at {t:.0} K"
                        ));
                    }
                }
                previous = Some((t, stress));
            }
        }
    }
    Ok(())
}

/// What happened to a candidate.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "status", content = "reason", rename_all = "kebab-case")]
pub enum Status {
    /// Every experiment simulated.
    Ok,
    /// Rejected before simulation by a realism constraint or invalid constants.
    Infeasible(String),
    /// A simulation failed (e.g. element inversion) or gave non-finite results.
    Failed(String),
}

/// One evaluated candidate.
///
/// Written (result.json, simulations.jsonl, Slurm result files) **by name**:
/// `{"constants": {"yield_stress": 7.9e8, ..}, "scores": {"experiments/taylor.toml": {..},
/// ..}, "status": .., "wall_time": ..}`, the constants in the model space's order and the
/// scores in the campaign's. Files written before stoss named them hold positional `values`
/// and `scores` arrays; they still read, with empty [`Evaluation::names`] and
/// [`Evaluation::experiments`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(from = "record::EvaluationRecord", into = "record::EvaluationRecord")]
pub struct Evaluation {
    /// Fitted constants (SI), in the model space's order.
    pub values: Vec<f64>,
    /// Scores per campaign experiment (`None`: not simulated or failed).
    pub scores: Vec<Option<Score>>,
    /// Outcome.
    pub status: Status,
    /// Wall time of the simulations (s).
    pub wall_time: f64,
    /// The names of `values` (the model space's constants); empty if read from a positional
    /// file.
    pub names: Vec<String>,
    /// The experiments of `scores` (their campaign file entries); empty if read from a
    /// positional file.
    pub experiments: Vec<String>,
    /// The mesh its simulations ran on (multi-fidelity; [`Fidelity::Fine`] otherwise).
    pub fidelity: Fidelity,
    /// Its coarse scores were corrected towards the fine mesh's
    /// ([`crate::fit::fidelity::Correction`]): a prediction of the fine simulation, not one.
    pub corrected: bool,
    /// The predictions of the experiments that have a coarse fidelity (multi-fidelity), per
    /// campaign experiment, as simulated (a corrected evaluation keeps its coarse ones);
    /// empty otherwise.
    pub predictions: Vec<Option<Vec<f64>>>,
}

impl Evaluation {
    /// An evaluation of `values` in `space`, labelled with its constants' and the campaign's
    /// experiments' names.
    pub fn labelled(
        campaign: &Campaign,
        space: &ModelSpace,
        values: &[f64],
        scores: Vec<Option<Score>>,
        status: Status,
        wall_time: f64,
    ) -> Self {
        Evaluation {
            values: values.to_vec(),
            scores,
            status,
            wall_time,
            names: space.names.clone(),
            experiments: campaign
                .file
                .experiments
                .iter()
                .map(|e| e.file.clone())
                .collect(),
            fidelity: Fidelity::Fine,
            corrected: false,
            predictions: Vec::new(),
        }
    }

    /// Label an evaluation read from a positional file with `space`'s constants and
    /// `campaign`'s experiments, if their counts match (a labelled one is left as it is).
    pub fn label_positional(&mut self, campaign: &Campaign, space: &ModelSpace) {
        if self.names.is_empty() && self.values.len() == space.names.len() {
            self.names = space.names.clone();
        }
        if self.experiments.is_empty() && self.scores.len() == campaign.file.experiments.len() {
            self.experiments = campaign
                .file
                .experiments
                .iter()
                .map(|e| e.file.clone())
                .collect();
        }
    }

    /// Weighted sum of the scaled errors over `experiments`; `None` if any is missing.
    pub fn total(&self, campaign: &Campaign, experiments: &[usize]) -> Option<f64> {
        experiments
            .iter()
            .map(|&i| {
                self.scores
                    .get(i)
                    .copied()
                    .flatten()
                    .map(|s| s.error * campaign.file.experiments[i].weight)
            })
            .sum()
    }

    /// The chi-square `sum (r / u)^2` over every recorded point of `experiments` (each
    /// experiment's `n chi^2`), and the number of those points; `None` if a score is missing.
    pub fn chi_square(&self, campaign: &Campaign, experiments: &[usize]) -> Option<(f64, usize)> {
        experiments.iter().try_fold((0.0, 0), |(sum, points), &i| {
            let score = self.scores.get(i).copied().flatten()?;
            let n = campaign.experiments.get(i)?.recording.len();
            Some((sum + n as f64 * score.chi * score.chi, points + n))
        })
    }

    /// Mean over `experiments` of the uncertainty-weighted RMS (1 = at the noise floor).
    pub fn mean_chi(&self, experiments: &[usize]) -> Option<f64> {
        let sum: Option<f64> = experiments
            .iter()
            .map(|&i| self.scores.get(i).copied().flatten().map(|s| s.chi))
            .sum();
        sum.map(|s| s / experiments.len().max(1) as f64)
    }
}

/// Simulate every experiment of `experiments` with the model's constants `values`.
pub fn evaluate(
    campaign: &Campaign,
    space: &ModelSpace,
    values: &[f64],
    experiments: &[usize],
    settings: &SolverSettings,
) -> Evaluation {
    evaluate_at(
        campaign,
        space,
        values,
        experiments,
        settings,
        Fidelity::Fine,
    )
}

/// [`evaluate`] at a fidelity: [`Fidelity::Coarse`] simulates the experiments that have a
/// coarse fidelity on their coarse mesh. In a multi-fidelity campaign the predictions of
/// those experiments are kept (at either fidelity), for the correction.
pub fn evaluate_at(
    campaign: &Campaign,
    space: &ModelSpace,
    values: &[f64],
    experiments: &[usize],
    settings: &SolverSettings,
    fidelity: Fidelity,
) -> Evaluation {
    let started = std::time::Instant::now();
    let mut scores = vec![None; campaign.experiments.len()];
    let mut predictions: Vec<Option<Vec<f64>>> = if campaign.is_multi_fidelity() {
        vec![None; campaign.experiments.len()]
    } else {
        Vec::new()
    };
    let finish = |scores, predictions, status| {
        let wall_time = started.elapsed().as_secs_f64();
        let mut evaluation =
            Evaluation::labelled(campaign, space, values, scores, status, wall_time);
        evaluation.fidelity = fidelity;
        evaluation.predictions = predictions;
        evaluation
    };
    let material = match space.material(&campaign.base, values) {
        Ok((_, material)) => material,
        Err(message) => return finish(scores, predictions, Status::Infeasible(message)),
    };
    let reference_temperature = 298.0;
    // The flow-stress realism constraints are for J2 metals.
    if let Some(metal) = material.j2() {
        let floor = campaign.flow_stress_floor();
        if let Err(message) = check_constraints(
            metal,
            &campaign.file.constraints,
            floor,
            reference_temperature,
        ) {
            return finish(scores, predictions, Status::Infeasible(message));
        }
    }
    // The set-up parameters (nuisance) written into the experiments they name.
    let setup = space.setup_values(values);
    let run = |&index: &usize| {
        let file = match (fidelity, &campaign.coarse.get(index)) {
            (Fidelity::Coarse, Some(Some(coarse))) => coarse,
            _ => &campaign.experiments[index],
        };
        let experiment = super::space::with_setup(file, &setup).map_err(Status::Failed)?;
        match experiment.simulate(&material, settings) {
            Ok(outcome) => score(&experiment.recording, &outcome.predicted)
                .map(|s| (s, outcome.predicted))
                .ok_or_else(|| {
                    Status::Failed(format!("{}: non-finite prediction", experiment.file.name))
                }),
            Err(error) => Err(Status::Failed(format!("{}: {error}", experiment.file.name))),
        }
    };
    // One solver thread per simulation: the experiments of a candidate run side by side on
    // the calling pool's threads (so a lone candidate, as in the polish, still fills the
    // cores). With more solver threads they run one after another, each using them all.
    let outcomes: Vec<Result<(Score, Vec<f64>), Status>> = if settings.threads == Some(1) {
        use rayon::prelude::*;
        experiments.par_iter().map(run).collect()
    } else {
        experiments.iter().map(run).collect()
    };
    // The first failure in the campaign's order decides, as if they had run in turn.
    for (&index, outcome) in experiments.iter().zip(outcomes) {
        match outcome {
            Ok((s, predicted)) => {
                scores[index] = Some(s);
                if campaign.coarse.get(index).is_some_and(Option::is_some) {
                    predictions[index] = Some(predicted);
                }
            }
            Err(status) => return finish(scores, predictions, status),
        }
    }
    finish(scores, predictions, Status::Ok)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(value: f64, uncertainty: f64) -> RecordedPoint {
        RecordedPoint {
            quantity: "q".into(),
            position: 0.0,
            value,
            uncertainty,
        }
    }

    #[test]
    fn evaluations_are_written_by_name_and_positional_ones_still_read() {
        // GOAL: result.json and simulations.jsonl carry constants and scores by name, in the
        //       model's and campaign's order (not sorted), and files written before stoss
        //       named them still read.
        // SETUP: an evaluation of two constants named against alphabetical order, one
        //        scored and one unsimulated experiment, and failed; a line as stoss wrote it
        //        before (positional `values` and `scores`).
        // REFERENCE: the JSON text; the round trip; the old line's numbers.
        let evaluation = Evaluation {
            values: vec![7.9e8, 0.014],
            scores: vec![
                Some(Score {
                    error: 0.1,
                    chi: 2.0,
                }),
                None,
            ],
            status: Status::Failed("taylor.toml: inverted".into()),
            wall_time: 1.5,
            names: vec!["yield_stress".into(), "rate_sensitivity".into()],
            experiments: vec!["tension.toml".into(), "taylor.toml".into()],
            fidelity: Fidelity::Fine,
            corrected: false,
            predictions: Vec::new(),
        };
        let text = serde_json::to_string(&evaluation).unwrap();
        // A fine evaluation writes no fidelity, correction or predictions.
        assert!(
            !text.contains("fidelity") && !text.contains("predictions"),
            "{text}"
        );
        // A corrected coarse one writes them, its predictions by experiment, and reads back.
        let coarse = Evaluation {
            fidelity: Fidelity::Coarse,
            corrected: true,
            predictions: vec![None, Some(vec![0.0221, 0.0105])],
            ..evaluation.clone()
        };
        let coarse_text = serde_json::to_string(&coarse).unwrap();
        assert!(
            coarse_text.contains(
                r#""fidelity":"coarse","corrected":true,"predictions":{"taylor.toml":[0.0221,0.0105]}"#
            ),
            "{coarse_text}"
        );
        assert_eq!(
            serde_json::from_str::<Evaluation>(&coarse_text).unwrap(),
            coarse
        );
        assert!(
            text.starts_with(
                r#"{"constants":{"yield_stress":790000000.0,"rate_sensitivity":0.014},"scores":{"tension.toml":{"error":0.1,"chi":2.0},"taylor.toml":null}"#
            ),
            "{text}"
        );
        let read: Evaluation = serde_json::from_str(&text).unwrap();
        assert_eq!(read, evaluation);
        let old = r#"{"values":[790000000.0,0.014],"scores":[{"error":0.1,"chi":2.0},null],"status":{"status":"failed","reason":"taylor.toml: inverted"},"wall_time":1.5}"#;
        let read: Evaluation = serde_json::from_str(old).unwrap();
        assert_eq!(read.values, evaluation.values);
        assert_eq!(read.scores, evaluation.scores);
        assert_eq!(read.status, evaluation.status);
        assert!(read.names.is_empty() && read.experiments.is_empty());
        // Written again, an unlabelled evaluation stays positional rather than inventing names.
        assert_eq!(serde_json::to_string(&read).unwrap(), old);
    }

    #[test]
    fn min_max_rmse_matches_a_hand_calculation() {
        // GOAL: the seed 000 error measure. SETUP: recorded 1, 2, 3; predicted 1.5, 2, 2.
        // REFERENCE: range 2; residuals 0.5, 0, -1 -> sqrt((0.0625 + 0 + 0.25)/3) = 0.3227.
        let recording = [point(1.0, 0.1), point(2.0, 0.1), point(3.0, 0.1)];
        let s = score(&recording, &[1.5, 2.0, 2.0]).unwrap();
        assert!((s.error - (0.3125_f64 / 3.0).sqrt()).abs() < 1e-15);
        assert!((s.chi - (125.0_f64 / 3.0).sqrt()).abs() < 1e-12);
        assert!(score(&recording, &[1.0, f64::NAN, 3.0]).is_none());
    }

    #[test]
    fn short_and_flat_curves_are_scaled_by_their_magnitude_and_quantities_separately() {
        // GOAL: the error of a curve that has no shape (two points, or a range within the
        // noise) is a relative error, not a multiple of a range the noise made; quantities of
        // one recording are scaled separately.
        // SETUP: a two-point flow curve 800 / 802 MPa (u 10 MPa) predicted 10 % high; a
        // five-point curve 800..804 MPa (range 4 MPa < 1.96 sqrt(2) 10 MPa) predicted 10 % high;
        // a recording of a time (1 ms) and a displacement (20 mm), each predicted 10 % high.
        // REFERENCE: a 10 % offset on a magnitude scale gives about 0.1 (exactly 0.1 when the
        // values are equal); the min-max scale would give 40 and 20.
        let mpa = |v: f64| point(v * 1e6, 10e6);
        let two = [mpa(800.0), mpa(802.0)];
        let s = score(&two, &[880e6, 882.2e6]).unwrap();
        assert!((s.error - 0.1).abs() < 1e-3, "{}", s.error);
        assert_eq!(error_scales(&two)[0].kind, ScaleKind::Magnitude);
        let flat: Vec<RecordedPoint> = (0..5).map(|k| mpa(800.0 + k as f64)).collect();
        let predicted: Vec<f64> = flat.iter().map(|p| 1.1 * p.value).collect();
        assert!((score(&flat, &predicted).unwrap().error - 0.1).abs() < 1e-12);
        assert_eq!(error_scales(&flat)[0].kind, ScaleKind::Magnitude);
        let mixed = [
            RecordedPoint {
                quantity: "first_crack_time".into(),
                position: 0.0,
                value: 1e-3,
                uncertainty: 1e-4,
            },
            RecordedPoint {
                quantity: "striker_displacement".into(),
                position: 0.0,
                value: 0.02,
                uncertainty: 1e-3,
            },
        ];
        let s = score(&mixed, &[1.1e-3, 0.022]).unwrap();
        assert!((s.error - 0.1).abs() < 1e-12, "{}", s.error);
        let scales = error_scales(&mixed);
        assert_eq!(scales.len(), 2);
        assert_eq!(scales[0].value, 1e-3);
        assert_eq!(scales[1].value, 0.02);
        // A resolved curve of three or more points keeps seed 000's range.
        let resolved = [mpa(300.0), mpa(500.0), mpa(700.0)];
        let scales = error_scales(&resolved);
        assert_eq!(scales[0].kind, ScaleKind::Range);
        assert!((scales[0].value - 400e6).abs() < 1.0);
    }

    #[test]
    fn constraints_reject_unrealistic_flow_stress() {
        // GOAL: candidates with absurd flow stress are rejected before simulation.
        // SETUP: 4340 JC (feasible); yield 10 GPa (too strong).
        // REFERENCE: Ok for 4340; an error naming the flow-stress bound otherwise.
        let constraints = Constraints::default();
        assert!(check_constraints(&Material::STEEL_4340, &constraints, 50e6, 298.0).is_ok());
        let mut jc = stoss_kernel::strength::JohnsonCook::STEEL_4340;
        jc.yield_stress = 10.0e9;
        let strong = Material::STEEL_4340.with_strength(jc);
        assert!(check_constraints(&strong, &constraints, 50e6, 298.0)
            .unwrap_err()
            .contains("outside"));
    }

    #[test]
    fn constraints_reject_a_flow_stress_that_rises_with_temperature() {
        // GOAL: a Zerilli-Armstrong candidate whose thermal factor grows with temperature at
        //       impact rates is rejected before it is simulated, and physical constants pass.
        // SETUP: Armco iron (C3 0.00698, C4 0.000415 /K: C3 > C4 ln(rate) up to 2e7 /s); a
        //        design point of seed 000's Eulerian campaign (2026-11-30, C3 / C4 = 6.8: the
        //        factor grows with temperature above 900 /s), which passes the room-temperature
        //        checks and whose 1250 m/s shot ran 43 minutes before it failed with the rod
        //        crushed to a ninth of its volume against the heated target; 4340 JC; the
        //        check switched off.
        // REFERENCE: ZA's factor exp(-(C3 - C4 ln(rate/e0)) T) (Zerilli & Armstrong 1987).
        use stoss_kernel::strength::ZerilliArmstrong;
        let constraints = Constraints::default();
        let iron = Material::STEEL_4340.with_strength(ZerilliArmstrong::ARMCO_IRON);
        assert!(check_constraints(&iron, &constraints, 50e6, 298.0).is_ok());
        assert!(check_constraints(&Material::STEEL_4340, &constraints, 50e6, 298.0).is_ok());
        let rising = Material::STEEL_4340.with_strength(ZerilliArmstrong {
            athermal_stress: 502_340_169.763_154_2,
            c1: 833_179_119.009_024_4,
            c3: 0.003_759_318_771_551_707_3,
            c4: 0.000_553_039_706_170_894_7,
            c5: 429_004_053.634_614_3,
            exponent: 0.317_697_698_720_896_2,
            ..ZerilliArmstrong::ARMCO_IRON
        });
        let room_only = Constraints {
            monotone_temperature: false,
            ..Constraints::default()
        };
        assert!(check_constraints(&rising, &room_only, 50e6, 298.0).is_ok());
        let error = check_constraints(&rising, &constraints, 50e6, 298.0).unwrap_err();
        assert!(error.contains("rises with temperature"), "{error}");
    }
}

/// The file form of an [`Evaluation`]: by name, or positional as written before.
mod record {
    use super::{Evaluation, Fidelity, Score, Status};
    use crate::fit::space::SETUP_PREFIX;
    use serde::de::{MapAccess, Visitor};
    use serde::ser::SerializeMap;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    /// Name-value pairs written as a JSON object in their order, and read back in the file's
    /// order (a `BTreeMap` would sort them).
    #[derive(Clone, Debug, Default)]
    pub struct Ordered<T>(pub Vec<(String, T)>);

    impl<T: Serialize> Serialize for Ordered<T> {
        fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
            let mut map = serializer.serialize_map(Some(self.0.len()))?;
            for (name, value) in &self.0 {
                map.serialize_entry(name, value)?;
            }
            map.end()
        }
    }

    impl<'de, T: Deserialize<'de>> Deserialize<'de> for Ordered<T> {
        fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
            struct Pairs<T>(std::marker::PhantomData<T>);
            impl<'de, T: Deserialize<'de>> Visitor<'de> for Pairs<T> {
                type Value = Ordered<T>;
                fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                    f.write_str("an object of named values")
                }
                fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
                    let mut pairs = Vec::new();
                    while let Some(pair) = map.next_entry::<String, T>()? {
                        pairs.push(pair);
                    }
                    Ok(Ordered(pairs))
                }
            }
            deserializer.deserialize_map(Pairs(std::marker::PhantomData))
        }
    }

    /// Scores by experiment, or by position (files written before stoss named them).
    #[derive(Clone, Debug, Serialize, Deserialize)]
    #[serde(untagged)]
    pub enum Scores {
        Named(Ordered<Option<Score>>),
        Positional(Vec<Option<Score>>),
    }

    #[derive(Clone, Debug, Serialize, Deserialize)]
    pub struct EvaluationRecord {
        #[serde(default, skip_serializing_if = "Option::is_none")]
        constants: Option<Ordered<f64>>,
        /// The set-up parameters (nuisance), by their names without the `setup.` prefix,
        /// apart from the material constants.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        setup: Option<Ordered<f64>>,
        /// Positional constants (files written before stoss named them).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        values: Option<Vec<f64>>,
        scores: Scores,
        status: Status,
        wall_time: f64,
        /// The mesh (multi-fidelity); absent for the fine one.
        #[serde(default, skip_serializing_if = "Fidelity::is_fine")]
        fidelity: Fidelity,
        /// The scores are of corrected coarse predictions; absent when not.
        #[serde(default, skip_serializing_if = "std::ops::Not::not")]
        corrected: bool,
        /// The predictions of the experiments with a coarse fidelity, by experiment.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        predictions: Option<Ordered<Vec<f64>>>,
    }

    impl From<Evaluation> for EvaluationRecord {
        fn from(e: Evaluation) -> Self {
            let named = e.names.len() == e.values.len() && e.experiments.len() == e.scores.len();
            if named {
                type Named = Vec<(String, f64)>;
                let (setup, constants): (Named, Named) = e
                    .names
                    .into_iter()
                    .zip(e.values)
                    .partition(|(name, _)| name.starts_with(SETUP_PREFIX));
                let setup: Vec<(String, f64)> = setup
                    .into_iter()
                    .map(|(name, value)| (name[SETUP_PREFIX.len()..].to_string(), value))
                    .collect();
                let predictions: Vec<(String, Vec<f64>)> = e
                    .experiments
                    .iter()
                    .zip(&e.predictions)
                    .filter_map(|(name, p)| p.clone().map(|p| (name.clone(), p)))
                    .collect();
                EvaluationRecord {
                    constants: Some(Ordered(constants)),
                    setup: (!setup.is_empty()).then_some(Ordered(setup)),
                    values: None,
                    scores: Scores::Named(Ordered(
                        e.experiments.into_iter().zip(e.scores).collect(),
                    )),
                    status: e.status,
                    wall_time: e.wall_time,
                    fidelity: e.fidelity,
                    corrected: e.corrected,
                    predictions: (!predictions.is_empty()).then_some(Ordered(predictions)),
                }
            } else {
                EvaluationRecord {
                    constants: None,
                    setup: None,
                    values: Some(e.values),
                    scores: Scores::Positional(e.scores),
                    status: e.status,
                    wall_time: e.wall_time,
                    fidelity: e.fidelity,
                    corrected: e.corrected,
                    predictions: None,
                }
            }
        }
    }

    impl From<EvaluationRecord> for Evaluation {
        fn from(r: EvaluationRecord) -> Self {
            let setup = r.setup.map(|Ordered(pairs)| pairs).unwrap_or_default();
            let (names, values) = match (r.constants, r.values) {
                (Some(Ordered(pairs)), _) => pairs
                    .into_iter()
                    .chain(
                        setup
                            .into_iter()
                            .map(|(name, value)| (format!("{SETUP_PREFIX}{name}"), value)),
                    )
                    .unzip(),
                (None, values) => (Vec::new(), values.unwrap_or_default()),
            };
            let (experiments, scores): (Vec<String>, _) = match r.scores {
                Scores::Named(Ordered(pairs)) => pairs.into_iter().unzip(),
                Scores::Positional(scores) => (Vec::new(), scores),
            };
            // Predictions by experiment name, placed at the experiments' positions.
            let predictions = match r.predictions {
                Some(Ordered(pairs)) => experiments
                    .iter()
                    .map(|name| {
                        pairs
                            .iter()
                            .find(|(n, _)| n == name)
                            .map(|(_, p)| p.clone())
                    })
                    .collect(),
                None => Vec::new(),
            };
            Evaluation {
                values,
                scores,
                status: r.status,
                wall_time: r.wall_time,
                names,
                experiments,
                fidelity: r.fidelity,
                corrected: r.corrected,
                predictions,
            }
        }
    }
}

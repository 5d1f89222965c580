//! The error measure and the evaluation of one candidate set of constants.
//!
//! Per experiment (seed 000 sec. 4.1): the RMSE of the residuals scaled by the measured range
//! of that experiment, `e = sqrt(mean(((predicted - recorded) / (max - min))^2))`; a
//! one-point recording is scaled by its value. The campaign error is the weighted sum over the
//! fitted experiments. Reported beside it: the uncertainty-weighted RMS
//! `sqrt(mean(((predicted - recorded) / uncertainty)^2))` (1 = at the noise floor).

use super::campaign::{Campaign, Constraints};
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

/// Seed 000's min-max-scaled RMSE and the uncertainty-weighted RMS.
pub fn score(recording: &[RecordedPoint], predicted: &[f64]) -> Option<Score> {
    if recording.len() != predicted.len() || predicted.iter().any(|p| !p.is_finite()) {
        return None;
    }
    let (low, high) = recording
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p.value), hi.max(p.value))
        });
    let range = if high > low {
        high - low
    } else {
        high.abs().max(f64::MIN_POSITIVE)
    };
    let n = recording.len() as f64;
    let error = (recording
        .iter()
        .zip(predicted)
        .map(|(r, p)| ((p - r.value) / range).powi(2))
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

/// Check the realism constraints on the flow stress; `Err` names the violated one.
pub fn check_constraints(
    material: &Material,
    constraints: &Constraints,
    floor: f64,
    temperature: f64,
) -> Result<(), String> {
    let strains: Vec<f64> = (0..=20).map(|k| 0.05 * k as f64).collect();
    let rates = [1e-4, 1e-2, 1.0, 1e2, 1e3, 1e4];
    let mut previous_rate_row: Option<Vec<f64>> = None;
    for &rate in &rates {
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

    /// Weighted sum of the min-max errors over `experiments`; `None` if any is missing.
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
    let started = std::time::Instant::now();
    let mut scores = vec![None; campaign.experiments.len()];
    let finish = |scores, status| {
        let wall_time = started.elapsed().as_secs_f64();
        Evaluation::labelled(campaign, space, values, scores, status, wall_time)
    };
    let material = match space.material(&campaign.base, values) {
        Ok((_, material)) => material,
        Err(message) => return finish(scores, Status::Infeasible(message)),
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
            return finish(scores, Status::Infeasible(message));
        }
    }
    // The set-up parameters (nuisance) written into the experiments they name.
    let setup = space.setup_values(values);
    let run = |&index: &usize| {
        let experiment = super::space::with_setup(&campaign.experiments[index], &setup)
            .map_err(Status::Failed)?;
        match experiment.simulate(&material, settings) {
            Ok(outcome) => score(&experiment.recording, &outcome.predicted).ok_or_else(|| {
                Status::Failed(format!("{}: non-finite prediction", experiment.file.name))
            }),
            Err(error) => Err(Status::Failed(format!("{}: {error}", experiment.file.name))),
        }
    };
    // One solver thread per simulation: the experiments of a candidate run side by side on
    // the calling pool's threads (so a lone candidate, as in the polish, still fills the
    // cores). With more solver threads they run one after another, each using them all.
    let outcomes: Vec<Result<Score, Status>> = if settings.threads == Some(1) {
        use rayon::prelude::*;
        experiments.par_iter().map(run).collect()
    } else {
        experiments.iter().map(run).collect()
    };
    // The first failure in the campaign's order decides, as if they had run in turn.
    for (&index, outcome) in experiments.iter().zip(outcomes) {
        match outcome {
            Ok(s) => scores[index] = Some(s),
            Err(status) => return finish(scores, status),
        }
    }
    finish(scores, Status::Ok)
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
        };
        let text = serde_json::to_string(&evaluation).unwrap();
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
}

/// The file form of an [`Evaluation`]: by name, or positional as written before.
mod record {
    use super::{Evaluation, Score, Status};
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
                EvaluationRecord {
                    constants: Some(Ordered(constants)),
                    setup: (!setup.is_empty()).then_some(Ordered(setup)),
                    values: None,
                    scores: Scores::Named(Ordered(
                        e.experiments.into_iter().zip(e.scores).collect(),
                    )),
                    status: e.status,
                    wall_time: e.wall_time,
                }
            } else {
                EvaluationRecord {
                    constants: None,
                    setup: None,
                    values: Some(e.values),
                    scores: Scores::Positional(e.scores),
                    status: e.status,
                    wall_time: e.wall_time,
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
            let (experiments, scores) = match r.scores {
                Scores::Named(Ordered(pairs)) => pairs.into_iter().unzip(),
                Scores::Positional(scores) => (Vec::new(), scores),
            };
            Evaluation {
                values,
                scores,
                status: r.status,
                wall_time: r.wall_time,
                names,
                experiments,
            }
        }
    }
}

//! The identification rate of `stoss diagnose` on the concealed-effect cases of
//! `fixtures/diagnosis/`: for a case and a noise level, the truth's noise-free predictions are
//! perturbed by Gaussian noise of that relative size (one recorded seed per repetition), the
//! Johnson-Cook model is calibrated (a short Bayesian run plus polish) and diagnosed. A case is
//! *identified* when the accepted term (or, for `za-bcc`, the family that replaces the model)
//! is the concealed one; *same physics* when another term of the same physics is accepted (the
//! two heating terms); a *false alarm* when an unrelated term is accepted, or any term on the
//! control.
//!
//! Used by the `identify-*` rows of `stoss validate` and by `cargo bench -p stoss --bench
//! diagnosis`, which prints the full table of docs/diagnosis.md.

use crate::calibrate::proposer::bayesian_factory;
use crate::calibrate::run::{calibrate, RunOptions};
use crate::diagnose::{diagnose, Options};
use crate::experiment::Experiment;
use crate::fit::campaign::LeaveOneOut;
use crate::fit::executor::Local;
use crate::fit::Campaign;
use crate::input::material;
use crate::random::SplitMix64;
use crate::solver::SolverSettings;
use std::path::Path;

/// The cases (folders of `fixtures/diagnosis/`) and the term each conceals (none: the
/// control). A case's position here enters its noise seeds.
pub const CASES: [(&str, Option<&str>); 9] = [
    ("control", None),
    ("heating", Some("adiabatic-heating")),
    ("upturn", Some("high-rate-upturn")),
    ("saturation", Some("voce-saturation")),
    ("coupling", Some("rate-temperature-coupling")),
    ("friction", Some("anvil-friction")),
    ("za-bcc", Some("zerilli-armstrong-bcc")),
    ("heating-window", Some("heating-transition-1-100")),
    // Any centre of the thermal drop's grid (the truth's 840-960 K drop is not one of them).
    ("thermal-drop", Some("thermal-drop")),
];

/// The relative noise levels of the benchmark; a level's position enters its noise seeds.
pub const NOISE_LEVELS: [f64; 3] = [0.01, 0.03, 0.05];

/// The noise seeds per case and level that the documents quote.
pub const SEEDS: u64 = 10;

/// The physics a term belongs to (the two heating terms are one physics).
pub fn physics(term: &str) -> &str {
    match term {
        "adiabatic-heating" => "heating",
        t if t.starts_with("heating-transition") => "heating",
        other => other,
    }
}

/// The counts of one case at one noise level.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Tally {
    /// Diagnoses that accepted the concealed term.
    pub identified: u64,
    /// Diagnoses that accepted another term of the same physics.
    pub same_physics: u64,
    /// Diagnoses that accepted an unrelated term (any term, on the control).
    pub false_alarms: u64,
    /// Sets of constants the diagnoses simulated, summed.
    pub points: usize,
    /// Experiment runs of the diagnoses, summed.
    pub simulations: usize,
    /// Sets of constants the calibrations simulated, summed.
    pub calibration_points: usize,
}

/// One diagnosis of a case: its noise seed, the accepted term, the leading score test and
/// the refits with their reasons.
#[derive(Clone, Debug)]
pub struct Verdict {
    /// The noise seed.
    pub noise_seed: u64,
    /// The accepted term or family, if any.
    pub accepted: Option<String>,
    /// The leading score test, `name p value`.
    pub top_test: String,
    /// Each refit or alternative family tried, with why it was accepted or not.
    pub refits: Vec<String>,
}

/// Noise-free truth predictions of every experiment of the case (its truth set-up where the
/// case has one).
fn truth(case_dir: &Path, campaign: &Campaign) -> Result<Vec<Vec<f64>>, String> {
    let path = case_dir.join("TRUTH.toml");
    let (_, truth) = material::load(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    campaign
        .experiments
        .iter()
        .map(|e| {
            let setup = e.path.with_extension("truth-setup.toml");
            let experiment = if setup.exists() {
                Experiment::load(&setup).map_err(|e| e.to_string())?
            } else {
                e.clone()
            };
            experiment
                .simulate(
                    &stoss_kernel::PartMaterial::from(truth),
                    &SolverSettings::default(),
                )
                .map(|outcome| outcome.predicted)
                .map_err(|e| format!("{}: {e}", experiment.path.display()))
        })
        .collect()
}

/// Calibrate and diagnose `case` (a name of [`CASES`], its folder under `root`) at relative
/// noise `noise`, the `level`-th of the noise list, over noise seeds `1000 case + 100 level +
/// seed` for seed 1 to `seeds`; `on_verdict` sees each diagnosis as it ends.
pub fn identification(
    root: &Path,
    case: &str,
    noise: f64,
    level: usize,
    seeds: u64,
    on_verdict: &mut dyn FnMut(&Verdict),
) -> Result<Tally, String> {
    let (case_index, expected) = CASES
        .iter()
        .enumerate()
        .find(|(_, (name, _))| *name == case)
        .map(|(k, (_, expected))| (k, *expected))
        .ok_or_else(|| format!("no diagnosis case `{case}`"))?;
    let dir = root.join(case);
    let path = dir.join("campaign.toml");
    let template = Campaign::load(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let clean = truth(&dir, &template)?;
    // The friction case simulates Taylor rods: a shorter calibration.
    let (budget, polish) = if case == "friction" { (8, 4) } else { (16, 16) };
    let mut tally = Tally::default();
    for seed in 1..=seeds {
        let noise_seed = 1000 * case_index as u64 + 100 * level as u64 + seed;
        let mut rng = SplitMix64::new(noise_seed);
        let mut campaign = template.clone();
        for (experiment, values) in campaign.experiments.iter_mut().zip(&clean) {
            for (point, value) in experiment.recording.iter_mut().zip(values) {
                let sigma = noise * value.abs();
                point.value = value + sigma * rng.normal();
                point.uncertainty = sigma;
            }
        }
        let output = std::env::temp_dir().join(format!(
            "stoss-identification-{}-{case}-{level}-{seed}",
            std::process::id()
        ));
        let _ = std::fs::remove_dir_all(&output);
        std::fs::create_dir_all(&output).map_err(|e| format!("{}: {e}", output.display()))?;
        let factory = bayesian_factory(None);
        let mut progress =
            |_: &str, _: Option<&str>, _: usize, _: usize, _: usize, _: Option<f64>| {};
        let mut executor =
            Local::new(campaign.file.optimiser.parallel).map_err(|e| e.to_string())?;
        let results = calibrate(
            &campaign,
            &output,
            &RunOptions {
                budget: Some(budget),
                instances: Some(1),
                leave_one_out: Some(LeaveOneOut::Off),
                polish: Some(polish),
                least_squares: None,
                outcomes: false,
            },
            &mut executor,
            &factory,
            &mut progress,
        )
        .map(|calibration| calibration.results);
        let _ = std::fs::remove_dir_all(&output);
        let results = results.map_err(|e| format!("{case}, noise seed {noise_seed}: {e}"))?;
        let model = results
            .first()
            .ok_or_else(|| format!("{case}: the calibration returned no model"))?;
        tally.calibration_points += budget + polish;
        let outcome = diagnose(
            &campaign,
            model,
            &Options {
                parallel: 2,
                ..Options::default()
            },
            &mut Local::new(2).map_err(|e| e.to_string())?,
            None,
            &mut |_| {},
        )
        .map_err(|e| format!("{case}, noise seed {noise_seed}: {e}"))?;
        let d = &outcome.diagnosis;
        tally.points += d.cost.stages.iter().map(|s| s.1).sum::<usize>();
        tally.simulations += d.cost.simulated;
        on_verdict(&Verdict {
            noise_seed,
            accepted: if d.rounds.len() > 1 && d.replacement.is_none() {
                Some(
                    d.rounds
                        .iter()
                        .map(|r| r.accepted.as_str())
                        .collect::<Vec<_>>()
                        .join(", then "),
                )
            } else {
                d.accepted.clone()
            },
            top_test: d
                .tests
                .first()
                .map(|t| format!("{} p {:.1e}", t.name, t.p_value))
                .unwrap_or_default(),
            refits: d
                .refits
                .iter()
                .chain(d.later_rounds.iter().flat_map(|r| &r.refits))
                .chain(&d.alternatives)
                .map(|r| format!("{}: {}", r.candidate, r.reason))
                .collect(),
        });
        // Every accepted change: the rounds' terms, or the family that replaced the model.
        let accepted: Vec<&str> = if d.replacement.is_some() || d.rounds.is_empty() {
            d.accepted.iter().map(String::as_str).collect()
        } else {
            d.rounds.iter().map(|r| r.accepted.as_str()).collect()
        };
        let is_expected =
            |a: &str| expected.is_some_and(|e| e == a || a.starts_with(&format!("{e}-")));
        let same_physics = |a: &str| expected.is_some_and(|e| physics(e) == physics(a));
        if accepted.iter().any(|a| is_expected(a)) {
            tally.identified += 1;
        } else if accepted.iter().any(|a| same_physics(a)) {
            tally.same_physics += 1;
        }
        if accepted.iter().any(|a| !is_expected(a) && !same_physics(a)) {
            tally.false_alarms += 1;
        }
    }
    Ok(tally)
}

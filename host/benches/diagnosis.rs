//! Identification rate of `stoss diagnose` on the concealed-effect cases of
//! fixtures/diagnosis/ over noise seeds and levels: for each case, the truth's noise-free
//! predictions are perturbed by Gaussian noise of 1, 3 and 5 % (seeds recorded below), the
//! Johnson-Cook model is calibrated (short Bayesian run plus polish, as in tests/diagnose.rs)
//! and diagnosed; a case is identified when the accepted term (or, for `za-bcc`, the family
//! that replaces the model) is the concealed one, and the
//! control raises a false alarm when any term is accepted. A case also counts the diagnoses that
//! accept another term of the same physics (the two heating terms, which the case's recordings
//! barely tell apart) and those that accept an unrelated term (a false alarm). Also reports the
//! simulations each diagnosis costs. Every diagnosis's accepted term is printed to stderr.
//!
//! Run: `cargo bench -p stoss --bench diagnosis` (environment: `SEEDS` (default 10), `CASES`
//! (comma-separated, default all), `NOISE` (comma-separated, default 0.01,0.03,0.05)).

use std::path::{Path, PathBuf};
use stoss::calibrate::proposer::bayesian_factory;
use stoss::calibrate::run::{calibrate, RunOptions};
use stoss::diagnose::{diagnose, Options};
use stoss::experiment::Experiment;
use stoss::fit::executor::Local;
use stoss::fit::Campaign;
use stoss::input::material;
use stoss::random::SplitMix64;
use stoss::solver::SolverSettings;

const CASES: [(&str, Option<&str>); 9] = [
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

/// The physics a term belongs to (the two heating terms are one physics).
fn physics(term: &str) -> &str {
    match term {
        "adiabatic-heating" => "heating",
        t if t.starts_with("heating-transition") => "heating",
        other => other,
    }
}

fn env_list(name: &str, default: &str) -> Vec<String> {
    std::env::var(name)
        .unwrap_or_else(|_| default.into())
        .split(',')
        .map(str::to_string)
        .collect()
}

/// Noise-free truth predictions of every experiment of the case (truth set-up where present).
fn truth(case_dir: &Path, campaign: &Campaign) -> Vec<Vec<f64>> {
    let (_, truth) = material::load(&case_dir.join("TRUTH.toml")).expect("truth");
    campaign
        .experiments
        .iter()
        .map(|e| {
            let setup = e.path.with_extension("truth-setup.toml");
            let experiment = if setup.exists() {
                Experiment::load(&setup).expect("truth set-up")
            } else {
                e.clone()
            };
            experiment
                .simulate(
                    &stoss_kernel::PartMaterial::from(truth),
                    &SolverSettings::default(),
                )
                .expect("truth simulation")
                .predicted
        })
        .collect()
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/diagnosis");
    let seeds: u64 = std::env::var("SEEDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(10);
    let cases = env_list(
        "CASES",
        "control,heating,upturn,saturation,coupling,friction,za-bcc,heating-window,thermal-drop",
    );
    let noises: Vec<f64> = env_list("NOISE", "0.01,0.03,0.05")
        .iter()
        .map(|n| n.parse().expect("NOISE"))
        .collect();
    println!("case          noise  identified  same physics  false alarms  points/diagnosis  simulations/diagnosis  points/calibration  (seeds 1..={seeds}, noise seed = 1000 case + 100 level + seed)");
    for (case_index, (case, expected)) in CASES.iter().enumerate() {
        if !cases.iter().any(|c| c == case) {
            continue;
        }
        let dir: PathBuf = root.join(case);
        let template = Campaign::load(&dir.join("campaign.toml")).expect("campaign");
        let clean = truth(&dir, &template);
        let (budget, polish) = if *case == "friction" {
            (8, 4)
        } else {
            (16, 16)
        };
        for (level, noise) in noises.iter().enumerate() {
            let (mut identified, mut family, mut alarms) = (0, 0, 0);
            let (mut points, mut simulations, mut calibration_points) = (0, 0, 0);
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
                    "stoss-bench-diagnosis-{}-{case}-{level}-{seed}",
                    std::process::id()
                ));
                let _ = std::fs::remove_dir_all(&output);
                std::fs::create_dir_all(&output).expect("temporary folder");
                let factory = bayesian_factory(None);
                let mut progress =
                    |_: &str, _: Option<&str>, _: usize, _: usize, _: usize, _: Option<f64>| {};
                let results = calibrate(
                    &campaign,
                    &output,
                    &RunOptions {
                        budget: Some(budget),
                        instances: Some(1),
                        leave_one_out: Some(stoss::fit::campaign::LeaveOneOut::Off),
                        polish: Some(polish),
                        least_squares: None,
                    },
                    &mut Local::new(campaign.file.optimiser.parallel).expect("thread pool"),
                    &factory,
                    &mut progress,
                )
                .expect("calibration");
                let _ = std::fs::remove_dir_all(&output);
                calibration_points += budget + polish;
                let outcome = diagnose(
                    &campaign,
                    &results[0],
                    &Options {
                        parallel: 2,
                        ..Options::default()
                    },
                    &mut Local::new(2).expect("thread pool"),
                    None,
                    &mut |_| {},
                )
                .expect("diagnosis");
                let d = &outcome.diagnosis;
                points += d.cost.stages.iter().map(|s| s.1).sum::<usize>();
                simulations += d.cost.simulated;
                let top = d
                    .tests
                    .first()
                    .map(|t| format!("{} p {:.1e}", t.name, t.p_value))
                    .unwrap_or_default();
                let refits: Vec<String> = d
                    .refits
                    .iter()
                    .chain(&d.alternatives)
                    .map(|r| format!("{}: {}", r.candidate, r.reason))
                    .collect();
                eprintln!(
                    "{case} noise {noise} seed {noise_seed}: accepted {} (top test {top}; refits: {})",
                    d.accepted.as_deref().unwrap_or("none"),
                    refits.join("; ")
                );
                match (expected, &d.accepted) {
                    (None, Some(_)) => alarms += 1,
                    (Some(e), Some(a)) if *e == a.as_str() || a.starts_with(&format!("{e}-")) => {
                        identified += 1
                    }
                    (Some(e), Some(a)) if physics(e) == physics(a) => family += 1,
                    (Some(_), Some(_)) => alarms += 1,
                    _ => {}
                }
            }
            println!(
                "{case:<12} {:>5.0} %  {:>5}/{seeds:<4}  {:>6}/{seeds:<5}  {:>6}/{seeds:<5}  {:>16.0}  {:>21.0}  {:>18}",
                100.0 * noise,
                if expected.is_some() { identified.to_string() } else { "-".into() },
                if expected.is_some() { family.to_string() } else { "-".into() },
                alarms,
                points as f64 / seeds as f64,
                simulations as f64 / seeds as f64,
                calibration_points / seeds as usize,
            );
        }
    }
}

//! `stoss diagnose <calibration folder>`: locate the misfit of the calibrated model, rank the
//! candidate physics terms by a score test, refit with the best ones, and accept a term only if
//! it earns its constant. Writes `diagnosis/` (report.md, figures, diagnosis.json, the refitted
//! material) into the calibration folder; every simulation is logged in `diagnosis.jsonl`, so
//! a killed diagnosis rerun replays instead of simulating again.

use super::executor_args::{start_executor, ExecutorArgs};
use super::output::{log_line, say, say_inline};
use super::output_folder::{write_folder, Leftovers};
use crate::diagnose::{self, Options};
use crate::fit::result::ModelResult;
use crate::fit::Campaign;
use clap::Args;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// File of a calibration folder naming the campaign file it ran.
pub const CAMPAIGN_PATH_FILE: &str = "campaign.path";

/// Arguments of `stoss diagnose`.
#[derive(Debug, Args)]
pub struct DiagnoseArgs {
    /// Calibration folder (the output of `stoss calibrate`).
    pub calibration: PathBuf,
    /// The model to diagnose (default: the calibration's selected model, as its report names it).
    #[arg(long)]
    pub model: Option<String>,
    /// The campaign file (default: the one named in `<calibration>/campaign.path`).
    #[arg(long)]
    pub campaign: Option<PathBuf>,
    /// Family-wise significance level of the tests.
    #[arg(long, default_value_t = 0.01)]
    pub alpha: f64,
    /// Simulations at once, one thread each (default: the number of cores); `--parallel`
    /// is the same flag under its former name.
    #[arg(long, alias = "parallel")]
    pub threads: Option<usize>,
    /// Levenberg-Marquardt iterations per refit (at most 50: each costs a simulation per
    /// constant and experiment, and a refit that has not converged in 50 will not).
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u64).range(1..=50))]
    pub iterations: u64,
    /// Terms refitted at most, in rank order: the significant ones; when none of them is
    /// accepted, as many of the others, judged by their likelihood ratio (at most 32: more
    /// than the library holds).
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u64).range(1..=32))]
    pub max_refits: u64,
    /// Rounds at most: after an accepted term, the search starts again from the extended
    /// model until nothing more earns its place or this many terms were accepted.
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u64).range(1..=16))]
    pub max_rounds: u64,
    /// Where the refits' simulations run (this machine, a Slurm cluster) and how; the
    /// campaign's `[executor]` table is the default, as for `stoss calibrate`.
    #[command(flatten)]
    pub executor: ExecutorArgs,
}

/// Least time between two lines of simulation counts.
const PROGRESS_INTERVAL: std::time::Duration = std::time::Duration::from_secs(10);

/// Run `stoss diagnose`.
pub fn run(args: &DiagnoseArgs) -> ExitCode {
    if let Err(message) = crate::fit::interrupt::install_handler() {
        eprintln!("warning: {message}: an interrupt will stop the run at once");
    }
    match run_diagnosis(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) if crate::fit::interrupt::requested() => {
            eprintln!(
                "{message}\nrun the same command again: the journalled simulations are replayed, \
                 none runs twice"
            );
            ExitCode::from(130)
        }
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

fn campaign_path(args: &DiagnoseArgs) -> Result<PathBuf, String> {
    if let Some(path) = &args.campaign {
        return Ok(path.clone());
    }
    let file = args.calibration.join(CAMPAIGN_PATH_FILE);
    let text = std::fs::read_to_string(&file).map_err(|e| {
        format!(
            "{}: {e} (is {} a `stoss calibrate` output folder? --campaign names the campaign file)",
            file.display(),
            args.calibration.display()
        )
    })?;
    Ok(PathBuf::from(text.trim()))
}

fn read_results(folder: &Path) -> Result<Vec<ModelResult>, String> {
    let path = folder.join("report").join("result.json");
    let text = std::fs::read_to_string(&path).map_err(|e| {
        format!(
            "{}: {e} (the calibration has not finished: run `stoss calibrate --resume`)",
            path.display()
        )
    })?;
    serde_json::from_str(&text).map_err(|e| format!("{}:{}: {e}", path.display(), e.line()))
}

fn run_diagnosis(args: &DiagnoseArgs) -> Result<(), String> {
    let most = crate::solver::explicit::MAXIMUM_THREADS;
    if let Some(parallel) = args.threads {
        if !(1..=most).contains(&parallel) {
            return Err(format!(
                "--threads must be in 1..={most} (simulations at once, one thread each), got \
                 {parallel}"
            ));
        }
    }
    if !(args.alpha > 0.0 && args.alpha < 1.0) {
        return Err(format!("--alpha must be in (0, 1), got {}", args.alpha));
    }
    let campaign_file = campaign_path(args)?;
    let campaign = Campaign::load(&campaign_file).map_err(|e| e.to_string())?;
    let results = read_results(&args.calibration)?;
    let model = diagnose::selected(&results, &campaign, args.model.as_deref())
        .map_err(|e| e.to_string())?;
    let entry = campaign.model(&model.model).ok_or_else(|| {
        format!(
            "model `{}` is not in {}",
            model.model,
            campaign_file.display()
        )
    })?;
    model.check_against(&campaign.space(entry)).map_err(|e| {
        format!(
            "result.json of {} does not match {}: {e}",
            args.calibration.display(),
            campaign_file.display()
        )
    })?;
    let options = Options {
        alpha: args.alpha,
        parallel: args.threads.unwrap_or(Options::default().parallel),
        iterations: args.iterations as usize,
        max_refits: args.max_refits as usize,
        max_rounds: args.max_rounds as usize,
    };
    let _lock = crate::run_lock::RunLock::acquire(&args.calibration)?;
    log_line!("campaign: {} (model {})", campaign.file.name, model.model);
    if matches!(
        campaign.base,
        crate::input::material::AnyMaterialFile::Kc(_)
    ) {
        // K&C concrete: the structural diagnosis (where damage localises; non-local
        // regularisation as the candidate term).
        let settings = crate::solver::SolverSettings {
            threads: Some(options.parallel),
            ..crate::solver::SolverSettings::default()
        };
        let localisation = diagnose::localisation::diagnose(
            &campaign,
            &campaign.space(entry),
            &model.selected.values,
            &settings,
        )?;
        let text = localisation.report(&campaign.file.name, &model.model);
        say_inline!("\n{text}");
        let report = args.calibration.join("diagnosis");
        write_folder(&report, Leftovers::Clean, |folder| {
            std::fs::create_dir_all(folder).map_err(|e| format!("{}: {e}", folder.display()))?;
            std::fs::write(folder.join("report.md"), &text)
                .map_err(|e| format!("{}: {e}", folder.display()))
        })?;
        say!("report: {}", report.join("report.md").display());
        return Ok(());
    }
    let log = args.calibration.join("diagnosis.jsonl");
    let executor_entry = args.executor.settings(&campaign.file.executor)?;
    let mut executor = start_executor(
        &executor_entry,
        options.parallel,
        &campaign,
        &args.calibration,
        super::output::get().quiet,
    )?;
    // A line per stage, and within a stage the simulation counts at most every
    // PROGRESS_INTERVAL (a refit of penetration or blast experiments runs for minutes).
    let started = std::time::Instant::now();
    let mut last_line = started;
    let output = super::output::get();
    let mut progress = |event: diagnose::Progress<'_>| {
        if output.quiet {
            return;
        }
        let now = std::time::Instant::now();
        match event {
            diagnose::Progress::Stage(stage) => {
                last_line = now;
                eprintln!(
                    "  {stage} ({:.0} s elapsed)",
                    now.duration_since(started).as_secs_f64()
                );
            }
            diagnose::Progress::Simulations { run, replayed } => {
                if output.verbose || now.duration_since(last_line) >= PROGRESS_INTERVAL {
                    last_line = now;
                    eprintln!(
                        "    {run} simulations run, {replayed} replayed from the log, {:.0} s \
                         elapsed",
                        now.duration_since(started).as_secs_f64()
                    );
                }
            }
        }
    };
    let diagnose::Outcome {
        diagnosis,
        before,
        after,
    } = diagnose::diagnose(
        &campaign,
        model,
        &options,
        executor.as_mut(),
        Some(&log),
        &mut progress,
    )
    .map_err(|e| e.to_string())?;
    say!(
        "\n{:<28} {:>10} {:>10}  significant",
        "term",
        "statistic",
        "p"
    );
    for test in &diagnosis.tests {
        say!(
            "{:<28} {:>10.2} {:>10.2e}  {}{}",
            test.name,
            test.statistic,
            test.p_value,
            if test.significant { "yes" } else { "no" },
            test.note
                .as_ref()
                .map(|n| format!(" ({n})"))
                .unwrap_or_default()
        );
    }
    for check in &diagnosis.numerical {
        say!(
            "simulation or material: {} with {}: predictions move by {} recorded uncertainties RMS (misfit {:.2}){}",
            check.name,
            check.change,
            check
                .shift
                .map_or_else(|| "? (failed)".to_string(), |s| format!("{s:.2}")),
            check.misfit,
            if check.numerical {
                ": the simulation's"
            } else {
                ""
            }
        );
    }
    // Every refit, the first round's and the later rounds'.
    let rounds = std::iter::once((String::new(), &diagnosis.refits)).chain(
        diagnosis
            .later_rounds
            .iter()
            .map(|search| (format!("round {}: ", search.round), &search.refits)),
    );
    for (round, refits) in rounds {
        for refit in refits {
            say!(
                "{round}refit + {}: fit error {:.4}, held-out {}, BIC {:.1} -> {}: {}",
                refit.candidate,
                refit.assessment.fit_error,
                refit
                    .assessment
                    .held_out_error
                    .map_or("-".into(), |h| format!("{h:.4}")),
                refit.assessment.bic,
                if refit.accepted {
                    "accepted"
                } else {
                    "rejected"
                },
                refit.reason
            );
        }
    }
    if let Some(m) = diagnosis.state_misfit.first() {
        say!(
            "misfit in state space: organised most by {} ({:.0} % of it): {}",
            m.variable,
            100.0 * m.share,
            m.describe().unwrap_or_else(|| "within the noise".into())
        );
    }
    for alternative in &diagnosis.alternatives {
        say!(
            "family {}: fit error {:.4}, held-out {}, BIC {:.1} -> {}: {}",
            alternative.candidate,
            alternative.assessment.fit_error,
            alternative
                .assessment
                .held_out_error
                .map_or("-".into(), |h| format!("{h:.4}")),
            alternative.assessment.bic,
            if diagnosis.replacement.as_ref() == Some(&alternative.candidate) {
                "replaces the model"
            } else {
                "rejected"
            },
            alternative.reason
        );
    }
    let flagged = std::iter::once(("before", &diagnosis.before)).chain(
        diagnosis
            .refits
            .iter()
            .chain(&diagnosis.alternatives)
            .map(|r| (r.candidate.as_str(), &r.assessment)),
    );
    for (label, assessment) in flagged {
        if !assessment.at_bounds.is_empty() {
            say!(
                "warning: {label}: constants at a bound of their range: {}",
                assessment.at_bounds.join(", ")
            );
        }
    }
    say!("\nverdict: {}", diagnosis.verdict);
    let accepted: Vec<&str> = if diagnosis.replacement.is_some() {
        diagnosis.accepted.iter().map(String::as_str).collect()
    } else {
        diagnosis
            .rounds
            .iter()
            .map(|r| r.accepted.as_str())
            .collect()
    };
    say!(
        "accepted: {}",
        if accepted.is_empty() {
            "none".to_string()
        } else {
            accepted.join(", then ")
        }
    );
    let report = args.calibration.join("diagnosis");
    write_folder(&report, Leftovers::Clean, |folder| {
        diagnose::report::write(folder, &campaign, &diagnosis, &before, after.as_deref())
    })?;
    say!("report: {}", report.join("report.md").display());
    super::output::json(&serde_json::json!({
        "command": "diagnose",
        "model": model.model,
        "verdict": diagnosis.verdict,
        "accepted": accepted,
        "report": report.join("report.md"),
        "diagnosis": report.join("diagnosis.json"),
    }));
    Ok(())
}

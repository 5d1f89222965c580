//! `stoss calibrate <campaign.toml>`: Bayesian optimisation of model constants over the
//! campaign's experiments; writes `simulations.jsonl` (every simulation, as it ends), and at
//! the end `report/` (report.md, figures, cards, result.json). `--resume` continues a killed
//! run without re-running any logged simulation.

use super::executor_args::{start_executor, ExecutorArgs};
use super::output::{log_line, say};
use super::output_folder::{write_folder, Leftovers};
use crate::calibrate::run::{calibrate, RunOptions};
use crate::fit::Campaign;
use crate::report::calibration;
use clap::Args;
use std::path::PathBuf;
use std::process::ExitCode;

/// Least time between two progress lines when stderr is not a terminal.
const PROGRESS_INTERVAL: std::time::Duration = std::time::Duration::from_secs(10);

/// Arguments of `stoss calibrate`.
#[derive(Debug, Args)]
pub struct CalibrateArgs {
    /// Campaign file (TOML).
    pub campaign: PathBuf,
    /// Output folder (default `out/calibrate-<campaign name>`).
    #[arg(long)]
    pub output: Option<PathBuf>,
    /// Continue the run logged in the output folder.
    #[arg(long)]
    pub resume: bool,
    /// Override the campaign's budget (simulations per instance).
    #[arg(long)]
    pub budget: Option<usize>,
    /// Override the campaign's number of instances.
    #[arg(long)]
    pub instances: Option<usize>,
    /// Run leave-one-out over the fitted experiments.
    #[arg(long)]
    pub leave_one_out: bool,
    /// Override the campaign's Nelder-Mead polish budget.
    #[arg(long)]
    pub polish: Option<usize>,
    /// Levenberg-Marquardt iterations of a least-squares finish from each instance's best
    /// point (overrides the campaign's `least_squares`; 0 disables).
    #[arg(long)]
    pub least_squares: Option<usize>,
    /// Simulations at once, one thread each (default: the campaign's `[optimiser] parallel`).
    /// The results do not depend on it: the optimiser still proposes its batches of
    /// `parallel` candidates.
    #[arg(long)]
    pub threads: Option<usize>,
    /// The cards' unit system: `si` (kg, m, s, Pa), or length-time-mass[-stress] as the
    /// codes' users name them (`mm-ms-kg-GPa`, `mm-s-t-MPa`, `mm-ms-g-MPa`, `cm-us-g-Mbar`).
    #[arg(long, default_value = "si")]
    pub units: String,
    /// The cards' material id (LS-DYNA MID and EOSID, OpenRadioss mat_ID and unit_ID).
    #[arg(long, default_value_t = 1)]
    pub material_id: u32,
    /// The cards' material name (Abaqus NAME=, OpenRadioss title).
    #[arg(long, default_value = "STOSS")]
    pub name: String,
    /// Where the simulations run (this machine, a Slurm cluster) and how.
    #[command(flatten)]
    pub executor: ExecutorArgs,
}

/// Run `stoss calibrate`.
pub fn run(args: &CalibrateArgs) -> ExitCode {
    if let Err(message) = crate::fit::interrupt::install_handler() {
        eprintln!("warning: {message}: an interrupt will stop the run at once");
    }
    match run_calibration(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) if crate::fit::interrupt::requested() => {
            eprintln!(
                "{message}\nresume with the same command and --resume: no logged simulation \
                 runs again"
            );
            ExitCode::from(130)
        }
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

fn run_calibration(args: &CalibrateArgs) -> Result<(), String> {
    if let Some(budget) = args.budget.filter(|b| *b < 4) {
        return Err(format!(
            "--budget {budget}: give at least 4 simulations per instance (the initial design)"
        ));
    }
    if args.instances == Some(0) {
        return Err("--instances 0: give at least 1".into());
    }
    let most = crate::solver::explicit::MAXIMUM_THREADS;
    if let Some(threads) = args.threads.filter(|t| !(1..=most).contains(t)) {
        return Err(format!(
            "--threads must be in 1..={most} (simulations at once, one thread each), got \
             {threads}"
        ));
    }
    // The card options are checked before anything runs.
    let units =
        crate::report::cards::CardUnits::parse(&args.units).map_err(|e| format!("--units: {e}"))?;
    let card_options = crate::report::cards::CardOptions::new(units, args.material_id, &args.name)?;
    let campaign = Campaign::load(&args.campaign).map_err(|e| e.to_string())?;
    if args.leave_one_out && campaign.fitted().len() < 2 {
        return Err(format!(
            "--leave-one-out: needs at least 2 fitted experiments; {} fits {}",
            args.campaign.display(),
            campaign.fitted().len()
        ));
    }
    let options = RunOptions {
        budget: args.budget,
        instances: args.instances,
        leave_one_out: args
            .leave_one_out
            .then_some(crate::fit::campaign::LeaveOneOut::Every),
        polish: args.polish,
        least_squares: args.least_squares,
        outcomes: true,
    };
    // What the run will cost, before anything is written (issue 52: every size bounded by
    // what it costs).
    let sizes = crate::calibrate::cost::Sizes::of(&campaign, &options);
    let budget_source = if args.budget.is_some() {
        "--budget"
    } else {
        "[optimiser] budget"
    };
    crate::calibrate::cost::check(&campaign, &sizes, budget_source)?;
    let executor_entry = args.executor.settings(&campaign.file.executor)?;
    let output = args.output.clone().unwrap_or_else(|| {
        PathBuf::from("out").join(format!(
            "calibrate-{}",
            args.campaign
                .file_stem()
                .map_or_else(|| "campaign".into(), |s| s.to_string_lossy().into_owned())
        ))
    });
    let log_path = output.join("simulations.jsonl");
    if log_path.exists() && !args.resume {
        return Err(format!(
            "{} holds a previous run: use --resume to continue it, or --output for a new folder",
            output.display()
        ));
    }
    // A folder this run creates is removed again if the run ends before it logs anything (a
    // bad executor, a campaign that fails its checks late): no empty run is left behind.
    let mut created = (!output.exists()).then(|| CreatedFolder(output.clone()));
    std::fs::create_dir_all(&output).map_err(|e| format!("{}: {e}", output.display()))?;
    let _lock = crate::run_lock::RunLock::acquire(&output)?;
    // The run's inputs: a copy of the campaign and where it lives (its experiment paths are
    // relative to it; `stoss diagnose` reads this). A resumed run replaces a logged run's
    // copies only once it has succeeded, so a resume that fails (say, on a changed campaign)
    // leaves them as they were.
    let record_inputs = || -> Result<(), String> {
        std::fs::copy(&args.campaign, output.join("campaign.toml"))
            .map_err(|e| format!("{}: {e}", output.display()))?;
        let source = args
            .campaign
            .canonicalize()
            .map_err(|e| format!("{}: {e}", args.campaign.display()))?;
        std::fs::write(
            output.join(crate::cli::diagnose::CAMPAIGN_PATH_FILE),
            source.to_string_lossy().as_bytes(),
        )
        .map_err(|e| format!("{}: {e}", output.display()))
    };
    let resuming_a_logged_run = args.resume && output.join("campaign.toml").exists();
    if !resuming_a_logged_run {
        record_inputs()?;
    }
    log_line!(
        "campaign: {} ({} experiments, {} fitted; {} model(s))",
        campaign.file.name,
        campaign.experiments.len(),
        campaign.fitted().len(),
        campaign.file.models.len()
    );
    log_line!("output:   {}", output.display());
    // On a terminal, a bar per optimiser instance; otherwise (a log file, a batch job) a plain
    // line when an instance starts or ends and at most every PROGRESS_INTERVAL in between.
    let terminal = std::io::IsTerminal::is_terminal(&std::io::stderr());
    let started = std::time::Instant::now();
    let mut stage_start = started;
    let mut last_line: Option<std::time::Instant> = None;
    let bars = indicatif::MultiProgress::new();
    let style = indicatif::ProgressStyle::with_template(
        "{prefix:>24} [{bar:30}] {pos}/{len} {msg} (eta {eta})",
    )
    .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar());
    let mut current: Option<(String, indicatif::ProgressBar)> = None;
    let mut progress = |model: &str,
                        fold: Option<&str>,
                        instance: usize,
                        done: usize,
                        budget: usize,
                        best: Option<f64>| {
        let label = format!(
            "{model}{} #{instance}",
            fold.map(|f| format!(" w/o {f}")).unwrap_or_default()
        );
        if !super::output::logging() {
            return;
        }
        if !terminal {
            let new_stage = current.as_ref().is_none_or(|(l, _)| *l != label);
            if new_stage {
                stage_start = std::time::Instant::now();
                current = Some((label.clone(), indicatif::ProgressBar::hidden()));
            }
            let now = std::time::Instant::now();
            let due = super::output::get().verbose
                || last_line.is_none_or(|t| now.duration_since(t) >= PROGRESS_INTERVAL);
            if new_stage || done >= budget || due {
                last_line = Some(now);
                let stage = now.duration_since(stage_start).as_secs_f64();
                let left = if done > 0 && done < budget {
                    format!(
                        ", about {:.0} s left in this instance",
                        stage / done as f64 * (budget.saturating_sub(done)) as f64
                    )
                } else {
                    String::new()
                };
                eprintln!(
                    "{label}: {done}/{budget} simulations, {}, {:.0} s elapsed{left}",
                    best.map_or_else(
                        || "no feasible candidate yet".into(),
                        |b| format!("best error {b:.4}")
                    ),
                    now.duration_since(started).as_secs_f64()
                );
            }
            return;
        }
        if current.as_ref().is_none_or(|(l, _)| *l != label) {
            if let Some((_, bar)) = current.take() {
                bar.finish();
            }
            let bar = bars.add(
                indicatif::ProgressBar::new(budget as u64)
                    .with_style(style.clone())
                    .with_prefix(label.clone()),
            );
            current = Some((label, bar));
        }
        if let Some((_, bar)) = &current {
            bar.set_position(done as u64);
            bar.set_message(best.map_or_else(
                || "no feasible candidate yet".into(),
                |b| format!("best error {b:.4}"),
            ));
        }
    };
    let mut executor = start_executor(
        &executor_entry,
        args.threads.unwrap_or(campaign.file.optimiser.parallel),
        &campaign,
        &output,
        super::output::get().quiet,
    )?;
    let factory = crate::calibrate::proposer::bayesian_factory(campaign.file.optimiser.design);
    let crate::calibrate::run::Calibration { results, simulated } = calibrate(
        &campaign,
        &output,
        &options,
        executor.as_mut(),
        &factory,
        &mut progress,
    )
    .map_err(|e| e.to_string())?;
    drop(executor);
    if resuming_a_logged_run {
        record_inputs()?;
    }
    say!(
        "\n{:<10} {:>12} {:>14}",
        "model",
        "fit error",
        "held-out error"
    );
    for r in &results {
        say!(
            "{:<10} {:>12.4} {:>14}",
            r.model,
            r.fit_error,
            r.holdout_error.map_or("-".into(), |h| format!("{h:.4}"))
        );
    }
    say!();
    let sets: Vec<crate::fit::result::SetScore> = results
        .iter()
        .flat_map(|r| r.set_scores(&campaign))
        .collect();
    if let Some(recommendation) = crate::fit::result::recommend(&sets) {
        say!("recommended: use {}:", recommendation.set.label());
        for reason in &recommendation.reasons {
            say!("  - {reason}.");
        }
        say!();
    }
    for r in &results {
        if let Some(rejections) = r.rejection_summary() {
            say!("{rejections}.");
        }
        if let Some(fidelity) = r.fidelity_summary() {
            say!("{fidelity}.");
        }
        if let Some(verdict) = r.baseline_verdict() {
            say!("{verdict}.");
        }
        if let Some(model) = campaign.file.models.iter().find(|m| m.name == r.model) {
            for line in r.uncertainty_lines(&campaign.space(model).names) {
                say!("{line}.");
            }
        }
        for bound in &r.at_bounds {
            say!(
                "warning: {}: {bound}; the optimum may lie beyond it (widen the bound if that \
                 is physical)",
                r.model
            );
        }
    }
    let (outcomes, starting) =
        simulated.map_or_else(Default::default, |s| (s.selected, s.starting));
    let report = output.join("report");
    write_folder(&report, Leftovers::Clean, |folder| {
        calibration::write(
            folder,
            &campaign,
            &results,
            &outcomes,
            &starting,
            &card_options,
        )
    })?;
    say!("\nreport: {}", report.join("report.md").display());
    super::output::json(&result_document(&campaign, &results, &sets, &report));
    if let Some(folder) = created.as_mut() {
        folder.keep();
    }
    Ok(())
}

/// `stoss calibrate --json`: the recommendation, each model's errors and constants (name,
/// symbol, SI unit, value, 95 % half-width where computed) and the report's path.
fn result_document(
    campaign: &Campaign,
    results: &[crate::fit::result::ModelResult],
    sets: &[crate::fit::result::SetScore],
    report: &std::path::Path,
) -> serde_json::Value {
    let recommendation = crate::fit::result::recommend(sets).map(|r| {
        serde_json::json!({
            "model": r.set.model,
            "starting_constants": r.set.starting,
            "set": r.set.label(),
            "by_held_out": r.by_held_out,
            "reasons": r.reasons,
        })
    });
    let models: Vec<serde_json::Value> = results
        .iter()
        .map(|r| {
            let space = campaign.model(&r.model).map(|m| campaign.space(m));
            let symbols = space.as_ref().map(|s| s.symbols()).unwrap_or_default();
            let half = r.uncertainty.as_ref().map(|u| &u.half_width_95);
            let constants: Vec<serde_json::Value> = r
                .constants
                .iter()
                .enumerate()
                .map(|(k, c)| {
                    serde_json::json!({
                        "name": c.name,
                        "symbol": symbols.get(k),
                        "unit": c.unit,
                        "value": c.value,
                        "half_width_95": half.and_then(|h| h.get(k).copied().flatten()),
                        "posterior_95": r
                            .posterior
                            .as_ref()
                            .map(|p| [p.lower_95[k], p.upper_95[k]]),
                    })
                })
                .collect();
            serde_json::json!({
                "model": r.model,
                "fit_error": r.fit_error,
                "holdout_error": r.holdout_error,
                "constants": constants,
                "setup": r.setup,
                "at_bounds": r.at_bounds,
            })
        })
        .collect();
    serde_json::json!({
        "command": "calibrate",
        "campaign": campaign.path,
        "recommendation": recommendation,
        "models": models,
        "report": report.join("report.md"),
        "result": report.join("result.json"),
        "cards": report.join("cards"),
    })
}

/// A run's output folder that the run created: removed on drop unless kept or the run logged
/// a simulation into it.
struct CreatedFolder(PathBuf);

impl CreatedFolder {
    /// Keep the folder (the run succeeded).
    fn keep(&mut self) {
        self.0 = PathBuf::new();
    }
}

impl Drop for CreatedFolder {
    fn drop(&mut self) {
        if self.0.as_os_str().is_empty() {
            return;
        }
        let logged = std::fs::metadata(self.0.join("simulations.jsonl")).is_ok_and(|m| m.len() > 0);
        if !logged {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
}

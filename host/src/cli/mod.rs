//! The `stoss` command line.

pub mod analyse_shpb;
mod calibrate;
pub(crate) mod diagnose;
mod evaluate;
mod executor_args;
mod fit_jc;
pub mod output;
mod output_folder;
mod simulate;
pub mod synthesize;
mod validate;
mod verify;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// stoss: calibrate and diagnose high strain-rate material models from functional experiments.
#[derive(Debug, Parser)]
#[command(name = "stoss", version, about)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
    /// Accept input values outside their plausible range (a rod longer than 10 m, a velocity
    /// above 10 km/s...) and runs above the size limits (2 M elements, 2e10 element-cycles),
    /// which are otherwise refused as likely unit slips.
    #[arg(long, global = true)]
    pub force: bool,
    /// No progress or log lines on stderr (errors and warnings still).
    #[arg(long, global = true)]
    pub quiet: bool,
    /// Progress at every event, not at most every few seconds.
    #[arg(long, global = true, conflicts_with = "quiet")]
    pub verbose: bool,
    /// The result as one JSON document on stdout, in place of the text tables.
    #[arg(long, global = true)]
    pub json: bool,
}

/// Sub-commands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Fit model constants to the recordings of a campaign by Bayesian optimisation over
    /// simulations; leave-one-out, model selection, report and cards.
    Calibrate(calibrate::CalibrateArgs),
    /// After a calibration: locate the misfit, name the missing physics, add it, refit, and
    /// report whether the fit improves.
    Diagnose(diagnose::DiagnoseArgs),
    /// Verify the material kernel against closed forms, published numbers and the golden
    /// bit-exact histories.
    Verify(verify::VerifyArgs),
    /// Re-run the headline figures of README.md and docs/*.md and compare each with the
    /// value it is quoted at (pass/fail table; `--fast` for the rows CI runs).
    Validate(validate::ValidateArgs),
    /// Run one experiment with given constants; print the energy balance and the comparison
    /// with the recording; write measurements, state histories and VTK.
    Simulate(simulate::SimulateArgs),
    /// Generate a synthetic recording (and its noise-free truth) from a known material.
    Synthesize(synthesize::SynthesizeArgs),
    /// Simulate one candidate of a distributed calibration from its task file (the worker
    /// that `stoss calibrate --executor slurm` runs on the cluster's nodes).
    Evaluate(evaluate::EvaluateArgs),
    /// Kolsky analysis of a real split Hopkinson bar's recorded gauge signals: stress, strain
    /// and strain rate by the 1-, 2- and 3-wave analyses, and a recording a campaign can fit.
    AnalyseShpb(analyse_shpb::AnalyseShpbArgs),
    /// The conventional direct Johnson-Cook fit from flow curves (seed 001 sec. 3.2), with no
    /// simulation: a starting point and a baseline for `calibrate`.
    FitJc(fit_jc::FitJcArgs),
}

/// Run the parsed command line.
pub fn run(cli: Cli) -> ExitCode {
    crate::input::allow_implausible(cli.force);
    output::set(output::Output {
        quiet: cli.quiet,
        verbose: cli.verbose,
        json: cli.json,
    });
    match cli.command {
        Command::Verify(args) => verify::run(&args),
        Command::Validate(args) => validate::run(&args),
        Command::Calibrate(args) => calibrate::run(&args),
        Command::Diagnose(args) => diagnose::run(&args),
        Command::Simulate(args) => simulate::run(&args),
        Command::Synthesize(args) => synthesize::run(&args),
        Command::Evaluate(args) => evaluate::run(&args),
        Command::AnalyseShpb(args) => analyse_shpb::run(&args),
        Command::FitJc(args) => fit_jc::run(&args),
    }
}

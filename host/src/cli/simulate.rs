//! `stoss simulate <experiment.toml> [--material m.toml]`: run one experiment with given
//! constants; print the energy balance and the comparison with the recording; write
//! `measurements.csv`, `summary.json`, `energy.csv`, `states.csv`, `final.vtu` and `run.pvd`
//! (every field of the run with its time; a sweep's shots also as `shot-<v>mps.vtu` and
//! `shots.pvd`) into the output folder, with an experiment report's text and charts (each
//! chart as `.svg` and `.csv`); all written to a temporary folder first and moved into place,
//! so a failed run leaves no partial output.

use super::output::{say, say_inline};
use super::output_folder::{write_folder, Leftovers};
use crate::analytic::penetration::{depth_at, rear_face_in_plastic_zone};
use crate::experiment::{Experiment, Outcome, PenetrationSpec, Setup};
use crate::input::{material, InputError};
use crate::report::{plots, vtk};
use crate::solver::SolverSettings;
use clap::Args;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Arguments of `stoss simulate`.
#[derive(Debug, Args)]
pub struct SimulateArgs {
    /// Experiment file (TOML).
    pub experiment: PathBuf,
    /// Material file (TOML); defaults to the experiment's `material`.
    #[arg(long)]
    pub material: Option<PathBuf>,
    /// Output folder (default `out/<experiment name>`).
    #[arg(long)]
    pub output: Option<PathBuf>,
    /// Worker threads (results do not depend on it).
    #[arg(long)]
    pub threads: Option<usize>,
}

/// Least time between two progress lines when stderr is not a terminal (`--verbose`: 1 s).
const PROGRESS_INTERVAL: std::time::Duration = std::time::Duration::from_secs(10);

/// Run `simulate` while reporting the current run's progress: on a terminal a spinner with
/// the fraction of the run done; otherwise a plain line at most every [`PROGRESS_INTERVAL`]
/// on stderr (fraction, elapsed, estimated time left; an experiment of several runs, a
/// ballistic-limit search, counts its finished shots and estimates the time left from them).
fn with_progress<T>(
    progress: &crate::solver::RunProgress,
    quiet: bool,
    simulate: impl FnOnce() -> T,
) -> T {
    let done = std::sync::atomic::AtomicBool::new(false);
    std::thread::scope(|scope| {
        let reporter = (!quiet).then(|| {
            scope.spawn(|| {
                let terminal = std::io::IsTerminal::is_terminal(&std::io::stderr());
                let bar = if terminal {
                    indicatif::ProgressBar::new_spinner()
                } else {
                    indicatif::ProgressBar::hidden()
                };
                let started = std::time::Instant::now();
                let mut last_line = started;
                while !done.load(std::sync::atomic::Ordering::Relaxed) {
                    // Woken at once when the simulation ends.
                    std::thread::park_timeout(std::time::Duration::from_millis(200));
                    let fraction = progress.fraction().unwrap_or(0.0);
                    let elapsed = started.elapsed().as_secs_f64();
                    // An experiment of several runs (a ballistic sweep's shots, some in
                    // parallel) counts its finished runs; the fraction is the latest run's.
                    let runs = progress
                        .runs()
                        .map_or(String::new(), |(finished, expected)| {
                            format!("{finished} of {expected} shots done, ")
                        });
                    if terminal {
                        bar.set_message(format!(
                            "simulating: {runs}{:.0} % of the current run, {elapsed:.0} s",
                            100.0 * fraction
                        ));
                        bar.tick();
                    } else if last_line.elapsed()
                        >= if super::output::get().verbose {
                            std::time::Duration::from_secs(1)
                        } else {
                            PROGRESS_INTERVAL
                        }
                    {
                        last_line = std::time::Instant::now();
                        let left = match progress.runs() {
                            Some((finished, expected)) if finished > 0 => format!(
                                ", about {:.0} s left",
                                elapsed / finished as f64 * (expected - finished) as f64
                            ),
                            Some(_) => String::new(),
                            None if fraction > 0.01 => format!(
                                ", about {:.0} s left in this run",
                                elapsed / fraction * (1.0 - fraction)
                            ),
                            None => String::new(),
                        };
                        eprintln!(
                            "simulating: {runs}{:.0} % of the current run, {elapsed:.0} s \
                             elapsed{left}",
                            100.0 * fraction
                        );
                    }
                }
                bar.finish_and_clear();
            })
        });
        let result = simulate();
        done.store(true, std::sync::atomic::Ordering::Relaxed);
        if let Some(reporter) = &reporter {
            reporter.thread().unpark();
        }
        result
    })
}

fn write_outputs(
    directory: &Path,
    experiment: &Experiment,
    outcome: &crate::experiment::Outcome,
) -> std::io::Result<()> {
    std::fs::create_dir_all(directory)?;
    let mut csv = String::from("quantity,position,recorded,uncertainty,predicted,residual\n");
    for (point, predicted) in experiment.recording.iter().zip(&outcome.predicted) {
        let _ = writeln!(
            csv,
            "{},{:e},{:e},{:e},{:e},{:e}",
            point.quantity,
            point.position,
            point.value,
            point.uncertainty,
            predicted,
            predicted - point.value
        );
    }
    std::fs::write(directory.join("measurements.csv"), csv)?;
    // Each result with its unit: {"final_length": {"value": 0.0203, "unit": "m"}, ...}.
    let summary: serde_json::Map<String, serde_json::Value> = outcome
        .summary
        .iter()
        .map(|s| {
            (
                s.name.clone(),
                serde_json::json!({"value": s.value, "unit": s.unit}),
            )
        })
        .chain(outcome.energy.map(|e| {
            (
                "energy_error_percent".to_string(),
                serde_json::json!({"value": e.error_percent(), "unit": "%"}),
            )
        }))
        .collect();
    std::fs::write(
        directory.join("summary.json"),
        serde_json::to_string_pretty(&summary).unwrap_or_default(),
    )?;
    if let Some(energy) = &outcome.energy {
        std::fs::write(directory.join("energy.txt"), energy.report() + "\n")?;
    }
    let mut states = String::from("point,time,plastic_strain,plastic_strain_rate,temperature,pressure,equivalent_stress,triaxiality,axial_stress\n");
    for history in &outcome.states {
        for s in &history.samples {
            let _ = writeln!(
                states,
                "{},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e}",
                history.label,
                s.time,
                s.plastic_strain,
                s.plastic_strain_rate,
                s.temperature,
                s.pressure,
                s.equivalent_stress,
                s.triaxiality,
                s.axial_stress
            );
        }
    }
    std::fs::write(directory.join("states.csv"), states)?;
    // Every field of the run, with its time, for `run.pvd`.
    let mut series: Vec<(f64, String)> = Vec::new();
    if let Some(report) = &outcome.report {
        for (file, field) in &report.snapshots {
            std::fs::write(directory.join(file), vtk::render_hexahedral(field))?;
            series.push((field.time, file.clone()));
        }
    }
    if let Some(field) = &outcome.field_3d {
        std::fs::write(directory.join("final.vtu"), vtk::render_hexahedral(field))?;
        series.push((field.time, "final.vtu".into()));
    }
    if let Some(field) = &outcome.field {
        std::fs::write(directory.join("final.vtu"), vtk::render(field))?;
        series.push((field.time, "final.vtu".into()));
    }
    if !series.is_empty() {
        series.sort_by(|a, b| a.0.total_cmp(&b.0));
        std::fs::write(directory.join("run.pvd"), vtk::collection(&series))?;
    }
    if let Some(report) = &outcome.report {
        std::fs::write(directory.join("report.txt"), &report.text)?;
        // A sweep's shots: one file each, and a collection whose "time" is the impact
        // velocity (m/s), so that ParaView steps from shot to shot.
        if !report.shot_fields.is_empty() {
            let mut shots = Vec::new();
            for (velocity, field) in &report.shot_fields {
                let file = format!("shot-{:04.0}mps.vtu", velocity);
                std::fs::write(directory.join(&file), vtk::render(field))?;
                shots.push((*velocity, file));
            }
            std::fs::write(directory.join("shots.pvd"), vtk::collection(&shots))?;
        }
        for map in &report.maps {
            plots::field_map(
                &directory.join(&map.file),
                &map.title,
                &map.x_label,
                &map.y_label,
                &map.cells,
                map.range,
            )
            .map_err(std::io::Error::other)?;
        }
        for chart in &report.charts {
            plots::line_chart(
                &directory.join(&chart.file),
                &chart.title,
                &chart.x_label,
                &chart.y_label,
                &chart.series,
            )
            .map_err(std::io::Error::other)?;
            // The chart's numbers beside it: `series,x,y` under the axis labels.
            let mut numbers = format!("# x: {}; y: {}\nseries,x,y\n", chart.x_label, chart.y_label);
            for series in &chart.series {
                for (x, y) in &series.points {
                    let _ = writeln!(numbers, "{},{x:e},{y:e}", series.label.replace(',', ";"));
                }
            }
            std::fs::write(directory.join(&chart.file).with_extension("csv"), numbers)?;
        }
    }
    Ok(())
}

/// Run `stoss simulate`.
pub fn run(args: &SimulateArgs) -> ExitCode {
    match simulate(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

fn simulate(args: &SimulateArgs) -> Result<(), String> {
    let experiment = Experiment::load(&args.experiment).map_err(|e| e.to_string())?;
    let material_path = args
        .material
        .clone()
        .or_else(|| experiment.default_material_path())
        .ok_or_else(|| {
            InputError::field(
                &args.experiment,
                "",
                "material",
                "no material: give --material or set `material` in the experiment",
            )
            .to_string()
        })?;
    let material_text = crate::input::read_text(&material_path).map_err(|e| e.to_string())?;
    let (material_file, material) =
        material::parse_part(&material_path, &material_text).map_err(|e| e.to_string())?;
    experiment.file.setup.accepts(&material).map_err(|error| {
        InputError::field(&material_path, &material_text, "model", error.to_string()).to_string()
    })?;
    say!(
        "experiment: {} ({})",
        experiment.file.name,
        args.experiment.display()
    );
    say!(
        "material:   {} ({})",
        material_file.name(),
        material_path.display()
    );
    let progress = crate::solver::RunProgress::watched();
    let settings = SolverSettings {
        threads: args.threads,
        progress: progress.clone(),
        ..SolverSettings::default()
    };
    let started = std::time::Instant::now();
    let outcome = with_progress(&progress, super::output::get().quiet, || {
        experiment.simulate(&material, &settings)
    })
    .map_err(|e| format!("{}: {e}", args.experiment.display()))?;
    let wall = started.elapsed().as_secs_f64();
    say!("wall time:  {wall:.2} s");
    if outcome.element_cycles > 0 {
        say!(
            "element-cycles: {} ({:.2} M per wall-clock second)",
            outcome.element_cycles,
            outcome.element_cycles as f64 / wall * 1e-6
        );
    }
    if let Some(energy) = &outcome.energy {
        say!("{}", energy.report());
    }
    for s in &outcome.summary {
        say!("{:<24} {:.6e} {}", s.name, s.value, s.unit);
    }
    say!(
        "\n{:<20} {:>12} {:>12} {:>12} {:>10} {:>8}",
        "quantity",
        "position",
        "recorded",
        "predicted",
        "diff %",
        "diff/u"
    );
    for (point, predicted) in experiment.recording.iter().zip(&outcome.predicted) {
        // A recorded 0 (a stopped projectile) has no relative difference: the difference in
        // recorded uncertainties says it.
        let relative = if point.value == 0.0 {
            format!("{:>10}", "-")
        } else {
            format!(
                "{:>+9.2}%",
                100.0 * (predicted - point.value) / point.value.abs()
            )
        };
        say!(
            "{:<20} {:>12.4e} {:>12.4e} {:>12.4e} {relative} {:>+8.2}",
            point.quantity,
            point.position,
            point.value,
            predicted,
            (predicted - point.value) / point.uncertainty
        );
    }
    if let (Setup::Penetration(spec), Some(metal)) = (&experiment.file.setup, material.j2()) {
        print_cross_check(spec, metal, &experiment, &outcome);
    }
    if let Some(report) = &outcome.report {
        say_inline!("{}", report.text);
    }
    let missing: Vec<_> = experiment
        .recording
        .iter()
        .zip(&outcome.predicted)
        .filter(|(_, predicted)| !predicted.is_finite())
        .collect();
    if let Some((first, _)) = missing.first() {
        return Err(format!(
            "{}: the simulation gave no finite prediction at {} of {} recorded points (first: \
             {} at position {:e}); a yield stress in the wrong unit or a flow curve that never \
             reaches the recorded strains gives this; nothing written",
            args.experiment.display(),
            missing.len(),
            experiment.recording.len(),
            first.quantity,
            first.position
        ));
    }
    let output = args.output.clone().unwrap_or_else(|| {
        PathBuf::from("out").join(
            args.experiment
                .file_stem()
                .map_or_else(|| "run".into(), |s| s.to_string_lossy().into_owned()),
        )
    });
    // No run lock here (the folder itself is replaced): leftovers of other processes stay.
    write_folder(&output, Leftovers::Keep, |folder| {
        write_outputs(folder, &experiment, &outcome)
            .map_err(|e| format!("{}: {e}", folder.display()))
    })?;
    say!("\nwrote {}", output.display());
    super::output::json(&serde_json::json!({
        "command": "simulate",
        "experiment": args.experiment,
        "material": material_path,
        "wall_time_s": wall,
        "element_cycles": outcome.element_cycles,
        "energy_error_percent": outcome.energy.map(|e| e.error_percent()),
        "summary": outcome
            .summary
            .iter()
            .map(|s| {
                (
                    s.name.clone(),
                    serde_json::json!({"value": s.value, "unit": s.unit}),
                )
            })
            .collect::<serde_json::Map<_, _>>(),
        "measurements": experiment
            .recording
            .iter()
            .zip(&outcome.predicted)
            .map(|(point, predicted)| serde_json::json!({
                "quantity": point.quantity,
                "position": point.position,
                "recorded": point.value,
                "uncertainty": point.uncertainty,
                "predicted": predicted,
            }))
            .collect::<Vec<_>>(),
        "output": output,
    }));
    Ok(())
}

/// The Walker–Anderson and Tate–Alekseevskii nose depths beside the FE and the recording, at
/// each recorded time (semi-infinite target; see [`PenetrationSpec::cross_check`]).
fn print_cross_check(
    spec: &PenetrationSpec,
    material: &stoss_kernel::Material,
    experiment: &Experiment,
    outcome: &Outcome,
) {
    let check = match spec.cross_check(material) {
        Ok(check) => check,
        Err(message) => {
            say!("\nanalytic cross-check not available: {message}");
            return;
        }
    };
    let case = &check.case;
    say!(
        "\nanalytic cross-check (semi-infinite target; rod strength {:.3} GPa, target strength \
         {:.3} GPa, Tate R_t {:.3} GPa)",
        case.rod_strength * 1e-9,
        case.target_strength * 1e-9,
        case.target_resistance * 1e-9
    );
    say!(
        "{:<12} {:>12} {:>12} {:>16} {:>12}",
        "time (us)",
        "recorded",
        "FE",
        "Walker-Anderson",
        "Tate"
    );
    let mut times: Vec<(f64, f64, f64)> = experiment
        .recording
        .iter()
        .zip(&outcome.predicted)
        .filter(|(point, _)| point.quantity == "nose_depth")
        .map(|(point, &fe)| (point.position, point.value, fe))
        .collect();
    if times.is_empty() {
        times.push((spec.end_time, f64::NAN, f64::NAN));
    }
    for (time, recorded, fe) in times {
        say!(
            "{:<12.2} {:>9.2} mm {:>9.2} mm {:>13.2} mm {:>9.2} mm",
            time * 1e6,
            recorded * 1e3,
            fe * 1e3,
            depth_at(&check.walker_anderson, time) * 1e3,
            depth_at(&check.tate, time) * 1e3
        );
    }
    if let Ok(Some((time, alpha, extent))) =
        rear_face_in_plastic_zone(case, &check.walker_anderson, spec.target_thickness)
    {
        say!(
            "note: from {:.1} us the {:.1} mm plate's rear face lies inside Walker-Anderson's \
             plastic zone ({alpha:.1} crater radii, {:.1} mm ahead of the nose): from then on \
             the semi-infinite models resist more than this plate, and the FE depth, which has \
             the rear face, may exceed them (docs/euler.md, \"Where in the shot the excess \
             builds\")",
            time * 1e6,
            spec.target_thickness * 1e3,
            extent * 1e3
        );
    }
}

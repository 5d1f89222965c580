//! `stoss fit-jc <flow-curve experiments...>`: the conventional direct Johnson-Cook fit
//! (seed 001 sec. 3.2, [`crate::calibrate::direct_jc`]) from flow-curve recordings, with no
//! simulation: a starting point for `stoss calibrate` and the baseline a calibration is
//! compared against. It prints the constants, which curves set each, and each curve's RMS
//! difference, and writes the material file if asked.

use super::output::say;
use crate::calibrate::direct_jc::{self, DirectFitSettings, FlowCurve};
use crate::experiment::uniaxial::RecordedStrain;
use crate::experiment::{Experiment, Setup};
use crate::input::material::{self, StrengthSpec};
use crate::report::cards::{bulk_modulus, young_and_poisson};
use clap::Args;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Arguments of `stoss fit-jc`.
#[derive(Debug, Args)]
pub struct FitJcArgs {
    /// Flow-curve experiment files (kind `uniaxial`, recording `true_stress`).
    #[arg(required = true)]
    pub experiments: Vec<PathBuf>,
    /// Reference rate `e0` (1/s): curves at or below it set A, B, n.
    #[arg(long, default_value_t = 1.0)]
    pub reference_rate: f64,
    /// Reference temperature `Tr` (K); default: the lowest test temperature.
    #[arg(long)]
    pub reference_temperature: Option<f64>,
    /// Melting temperature `Tm` (K); default: the base material's.
    #[arg(long)]
    pub melting_temperature: Option<f64>,
    /// Base material file (elasticity, EoS, heating); default: the first experiment's.
    #[arg(long)]
    pub material: Option<PathBuf>,
    /// Write the base material with the fitted Johnson-Cook strength here (TOML).
    #[arg(long)]
    pub output: Option<PathBuf>,
}

/// Run `stoss fit-jc`.
pub fn run(args: &FitJcArgs) -> ExitCode {
    match fit(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

fn fit(args: &FitJcArgs) -> Result<(), String> {
    let mut experiments = Vec::new();
    for path in &args.experiments {
        experiments.push(Experiment::load(path).map_err(|e| e.to_string())?);
    }
    let material_path = match &args.material {
        Some(path) => path.clone(),
        None => {
            let first = &experiments[0];
            let relative = first.file.material.as_ref().ok_or(format!(
                "{}: no `material` to take the elasticity from; give --material",
                first.path.display()
            ))?;
            first.path.parent().unwrap_or(Path::new(".")).join(relative)
        }
    };
    let (mut base, _) = material::load(&material_path).map_err(|e| e.to_string())?;
    let young = bulk_modulus(&base)
        .map(|bulk| young_and_poisson(bulk, base.shear_modulus).0)
        .unwrap_or(f64::NAN);
    let mut curves = Vec::new();
    for experiment in &experiments {
        let Setup::Uniaxial(spec) = &experiment.file.setup else {
            return Err(format!(
                "{}: fit-jc reads flow curves (kind \"uniaxial\"), not this kind",
                experiment.path.display()
            ));
        };
        let mut points = Vec::new();
        for point in experiment
            .recording
            .iter()
            .filter(|p| p.quantity == "true_stress")
        {
            let plastic = match spec.recorded_strain {
                RecordedStrain::Plastic => point.position,
                // Seed 001 eq. 3.3 without the 0.2 % offset: the elastic part removed.
                RecordedStrain::Total => point.position - point.value / young,
            };
            points.push((plastic, point.value, point.uncertainty));
        }
        if !points.iter().all(|p| p.0.is_finite()) {
            return Err(format!(
                "{}: total strains need the base material's Young's modulus, which its EoS does not give",
                experiment.path.display()
            ));
        }
        curves.push(FlowCurve {
            name: experiment.file.name.clone(),
            rate: spec.strain_rate,
            temperature: spec.temperature,
            points,
        });
    }
    let constant = |name: &str| base.strength.constant_named(name);
    let melting_temperature = args
        .melting_temperature
        .or_else(|| constant("melting_temperature"))
        .ok_or("the base material has no melting temperature; give --melting-temperature")?;
    let reference_temperature = args.reference_temperature.unwrap_or_else(|| {
        curves
            .iter()
            .map(|c| c.temperature)
            .fold(f64::INFINITY, f64::min)
    });
    let settings = DirectFitSettings {
        reference_rate: args.reference_rate,
        reference_temperature,
        melting_temperature,
        default_thermal_exponent: constant("thermal_exponent").unwrap_or(1.0),
    };
    let result = direct_jc::fit(&curves, &settings).map_err(|e| e.to_string())?;
    let c = result.constants;
    super::output::json(&serde_json::json!({
        "command": "fit-jc",
        "constants": {
            "yield_stress": c.yield_stress,
            "hardening_modulus": c.hardening_modulus,
            "hardening_exponent": c.hardening_exponent,
            "rate_sensitivity": c.rate_sensitivity,
            "thermal_exponent": c.thermal_exponent,
            "reference_rate": c.reference_rate,
            "reference_temperature": c.reference_temperature,
            "melting_temperature": c.melting_temperature,
        },
        "rms_relative": result.rms_relative,
        "notes": result.notes,
        "output": args.output,
    }));
    say!("Direct Johnson-Cook fit (seed 001 sec. 3.2; isothermal reading of every curve)");
    say!(
        "  A {:.1} MPa, B {:.1} MPa, n {:.4}, C {:.5}, m {:.4}  (e0 {} /s, Tr {} K, Tm {} K)",
        c.yield_stress / 1e6,
        c.hardening_modulus / 1e6,
        c.hardening_exponent,
        c.rate_sensitivity,
        c.thermal_exponent,
        c.reference_rate,
        c.reference_temperature,
        c.melting_temperature
    );
    for (step, names) in ["A, B, n", "C", "m"].iter().zip(&result.used) {
        say!("  {step} from: {}", names.join("; "));
    }
    say!("  RMS relative difference per curve:");
    for (name, rms) in &result.rms_relative {
        say!("    {:>6.2} %  {name}", 100.0 * rms);
    }
    for note in &result.notes {
        say!("  note: {note}");
    }
    if let Some(output) = &args.output {
        base.name = format!("{} (direct JC fit)", base.name);
        base.source = format!(
            "stoss fit-jc from {}",
            args.experiments
                .iter()
                .map(|p| p.display().to_string())
                .collect::<Vec<_>>()
                .join(", ")
        );
        base.strength = StrengthSpec::JohnsonCook(c);
        base.material()
            .map_err(|e| format!("the fitted constants are not a valid material: {e}"))?;
        crate::fit::executor::task::write_atomically(output, base.to_toml().as_bytes())
            .map_err(|e| format!("{}: {e}", output.display()))?;
        say!("  written: {}", output.display());
    }
    Ok(())
}
